// Bifurcation of simulated runs (simulated_bifurcation.h): the detector over the completed
// revolutions, with a diverged run's end taken as chatter; checked against the detector called
// directly on the same samples (second method) and counts known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "analysis/dynamics/simulated_bifurcation.h"
#include "analysis/milling/simulation.h"

namespace chatterlab {
namespace dynamics {
namespace {

constexpr double kNoiseM = 5e-7;  // measurement noise stated to the detector (000 sec. 6.1)

// 000 table 5.2, incline trial 1, 000 sec. 5.2 cut conditions.
milling::SimulationOptions incline1() {
  milling::SimulationOptions o;
  o.modal_x = {0.03134, 22.21, 9.84e5};
  o.coefficients = {milling::cutting_coefficients(2.483e8, 2.196e8),
                    milling::cutting_coefficients(6.641e9, 4.154e9)};
  return o;
}

TEST(CompletedRevolutions, CountsTheLeadingFiniteSamplesOfBothAxes) {
  milling::OncePerRevolution s;
  s.depth_m = Eigen::VectorXd::Zero(6);
  s.x_m = Eigen::VectorXd::Zero(6);
  s.y_m = Eigen::VectorXd::Zero(6);
  EXPECT_EQ(completed_revolutions(s), 6);
  s.y_m[3] = std::numeric_limits<double>::quiet_NaN();  // y alone breaks the run at 3
  EXPECT_EQ(completed_revolutions(s), 3);
  s.x_m[1] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(completed_revolutions(s), 1);
}

TEST(SimulatedRunBifurcation, DivergedRunEndsInChatterAtTheDetectorsDepth) {
  // Switching by angle alone keeps pulling on the tool once the chip is gone, so the chatter
  // past the stability limit grows until the deflection leaves the physical range.
  milling::SimulationOptions o = incline1();
  o.switching = milling::SwitchingRule::kAngleOnly;
  o.depth = milling::DepthProfile::ramp(0.0, 6e-3, 200.0);
  const milling::SimulationResult sim = milling::simulate(o);
  ASSERT_FALSE(sim.summary.ok()) << "the run was expected to diverge";
  BifurcationOptions bo;
  bo.measurement_noise_m = kNoiseM;
  const SimulatedRunBifurcation b = simulated_run_bifurcation(sim, bo);
  EXPECT_TRUE(b.diverged);
  // Every revolution before the failure is finite, none after it.
  const Eigen::Index done = b.completed_revolutions;
  ASSERT_GT(done, bo.window_revolutions);
  ASSERT_LT(done, sim.samples.x_m.size());
  EXPECT_TRUE(sim.samples.x_m.head(done).allFinite());
  EXPECT_FALSE(std::isfinite(sim.samples.x_m[done]));
  ASSERT_TRUE(b.result.has_value());
  ASSERT_TRUE(b.result->summary.ok()) << b.result->summary.message;
  // Second method: the detector on the same samples, told the run ends unbounded.
  BifurcationOptions direct = bo;
  direct.ends_unbounded = true;
  const BifurcationResult r =
      detect_bifurcation(sim.samples.depth_m.head(done), sim.samples.x_m.head(done), direct);
  ASSERT_TRUE(r.bifurcation_depth_m.has_value());
  ASSERT_TRUE(b.result->bifurcation_depth_m.has_value());
  EXPECT_EQ(*b.result->bifurcation_depth_m, *r.bifurcation_depth_m);
  EXPECT_EQ(b.result->verdict, RunVerdict::kChanges);
  EXPECT_EQ(b.result->state.back(), RevolutionState::kChatter);
}

TEST(SimulatedRunBifurcation, CompletedRampIsTheDetectorOnAllItsRevolutions) {
  // 0 to 2 mm: chatter-free throughout (000 table 5.2's incline 1 chatters near 3.8 mm).
  milling::SimulationOptions o = incline1();
  o.depth = milling::DepthProfile::ramp(0.0, 2e-3, 200.0);
  const milling::SimulationResult sim = milling::simulate(o);
  ASSERT_TRUE(sim.summary.ok()) << sim.summary.message;
  BifurcationOptions bo;
  bo.measurement_noise_m = kNoiseM;
  const SimulatedRunBifurcation b = simulated_run_bifurcation(sim, bo);
  EXPECT_FALSE(b.diverged);
  EXPECT_EQ(b.completed_revolutions, 400);  // 2 mm at 200 revolutions per mm
  ASSERT_TRUE(b.result.has_value());
  const BifurcationResult r = detect_bifurcation(sim.samples.depth_m, sim.samples.x_m, bo);
  EXPECT_EQ(b.result->verdict, r.verdict);
  EXPECT_EQ(b.result->verdict, RunVerdict::kAllStable);
  EXPECT_FALSE(b.result->bifurcation_depth_m.has_value());
}

TEST(SimulatedRunBifurcation, TooFewRevolutionsLeaveTheDetectorOut) {
  // 61 revolutions is the detector's default window: a run must be longer.
  milling::SimulationOptions o = incline1();
  o.depth = milling::DepthProfile::constant(1e-3, 61);
  const milling::SimulationResult sim = milling::simulate(o);
  ASSERT_TRUE(sim.summary.ok());
  const SimulatedRunBifurcation b = simulated_run_bifurcation(sim);
  EXPECT_EQ(b.completed_revolutions, 61);
  EXPECT_FALSE(b.result.has_value());
}

}  // namespace
}  // namespace dynamics
}  // namespace chatterlab
