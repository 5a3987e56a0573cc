// The cut schedule and its simulated ramp against closed forms.
#include <gtest/gtest.h>

#include "analysis/common/summary.h"
#include "analysis/sync/cut_schedule.h"

namespace chatterlab {
namespace sync {
namespace {

constexpr double kExact = 1e-15;  // a few ulps of the values below

TEST(CutSchedule, DepthIsLinearInTimeAndClampedToTheWindow) {
  const CutSchedule ramp{1.0, 3.0, 0.0, 2e-3};  // 1 mm per second
  EXPECT_NEAR(ramp.depth_at_m(2.0), 1e-3, kExact);
  EXPECT_NEAR(ramp.depth_at_m(2.5), 1.5e-3, kExact);
  EXPECT_EQ(ramp.depth_at_m(0.0), 0.0);
  EXPECT_EQ(ramp.depth_at_m(9.0), 2e-3);
  EXPECT_TRUE(ramp.ramped());
  const CutSchedule flat{1.0, 3.0, 1e-3, 1e-3};
  EXPECT_EQ(flat.depth_at_m(2.0), 1e-3);
  EXPECT_FALSE(flat.ramped());
}

TEST(CutSchedule, RampProfileSpansTheCutWindowsRevolutions) {
  // 2 s at 15,000 rpm is 500 revolutions over 2 mm: 250 revolutions per mm, and the simulator
  // runs ceil(2 mm * 250) = 500 revolutions, the cut window's.
  const CutSchedule ramp{1.0, 3.0, 0.0, 2e-3};
  const milling::DepthProfile p = ramp_depth_profile(ramp, 15000.0);
  EXPECT_EQ(p.kind, milling::DepthProfile::Kind::kRamp);
  EXPECT_EQ(p.start_m, 0.0);
  EXPECT_EQ(p.end_m, 2e-3);
  EXPECT_NEAR(p.revolutions_per_mm, 250.0, 1e-12);
  milling::SimulationOptions o;
  o.modal_x = {0.03134, 22.21, 9.84e5};
  o.coefficients = {milling::cutting_coefficients(2.483e8, 2.196e8),
                    milling::cutting_coefficients(6.641e9, 4.154e9)};
  o.depth = p;
  EXPECT_EQ(milling::simulation_grid(o).revolutions, 500);
  // A decline gives the same rate.
  const CutSchedule decline{1.0, 3.0, 2e-3, 0.0};
  EXPECT_NEAR(ramp_depth_profile(decline, 15000.0).revolutions_per_mm, 250.0, 1e-12);
}

TEST(CutSchedule, RampProfileNeedsARamp) {
  try {
    ramp_depth_profile({1.0, 3.0, 1e-3, 1e-3}, 15000.0);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "cut.axial_depth_m = 0.001: must differ from the start depth (a ramp)");
  }
  EXPECT_THROW(ramp_depth_profile({3.0, 1.0, 0.0, 2e-3}, 15000.0), InputError);
  EXPECT_THROW(ramp_depth_profile({1.0, 3.0, 0.0, 2e-3}, 0.0), InputError);
}

}  // namespace
}  // namespace sync
}  // namespace chatterlab
