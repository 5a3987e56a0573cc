#include "analysis/milling/engagement.h"

#include <gtest/gtest.h>

#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/milling/force_model.h"
#include "analysis/milling/simulation.h"

namespace chatterlab {
namespace milling {
namespace {

constexpr double kR = 6.35e-3, kRi = 0.382e-3;  // 000 sec. 5.2

TEST(Engagement, UpMillingIsEqs28To29) {
  const EngagementWindow w = engagement_window(Operation::kUpMilling, kR, kRi);
  EXPECT_EQ(w.entry_rad, 0.0);
  // acos(1 - 0.382 / 6.35) = acos(0.9398425) = 0.3486273 rad = 19.97 deg.
  EXPECT_NEAR(w.exit_rad, 0.3486273, 1e-7);
  // Exit on the original surface y = r - r_i, entry on the finished wall y = r.
  EXPECT_NEAR(tooth_tip_position_m(kR, w.exit_rad).y(), kR - kRi, 1e-15);
  EXPECT_NEAR(tooth_tip_position_m(kR, w.entry_rad).y(), kR, 1e-15);
}

// Down-milling, same rotation (theta increasing: tip velocity (cos, -sin)) and feed (+x): the
// tooth must move with the feed where it cuts, tip velocity -x, so cos(theta) < 0 and the
// workpiece is on -y. It enters the original surface y = -(r - r_i) with the thickest chip and
// leaves at the finished wall y = -r (theta = pi) with none.
TEST(Engagement, DownMillingDerivation) {
  const EngagementWindow up = engagement_window(Operation::kUpMilling, kR, kRi);
  const EngagementWindow w = engagement_window(Operation::kDownMilling, kR, kRi);
  EXPECT_NEAR(w.entry_rad, kPi - up.exit_rad, 1e-15);
  EXPECT_EQ(w.exit_rad, kPi);
  EXPECT_NEAR(tooth_tip_position_m(kR, w.entry_rad).y(), -(kR - kRi), 1e-15);
  EXPECT_NEAR(tooth_tip_position_m(kR, w.exit_rad).y(), -kR, 1e-15);
  for (double th = w.entry_rad; th <= w.exit_rad; th += 0.01) {
    EXPECT_LT(std::cos(th), 0.0);  // tip velocity r w (cos, -sin) along -x: with the feed
  }
  // Chip h sin(theta): thickest at entry, zero at exit (the reverse of up-milling).
  EXPECT_NEAR(static_chip_thickness_m(6.35e-5, w.entry_rad),
              static_chip_thickness_m(6.35e-5, up.exit_rad), 1e-18);
  EXPECT_NEAR(static_chip_thickness_m(6.35e-5, w.exit_rad), 0.0, 1e-19);
  // Full slot: both give [0, pi].
  const EngagementWindow slot = engagement_window(Operation::kDownMilling, kR, 2 * kR);
  EXPECT_NEAR(slot.entry_rad, 0.0, 1e-15);
  EXPECT_EQ(slot.exit_rad, kPi);
}

TEST(Engagement, BadInput) {
  try {
    engagement_window(Operation::kUpMilling, kR, 3 * kR);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "engagement_window: radial_immersion_m = 0.01905: must satisfy 0 < r_i <= 2 r = "
              "0.0127");
  }
  EXPECT_THROW(engagement_window(Operation::kUpMilling, -1.0, kRi), InputError);
}

// The traditional simulator cuts only inside the window: down-milling at a small depth (0.1 mm)
// with switching by angle, each tooth has a chip exactly at the angle indices in [entry, exit),
// h sin(theta) (falling to the exit) plus the dynamic term.
TEST(Engagement, DownMillingSimulationCutsInsideTheWindowOnly) {
  SimulationOptions o;
  o.modal_x = {0.03134, 22.21, 9.840e5};
  o.coefficients = {cutting_coefficients(0.2483e9, 0.2196e9),
                    cutting_coefficients(6.641e9, 4.154e9)};
  o.operation = Operation::kDownMilling;
  o.switching = SwitchingRule::kAngleOnly;  // g = 1 exactly in the window (contact may drop a
                                            // tooth whose chip near the exit turns negative)
  o.depth = DepthProfile::constant(0.1e-3, 20);
  RecordingRequest rq;
  rq.full_revolutions = {19};
  const SimulationResult r = simulate(o, rq);
  ASSERT_TRUE(r.summary.ok());
  const RevolutionRecord& rec = r.records[0];
  const EngagementWindow w = engagement_window(Operation::kDownMilling, kR, kRi);
  // Dynamic term of eq. 2.7: |(d(t) - d(t - tau)) . (sin, cos)| <= 2 max |d| (steady orbit).
  const double dynamic =
      2 * std::hypot(rec.x_m.cwiseAbs().maxCoeff(), rec.y_m.cwiseAbs().maxCoeff());
  EXPECT_LT(dynamic, 0.2 * 6.35e-5);
  for (int p = 0; p < 2; ++p) {
    int cut = 0;
    for (Eigen::Index a = 0; a < rec.x_m.size(); ++a) {
      const double th = std::fmod(rec.theta1_rad[a] + p * kPi, 2 * kPi);
      const bool inside = th >= w.entry_rad && th < w.exit_rad;
      EXPECT_EQ(rec.chip_m(a, p) != 0.0, inside) << "tooth " << p + 1 << " theta " << th;
      if (inside) {
        ++cut;
        EXPECT_NEAR(rec.chip_m(a, p), 6.35e-5 * std::sin(th), dynamic);
      }
    }
    EXPECT_EQ(cut, 88);  // indices 712..799: entry 2.792965 rad / (2 pi / 1600) = 711.1
  }
}

}  // namespace
}  // namespace milling
}  // namespace chatterlab
