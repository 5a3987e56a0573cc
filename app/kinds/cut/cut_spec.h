// test.yaml keys of a cut test and the campaign.yaml `estimation:` block the cut kind owns
// (docs/formats.md).
#pragma once

#include <optional>
#include <string>
#include <utility>

#include "app/core/campaign.h"
#include "app/kinds/cut/estimation_options.h"

namespace chatterlab::app {

struct CutSpec : KindSpec {
  std::string operation;  // up-milling | down-milling
  double spindle_rpm = 0.0;
  double feed_per_tooth_m = 0.0;
  double radial_immersion_m = 0.0;
  std::pair<double, double> axial_depth_m{0.0, 0.0};  // start, end of cut window
  std::pair<double, double> cut_window_s{0.0, 0.0};
  std::optional<std::pair<double, double>> air_window_s;
  double sensor_to_tip = 1.0;
  // Optional: the part of the record the estimators run over (docs/identification.md).
  std::optional<std::pair<double, double>> estimation_window_s;
};

// campaign.yaml `estimation:` (every key optional; defaults: EstimationOptions).
struct EstimationBlock : KindSpec {
  EstimationOptions options;
};

}  // namespace chatterlab::app
