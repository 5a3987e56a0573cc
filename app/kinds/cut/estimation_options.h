// Options of the estimation part of a cut test (app/cut_estimation.h), read from campaign.yaml
// `estimation:` (docs/formats.md).
#pragma once

#include "analysis/estimate/ekf_options.h"
#include "analysis/estimate/repeatability.h"

namespace chatterlab::app {

// campaign.yaml `estimation:` (docs/formats.md). Defaults: 000 secs 6.1-6.2 where it gives a
// value, docs/identification.md otherwise.
struct EstimationOptions {
  double window_s = 0.2;               // data the filters run over, s, > 0 (000 sec. 6.2: 0.2 s)
  double resample_step_s = 5e-7;       // 000 sec. 6.1, s, > 0
  double settle_revolutions = 20.0;    // revolutions after the cut starts that are never used
  int max_passes = 8;                  // identification passes, >= 1 (1: 000 sec. 5.1 as written)
  double offset_tolerance_deg = 0.05;  // passes stop when the offset moves less than this
  double parameter_tolerance = 0.005;  // ... and every parameter by less than this fraction
  estimate::RepeatabilityOptions repeat;  // runs (10), spread (0.5), seed
  estimate::ModalEkfOptions modal;
  estimate::CoeffEkfOptions coeff;
};

}  // namespace chatterlab::app
