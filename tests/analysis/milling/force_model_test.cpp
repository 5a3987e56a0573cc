#include "analysis/milling/force_model.h"

#include <gtest/gtest.h>

#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace milling {
namespace {

// Hand-computed values are exact to the digits written; products of a few doubles agree to
// ~1e-15 relative, so 1e-9 N on forces of ~100 N is rounding only.
constexpr double kHandTolN = 1e-9;

// Coefficients chosen for round hand arithmetic: b = 2 mm, w = 0.05 mm gives
//   F_t = 6e8 * 2e-3 * 5e-5 + 1e4 * 2e-3 = 60 + 20 = 80 N,
//   F_r = 2e8 * 2e-3 * 5e-5 + 1.5e4 * 2e-3 = 20 + 30 = 50 N.
const CuttingCoefficients kHand{6e8, 2e8, 1e4, 1.5e4};

TEST(ToothForce, Eqs21And22WithEdgeTermsByHand) {
  const ToothForce f = tooth_force(kHand, 5e-5, 2e-3, true);
  EXPECT_NEAR(f.tangential_N, 80.0, kHandTolN);
  EXPECT_NEAR(f.radial_N, 50.0, kHandTolN);
}

TEST(ToothForce, ZeroWhenNotEngagedOrNoChip) {
  for (const ToothForce& f :
       {tooth_force(kHand, 5e-5, 2e-3, false), tooth_force(kHand, 0.0, 2e-3, true),
        tooth_force(kHand, -1e-6, 2e-3, true)}) {
    EXPECT_EQ(f.tangential_N, 0.0);
    EXPECT_EQ(f.radial_N, 0.0);
  }
}

TEST(ToothForceXy, Eqs23And24ByHand) {
  const ToothForce f{80.0, 50.0};
  // theta = 30 deg: Fx = -(80 cos30 + 50 sin30) = -(69.2820323 + 25) = -94.2820323,
  //                 Fy = 80 sin30 - 50 cos30 = 40 - 43.3012702 = -3.3012702.
  const Eigen::Vector2d f30 = tooth_force_xy_N(f, kPi / 6.0);
  EXPECT_NEAR(f30.x(), -94.28203230275509, kHandTolN);
  EXPECT_NEAR(f30.y(), -3.301270189221932, kHandTolN);
  // theta = 0 (tooth on +y, cutting towards +x): F_t opposes +x, F_r points at -y.
  const Eigen::Vector2d f0 = tooth_force_xy_N(f, 0.0);
  EXPECT_NEAR(f0.x(), -80.0, kHandTolN);
  EXPECT_NEAR(f0.y(), -50.0, kHandTolN);
  // theta = 90 deg (tooth on +x, cutting towards -y).
  const Eigen::Vector2d f90 = tooth_force_xy_N(f, kPi / 2.0);
  EXPECT_NEAR(f90.x(), -50.0, kHandTolN);
  EXPECT_NEAR(f90.y(), 80.0, kHandTolN);
}

TEST(ToothForceXy, TangentialOpposesTipVelocityRadialPointsInward) {
  // Property over a turn: the projection is a rotation (norm kept), F_t component is minus the
  // unit tip velocity d/dtheta (sin, cos) = (cos, -sin), F_r component is minus the unit tip
  // position.
  const ToothForce f{80.0, 50.0};
  for (int k = 0; k < 36; ++k) {
    const double th = 2.0 * kPi * k / 36.0;
    const Eigen::Vector2d F = tooth_force_xy_N(f, th);
    const Eigen::Vector2d velocity_dir(std::cos(th), -std::sin(th));
    const Eigen::Vector2d tip_dir = tooth_tip_position_m(1.0, th);
    EXPECT_NEAR(F.norm(), std::hypot(80.0, 50.0), kHandTolN);
    EXPECT_NEAR(-F.dot(velocity_dir), 80.0, kHandTolN);
    EXPECT_NEAR(-F.dot(tip_dir), 50.0, kHandTolN);
  }
}

TEST(Geometry, ToothAnglesTipAndStaticChip) {
  EXPECT_DOUBLE_EQ(tooth_angle_rad(0.3, 1, 2), 0.3);
  EXPECT_DOUBLE_EQ(tooth_angle_rad(0.3, 2, 2), 0.3 + kPi);
  EXPECT_DOUBLE_EQ(tooth_angle_rad(0.0, 3, 3), 4.0 * kPi / 3.0);
  const Eigen::Vector2d tip = tooth_tip_position_m(6.35e-3, kPi / 6.0);
  EXPECT_NEAR(tip.x(), 3.175e-3, 1e-15);                               // r sin 30
  EXPECT_NEAR(tip.y(), 6.35e-3 * std::sqrt(3.0) / 2.0, 1e-15);         // r cos 30
  EXPECT_NEAR(static_chip_thickness_m(1e-4, kPi / 6.0), 5e-5, 1e-18);  // h sin 30
  try {
    tooth_angle_rad(0.0, 3, 2);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "tooth_angle_rad: p = 3, n = 2: must satisfy 1 <= p <= n");
  }
}

TEST(Geometry, InCutWindowIsHalfOpenAndWraps) {
  EXPECT_TRUE(in_cut(0.0, 0.0, kPi));
  EXPECT_TRUE(in_cut(kPi - 1e-9, 0.0, kPi));
  EXPECT_FALSE(in_cut(kPi, 0.0, kPi));
  EXPECT_TRUE(in_cut(2.0 * kPi + 0.5, 0.0, kPi));
  EXPECT_FALSE(in_cut(-0.5, 0.0, kPi));
  // Up-milling, 0.382 mm immersion on a 6.35 mm radius: exit = acos(1 - ri/r) (000 eq 2.9).
  const double exit = std::acos(1.0 - 0.382 / 6.35);
  EXPECT_TRUE(in_cut(0.9 * exit, 0.0, exit));
  EXPECT_FALSE(in_cut(1.1 * exit, 0.0, exit));
}

}  // namespace
}  // namespace milling
}  // namespace chatterlab
