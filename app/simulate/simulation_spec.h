// The simulation spec of EXPERIMENT_FORMAT.md section 3 (`chatterlab simulate`).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "analysis/common/modal_parameters.h"

namespace chatterlab::app {

struct SimulationSpec {
  int teeth = 0;
  double radius_m = 0;
  ModalParameters x, y;                  // `modal` for both, or modal.x / modal.y
  std::vector<double> Kt_N_m2, Kr_N_m2;  // one per tooth (a single number fills every tooth)
  std::string operation = "up-milling";
  double spindle_rpm = 0, feed_per_tooth_m = 0, radial_immersion_m = 0;
  double depth_start_m = 0, depth_end_m = 0;
  std::optional<double> revolutions_per_mm;  // ramp rate (depth changes)
  std::optional<int> revolutions;            // constant depth: run length
  std::string chip_model = "traditional";    // traditional | numerical
  int steps_per_tooth = 800;
  std::string switching = "contact";           // contact | angle-only (docs/simulator.md)
  std::string euler_order = "velocity-first";  // velocity-first | position-first
  bool inertial = false;
  double eccentricity_m = 0, eccentricity_angle_rad = 0;
  std::vector<double> poincare_depths_m;
  // Noise floor the bifurcation detector judges the (noise-free) simulated x_n against: the
  // measurement noise of 000 sec. 6.1 by default, so that simulated and measured bifurcation
  // depths are read on one yardstick (docs/bifurcation.md).
  double detector_noise_m = 5e-7;
  // Keys of the spec nobody reads (a misspelt key gets a suggestion), naming the file and key:
  // `simulate` prints them and lists them in results.json `warnings`.
  std::vector<std::string> warnings;
};

// Reads and validates a spec; throws InputError listing every problem with file and key.
SimulationSpec load_simulation_spec(const std::filesystem::path& file);

}  // namespace chatterlab::app
