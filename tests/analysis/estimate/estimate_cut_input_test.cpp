#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/estimate/cut_input.h"
#include "analysis/estimate/spline_resample.h"
#include "analysis/milling/simulation.h"

namespace chatterlab {
namespace estimate {
namespace {

// Two revolutions of 000 table 5.2's incline-1 cut at 1 mm, recorded at the simulator's step,
// as a MeasuredCut (no noise, no resampling) with the simulator's own chips and forces.
struct Recorded {
  MeasuredCut cut;
  milling::SimulationResult sim;
};

Recorded recorded_cut(double depth_m) {
  using namespace milling;
  SimulationOptions o;
  o.modal_x = {0.03134, 22.21, 9.840e5};
  o.coefficients = {cutting_coefficients(2.483e8, 2.196e8), cutting_coefficients(6.641e9, 4.154e9)};
  o.depth = DepthProfile::constant(depth_m, 12);
  RecordingRequest rq;
  rq.full_revolutions = {10, 11};
  Recorded r;
  r.sim = simulate(o, rq);
  const int S = r.sim.steps_per_revolution;
  r.cut.time_step_s = r.sim.time_step_s;
  r.cut.x_m.resize(2 * S);
  r.cut.y_m.resize(2 * S);
  r.cut.theta1_rad.resize(2 * S);
  for (int j = 0; j < 2; ++j) {
    r.cut.x_m.segment(j * S, S) = r.sim.records[static_cast<std::size_t>(j)].x_m;
    r.cut.y_m.segment(j * S, S) = r.sim.records[static_cast<std::size_t>(j)].y_m;
    for (int a = 0; a < S; ++a) r.cut.theta1_rad[j * S + a] = 2.0 * kPi * (j * S + a) / S;
  }
  r.cut.depth_m = Eigen::VectorXd::Constant(1, depth_m);
  return r;
}

TEST(CutChips, MatchTheSimulatorsChipsAndForces) {
  // Reference: the simulator's recorded g_p w_p and Fx, Fy (000 eqs 2.3-2.4, 2.7) of revolution
  // 11, computed from the same deflections: the same arithmetic, so equal to rounding.
  const Recorded r = recorded_cut(1e-3);
  const CutChips chips(r.cut, CutSetup{});
  const int S = r.sim.steps_per_revolution;
  EXPECT_EQ(chips.delay_samples(), 800.0);  // tau = 2 ms at 2.5 us
  EXPECT_EQ(chips.first_step(), 800);
  const std::vector<ToothCoefficients> K = {{2.483e8, 2.196e8}, {6.641e9, 4.154e9}};
  const milling::RevolutionRecord& rec = r.sim.records[1];
  int engaged_steps = 0;
  for (int a = 0; a < S; ++a) {
    const StepChips c = chips.chips(S + a);
    for (int p = 0; p < 2; ++p) {
      EXPECT_NEAR(c.tooth[static_cast<std::size_t>(p)].bw_m2, 1e-3 * rec.chip_m(a, p), 1e-20)
          << "step " << a << " tooth " << p + 1;
      EXPECT_EQ(((c.engaged >> p) & 1u) != 0, rec.chip_m(a, p) > 0.0);
    }
    engaged_steps += c.engaged != 0;
    const Eigen::Vector2d F = cutting_force_N(c, K);
    EXPECT_NEAR(F.x(), rec.Fx_N[a], 1e-9 * (1.0 + std::abs(rec.Fx_N[a])));
    EXPECT_NEAR(F.y(), rec.Fy_N[a], 1e-9 * (1.0 + std::abs(rec.Fy_N[a])));
  }
  // r_i = 0.382 mm of r = 6.35 mm: each tooth's window is 0.3486 rad, 5.5 % of a revolution.
  EXPECT_GT(engaged_steps, 0);
  EXPECT_LT(engaged_steps, S / 9);
}

TEST(CutChips, RegressorIsTheForcesDerivative) {
  // F = regressor [Kt; Kr] per tooth (000 eqs 4.29-4.32 times m / T).
  ToothChip t;
  t.sin_theta = std::sin(0.2);
  t.cos_theta = std::cos(0.2);
  t.bw_m2 = 1.7e-8;
  StepChips c;
  c.teeth = 1;
  c.tooth[0] = t;
  const Eigen::Vector2d F = cutting_force_N(c, {{3e9, 2e9}});
  EXPECT_NEAR((tooth_regressor_m2(t) * Eigen::Vector2d(3e9, 2e9) - F).norm(), 0.0, 1e-12);
}

TEST(CutChips, FractionalDelayInterpolatesLinearly) {
  // T = 7e-7 s: tau / T = 2e-3 / 7e-7 = 2857.14..., not an integer.
  MeasuredCut cut;
  cut.time_step_s = 7e-7;
  const Eigen::Index n = 4000;
  cut.x_m = Eigen::VectorXd::LinSpaced(n, 0.0, 1e-5);  // a ramp: linear interpolation is exact
  cut.y_m = Eigen::VectorXd::Zero(n);
  cut.theta1_rad = Eigen::VectorXd::Constant(n, 0.1);  // tooth 1 in its window
  cut.depth_m = Eigen::VectorXd::Constant(1, 1e-3);
  const CutChips chips(cut, CutSetup{});
  EXPECT_NEAR(chips.delay_samples(), 2e-3 / 7e-7, 1e-9);
  EXPECT_EQ(chips.first_step(), 2858);
  const Eigen::Index k = 3500;
  const double slope = 1e-5 / static_cast<double>(n - 1);  // per sample
  const double dx = slope * chips.delay_samples();         // x(t) - x(t - tau)
  const double w = (0.0635e-3 + dx) * std::sin(0.1);
  EXPECT_NEAR(chips.chips(k).tooth[0].bw_m2, 1e-3 * w, 1e-18);
}

TEST(ResampleCut, ResamplesSignalsAndUnwrapsTheAngle) {
  // 100 kHz record with theta_1 wrapped to [0, 2 pi), resampled to 5e-7 s: x, y as
  // resample_cubic_spline gives them, theta_1 = omega t exactly (a straight line, reproduced by
  // the spline), a linear depth ramp likewise.
  MeasuredCut c;
  c.time_step_s = 1e-5;
  const Eigen::Index n = 1001;
  const double omega = 15000.0 * 2.0 * kPi / 60.0;
  c.x_m.resize(n);
  c.y_m.resize(n);
  c.theta1_rad.resize(n);
  c.depth_m.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * 1e-5;
    c.x_m[i] = 1e-5 * std::sin(5600.0 * t);
    c.y_m[i] = 1e-5 * std::cos(3000.0 * t);
    c.theta1_rad[i] = std::fmod(0.3 + omega * t, 2.0 * kPi);
    c.depth_m[i] = 1e-3 + 0.5 * t;
  }
  const MeasuredCut r = resample_cut(c, 5e-7);
  ASSERT_EQ(r.x_m.size(), 20001);
  EXPECT_EQ(r.time_step_s, 5e-7);
  EXPECT_EQ(r.x_m, resample_cubic_spline(c.x_m, 1e-5, 5e-7));
  EXPECT_EQ(r.y_m, resample_cubic_spline(c.y_m, 1e-5, 5e-7));
  for (Eigen::Index j = 0; j < r.x_m.size(); ++j) {
    const double t = static_cast<double>(j) * 5e-7;
    ASSERT_NEAR(r.theta1_rad[j], 0.3 + omega * t, 1e-9) << j;
    ASSERT_NEAR(r.depth_m[j], 1e-3 + 0.5 * t, 1e-15) << j;
  }
  c.depth_m = Eigen::VectorXd::Constant(1, 2e-3);
  EXPECT_EQ(resample_cut(c, 5e-7).depth_m.size(), 1);
}

void expect_error(const MeasuredCut& cut, const CutSetup& setup, const std::string& message) {
  try {
    const CutChips chips(cut, setup);
    FAIL() << "no error; expected: " << message;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(CutChips, RejectsBadInput) {
  MeasuredCut good;
  good.time_step_s = 5e-7;
  good.x_m = Eigen::VectorXd::Zero(5000);
  good.y_m = good.x_m;
  good.theta1_rad = good.x_m;
  good.depth_m = Eigen::VectorXd::Constant(1, 1e-3);
  EXPECT_NO_THROW(CutChips(good, CutSetup{}));

  MeasuredCut c = good;
  c.time_step_s = 0.0;
  expect_error(c, CutSetup{}, "cut.time_step_s = 0: must be finite and > 0");
  c = good;
  c.y_m.resize(10);
  expect_error(c, CutSetup{}, "cut.y_m.size() = 10: must equal cut.x_m.size() = 5000");
  c = good;
  c.theta1_rad.resize(3);
  expect_error(c, CutSetup{}, "cut.theta1_rad.size() = 3: must equal cut.x_m.size() = 5000");
  c = good;
  c.depth_m = Eigen::VectorXd::Zero(2);
  expect_error(c, CutSetup{},
               "cut.depth_m.size() = 2: must be 1 (constant depth) or cut.x_m.size() = 5000");
  c = good;
  c.x_m[7] = std::nan("");
  expect_error(c, CutSetup{}, "cut.x_m[7] = nan: must be finite");
  c = good;
  c.depth_m[0] = -1e-3;
  expect_error(c, CutSetup{}, "cut.depth_m[0] = -0.001: must be >= 0");
  c = good;
  c.x_m.resize(4001);
  c.y_m.resize(4001);
  c.theta1_rad.resize(4001);
  expect_error(c, CutSetup{},
               "cut.x_m.size() = 4001: must be >= the chip delay tau / T + 2 = 4002 samples (one "
               "tooth period plus one filter step)");

  CutSetup s;
  s.teeth = 0;
  expect_error(good, s, "setup.teeth = 0: must be in [1, 32]");
  s = CutSetup{};
  s.spindle_rpm = -1.0;
  expect_error(good, s, "setup.spindle_rpm = -1: must be > 0");
  s = CutSetup{};
  s.radial_immersion_m = 0.02;
  expect_error(good, s, "setup.radial_immersion_m = 0.02: must be in (0, 2 radius_m]");
  s = CutSetup{};
  s.radius_m = 0.0;
  expect_error(good, s, "setup.radius_m = 0: must be > 0");
  s = CutSetup{};
  s.feed_per_tooth_m = -1.0;
  expect_error(good, s, "setup.feed_per_tooth_m = -1: must be >= 0");
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
