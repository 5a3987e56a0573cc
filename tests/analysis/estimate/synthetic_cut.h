// Measured cuts with known truth for the estimator tests: the simulator (analysis/milling) cuts
// at a constant depth with 000 table 5.2's incline-1 parameters, the deflections are acquired
// at a sampling step, white Gaussian noise is added (000 sec. 6.1: 5e-7 m) and the record is
// resampled by cubic spline to the filter step (000 sec. 6.1: 5e-7 s), as a real run would be.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <stdexcept>

#include "analysis/estimate/cut_input.h"
#include "analysis/estimate/spline_resample.h"
#include "analysis/estimate/tool_model.h"
#include "analysis/milling/simulation.h"

namespace chatterlab {
namespace estimate {
namespace testing {

constexpr double kPi = 3.141592653589793238463;

// 000 table 5.2, incline trial 1 (the truth of these tests).
inline ModalParameters table52_modal() { return {0.03134, 22.21, 9.840e5}; }
inline std::vector<ToothCoefficients> table52_coefficients() {
  return {{2.483e8, 2.196e8}, {6.641e9, 4.154e9}};
}
// 000 sec. 5.1: the hammer test's values (damping 40 % below the EKF's 22.21 kg/s).
inline ModalParameters hammer_modal() { return {0.03211, 13.39, 1.023e6}; }
// 000 sec. 6.1: the randomized initial estimates used in 000 chs 5-6.
inline ModalParameters dissertation_start_modal() { return {0.02270, 40.56, 1.162e6}; }
inline std::vector<ToothCoefficients> dissertation_start_coefficients() {
  return {{1.493e8, 2.315e8}, {4.257e9, 3.106e9}};
}

struct SyntheticCutSpec {
  double depth_m = 1e-3;             // constant axial depth
  double record_s = 0.2;             // record handed to the filter (000 sec. 6.1: 0.2 s)
  int settle_revolutions = 30;       // simulated before the record starts (transient decays)
  double acquisition_step_s = 1e-5;  // sampling step of the "sensors" (100 kHz, 000 sec. 6.1)
  double noise_m = 5e-7;             // white measurement noise std (000 sec. 6.1)
  double filter_step_s = 5e-7;       // resampled step (000 sec. 6.1)
  SplineEnd spline_end = SplineEnd::kNotAKnot;
  // Simulator steps per tooth pass. 4,000 = 5e-7 s, the filter step: the record is simulated at
  // the resampled step (then acquired at 100 kHz and resampled, as a real run). 000 sec. 5.2's
  // 800 (2.5 us) adds the simulator's own zero-order-hold delay of the force, h / 2, which
  // biases the estimates by up to 1 % (docs/estimators.md).
  int steps_per_tooth = 4000;
  unsigned seed = 20240607;
  ModalParameters modal = table52_modal();
  std::vector<ToothCoefficients> coefficients = table52_coefficients();
};

inline CutSetup setup_for(const SyntheticCutSpec&) { return CutSetup{}; }  // 000 sec. 5.2

// Simulates at spec.steps_per_tooth, samples every acquisition step (a multiple of the
// simulator step), adds noise, resamples to filter_step_s.
inline MeasuredCut synthetic_cut(const SyntheticCutSpec& spec) {
  using namespace milling;
  SimulationOptions o;
  o.modal_x = {spec.modal.m_kg, spec.modal.c_kg_s, spec.modal.k_N_m};
  o.coefficients.clear();
  for (const ToothCoefficients& c : spec.coefficients) {
    o.coefficients.push_back(cutting_coefficients(c.Kt_N_m2, c.Kr_N_m2));
  }
  o.steps_per_tooth = spec.steps_per_tooth;
  const SimulationGrid probe = simulation_grid(o);
  const double h = probe.time_step_s;
  const int S = probe.steps_per_revolution;
  const int record_revolutions = static_cast<int>(std::ceil(spec.record_s / (h * S))) + 1;
  o.depth = DepthProfile::constant(spec.depth_m, spec.settle_revolutions + record_revolutions);
  RecordingRequest rq;
  for (int j = 0; j < record_revolutions; ++j)
    rq.full_revolutions.push_back(spec.settle_revolutions + j);
  const SimulationResult sim = simulate(o, rq);
  if (!sim.summary.ok) throw std::runtime_error("simulation failed: " + sim.summary.message);

  const int every = static_cast<int>(std::lround(spec.acquisition_step_s / h));
  const Eigen::Index fine_steps = static_cast<Eigen::Index>(std::llround(spec.record_s / h));
  const Eigen::Index n = fine_steps / every + 1;
  Eigen::VectorXd x(n), y(n);
  std::mt19937_64 rng(spec.seed);
  std::normal_distribution<double> noise(0.0, spec.noise_m);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index k = i * every;
    const RevolutionRecord& r = sim.records[static_cast<std::size_t>(k / S)];
    x[i] = r.x_m[k % S] + noise(rng);
    y[i] = r.y_m[k % S] + noise(rng);
  }
  MeasuredCut cut;
  cut.time_step_s = spec.filter_step_s;
  cut.x_m = resample_cubic_spline(x, spec.acquisition_step_s, spec.filter_step_s, spec.spline_end);
  cut.y_m = resample_cubic_spline(y, spec.acquisition_step_s, spec.filter_step_s, spec.spline_end);
  const double omega = o.spindle_rpm * 2.0 * kPi / 60.0;
  // The record starts at a revolution start: theta_1 = 0 there (simulation.h).
  cut.theta1_rad = Eigen::VectorXd::LinSpaced(
      cut.x_m.size(), 0.0, omega * spec.filter_step_s * static_cast<double>(cut.x_m.size() - 1));
  cut.depth_m = Eigen::VectorXd::Constant(1, spec.depth_m);
  return cut;
}

}  // namespace testing
}  // namespace estimate
}  // namespace chatterlab
