// Time-domain milling simulation (000 ch. 2, sec. 5.2, ch. 7): two uncoupled modal axes
// (eqs 2.5-2.6, or 7.8-7.9 with inertial forces) driven by the tooth forces of eqs 2.1-2.4,
// integrated by symplectic Euler (symplectic_euler.h) at steps_per_tooth steps per tooth pass,
// with the traditional (chip_traditional.h) or numerical (chip_numerical.h) chip thickness.
// The tool starts at rest (at options.initial_deflection_m) with theta_1 = 0 at t = 0.
//
// Revolution j covers steps j S .. (j + 1) S - 1 (S = n steps_per_tooth), theta_1 = 2 pi a / S at
// step j S + a. Depth, deflection, chip and forces of step k all belong to time k h and angle
// theta_1(k). The step loop allocates nothing: every buffer (history, records, trace, samples) is
// sized before it starts (tests/analysis/milling/simulation_test.cpp counts allocations).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/milling/simulation_options.h"

namespace chatterlab {
namespace milling {

// What to record besides the once-per-revolution samples.
struct RecordingRequest {
  // Full per-step records of these revolutions (0-based, each < the run's revolutions), e.g.
  // revolution_at_depth(options, 1e-3) for "one revolution near 1 mm" (000 figs 5.2, 7.3-7.4).
  std::vector<int> full_revolutions;
  // Compact float trace of x, y at every step of revolutions trace_first_revolution ..
  // trace_first_revolution + trace_revolutions - 1 (000 figs 7.8-7.9), with their mean
  // trajectory against angle. trace_revolutions = 0: none.
  int trace_first_revolution = 0;
  int trace_revolutions = 0;
};

// One revolution, one entry per step (S entries), all doubles.
struct RevolutionRecord {
  int revolution = -1;
  std::int64_t first_step = 0;  // step of entry 0 (time first_step * time_step_s)
  Eigen::VectorXd theta1_rad;   // theta_1 in [0, 2 pi)
  Eigen::VectorXd depth_m;      // axial depth b
  Eigen::VectorXd x_m, y_m;     // deflection (from the rotation axis)
  Eigen::VectorXd vx_m_s, vy_m_s;
  Eigen::MatrixXd chip_m;      // S x n: g_p w_p, the chip that made the force (0: not cutting;
                               // negative only with SwitchingRule::kAngleOnly)
  Eigen::VectorXd Fx_N, Fy_N;  // cutting force, 000 eqs 2.3-2.4
  Eigen::VectorXd centrifugal_x_N, centrifugal_y_N;  // 000 eqs 7.1, 7.5-7.6 (0 if disabled)
  Eigen::VectorXd coriolis_x_N, coriolis_y_N;        // 000 eqs 7.3-7.6 (0 if disabled)
};

// x, y at every step of a range of revolutions, as float (millions of points), and their mean
// over those revolutions at each angle.
struct CompactTrace {
  int first_revolution = 0;
  int revolutions = 0;
  std::vector<float> x_m, y_m;         // revolutions * S values, step order
  Eigen::VectorXd angle_rad;           // theta_1 of each of the S angles
  Eigen::VectorXd mean_x_m, mean_y_m;  // mean over the revolutions at each angle (doubles)
};

// Once-per-revolution samples x_n, y_n at theta_1 = angle_rad (000 sec. 5.2, fig. 5.1).
struct OncePerRevolution {
  double angle_rad = 0.0;    // sample angle used (options.sample_angle_rad on the step grid)
  Eigen::VectorXd depth_m;   // depth at the sample step of revolution j
  Eigen::VectorXd x_m, y_m;  // deflection at that step
};

// Counters of the numerical chip search (0 with the traditional model).
struct NumericalSearchStats {
  std::int64_t searches = 0;           // tooth steps whose tip was beyond the original surface
  std::int64_t points = 0;             // path points whose distance to the tooth was evaluated
  std::int64_t long_window_steps = 0;  // steps searched with the long window after the start
                                       // (re-expansions)
};

struct SimulationResult {
  StepSummary summary;     // not run until simulate() finishes; failed if it diverged
  int revolutions = 0;     // revolutions completed
  std::int64_t steps = 0;  // steps completed
  double runtime_s = 0.0;  // wall time of the step loop
  double time_step_s = 0.0;
  int steps_per_revolution = 0;
  OncePerRevolution samples;              // one per revolution, for every revolution run
  std::vector<RevolutionRecord> records;  // RecordingRequest::full_revolutions, same order
  CompactTrace trace;
  NumericalSearchStats numerical;
};

// Runs the simulation. Throws InputError for invalid options or recording requests (the
// message names the field); returns a failed summary with the revolution and depth if the
// deflection leaves the physical range (|x|, |y| > radius: the model broke down).
SimulationResult simulate(const SimulationOptions& options, const RecordingRequest& recording = {});

}  // namespace milling
}  // namespace chatterlab
