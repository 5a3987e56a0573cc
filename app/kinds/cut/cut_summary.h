// What a cut test provides to the campaign's group products (the stability lobes section,
// app/kinds/lobes/lobes_group.h): its conditions, stable or chatter as measured, and its
// identified set. Light on purpose: a consumer need not include the cut step.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "analysis/common/modal_parameters.h"
#include "analysis/dynamics/bifurcation.h"
#include "analysis/milling/simulation_options.h"

namespace chatterlab::app {

namespace value {
// CutSummary of each cut test whose step succeeded (in test id order).
inline const std::string kCutSummary = "cut/summary";
}  // namespace value

struct CutSummary {
  std::string id;
  milling::Operation operation = milling::Operation::kUpMilling;
  double spindle_rpm = 0.0;  // test.yaml's speed
  double radial_immersion_m = 0.0;
  double depth_start_m = 0.0, depth_end_m = 0.0;  // test.yaml axial_depth_mm
  bool ramped = false;
  // Constant depth: chatter by the Poincare class of the map at the middle of the cut window;
  // nullopt when it was not determined.
  std::optional<bool> chatter;
  // Ramped: the measured bifurcation (bifurcation_ok false: the detector did not run).
  bool bifurcation_ok = false;
  dynamics::DepthProfile profile = dynamics::DepthProfile::kConstant;
  dynamics::RunVerdict verdict = dynamics::RunVerdict::kAllStable;
  std::optional<double> bifurcation_depth_m;
  // The identified set (000 sec. 5.1: m, c, k on x and y, Kt_p, Kr_p), when the sequence finished.
  bool identified = false;
  ModalParameters modal;
  std::vector<double> Kt_N_m2, Kr_N_m2;
};

}  // namespace chatterlab::app
