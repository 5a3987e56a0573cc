#include <gtest/gtest.h>

#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/dynamics/orbit_synth.h"
#include "analysis/dynamics/poincare.h"

namespace chatterlab {
namespace dynamics {
namespace {

constexpr double kMm = 1e-3;
constexpr double kNoise = 5e-7;  // m, 000 sec. 6.1

// 0 -> 6 mm over 7,740 revolutions (000 sec. 5.2); chatter from 3 mm of the given pattern at
// 2e-5 m, 40 times the noise, as in the well-developed chatter of 000 Figs 5.1 and 5.7.
SyntheticOrbit incline(double nu, bool cloud, std::uint64_t seed) {
  OrbitSpec s;
  s.revolutions = 7740;
  s.start_depth_m = 0.0;
  s.end_depth_m = 6 * kMm;
  s.offset_m = 2e-5;
  s.drift_m_per_m = 1e-6 / (6 * kMm);
  s.noise_sigma_m = kNoise;
  s.seed = seed;
  ChatterEpisodeSpec e;
  e.low_depth_m = 3 * kMm;
  e.amplitude_m = 2e-5;
  e.rotation_number = nu;
  e.cloud = cloud;
  e.phase_rad = 0.4;
  s.chatter.push_back(e);
  return synthesize_orbit(s);
}

TEST(PoincareMap, TwentyPointsCentredOnTheRequestedDepth) {
  const SyntheticOrbit o = incline(0.618034, false, 1);
  const PoincareMap m = poincare_map(o.depth_m, o.x_m, 1.0 * kMm);
  // Depth of revolution n is 6 mm n / 7739: 1 mm is nearest n = 1290 (1.00013 mm).
  EXPECT_EQ(m.centre_revolution, 1290);
  EXPECT_EQ(m.first_revolution, 1280);
  ASSERT_EQ(m.points_m.rows(), 20);
  for (Eigen::Index i = 0; i < 20; ++i) {
    EXPECT_EQ(m.points_m(i, 0), o.x_m[1279 + i]);
    EXPECT_EQ(m.points_m(i, 1), o.x_m[1280 + i]);
  }
  EXPECT_DOUBLE_EQ(m.first_depth_m, o.depth_m[1280]);
  EXPECT_DOUBLE_EQ(m.last_depth_m, o.depth_m[1299]);
  EXPECT_EQ(m.requested_depth_m, 1.0 * kMm);

  // At the ends of the run the window shifts inward: x_(n-1) must exist, so n >= 1.
  const PoincareMap start = poincare_map(o.depth_m, o.x_m, 0.0);
  EXPECT_EQ(start.first_revolution, 1);
  const PoincareMap end = poincare_map(o.depth_m, o.x_m, 6 * kMm);
  EXPECT_EQ(end.first_revolution, 7740 - 20);

  const std::vector<PoincareMap> maps = poincare_maps(o.depth_m, o.x_m, {1 * kMm, 3 * kMm});
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps[0].centre_revolution, 1290);
  EXPECT_EQ(maps[1].centre_revolution, 3869);  // 3 mm falls midway: the first of the two

  PoincareMapOptions five;
  five.revolutions = 5;
  const PoincareMap small = poincare_map_at_revolution(o.depth_m, o.x_m, 100, five);
  EXPECT_EQ(small.first_revolution, 98);  // 100 - 5/2
  EXPECT_EQ(small.points_m.rows(), 5);
  EXPECT_TRUE(std::isnan(small.requested_depth_m));
}

TEST(OrbitClass, ReadsTheShapesOf000Section5_2) {
  // At 1 mm every run is on its period-one orbit; at 5 mm the pattern chosen shows.
  struct Case {
    double nu;
    bool cloud;
    OrbitShape shape;
    int period;
  };
  const Case cases[] = {
      {0.5, false, OrbitShape::kClusters, 2},   // two branches (000 sec. 7.2)
      {0.25, false, OrbitShape::kClusters, 4},  // four clusters (000 sec. 5.2)
      {0.618034, false, OrbitShape::kRing, 0},  // quasi-periodic ellipse
      {0.13, false, OrbitShape::kRing, 0},      // a slower one
      {0.0, true, OrbitShape::kCloud, 0},       // a cloud of numerous points
  };
  std::uint64_t seed = 2;
  for (const Case& c : cases) {
    const SyntheticOrbit o = incline(c.nu, c.cloud, seed++);
    const OrbitClass quiet = classify_orbit(poincare_map(o.depth_m, o.x_m, 1 * kMm), kNoise);
    EXPECT_EQ(quiet.shape, OrbitShape::kFixedPoint) << c.nu;
    EXPECT_EQ(quiet.period, 1);
    const OrbitClass loud = classify_orbit(poincare_map(o.depth_m, o.x_m, 5 * kMm), kNoise);
    EXPECT_EQ(loud.shape, c.shape) << c.nu << " " << c.cloud << ": " << to_string(loud.shape)
                                   << ", phase dispersion " << loud.phase_dispersion;
    EXPECT_EQ(loud.period, c.period);
    EXPECT_GT(loud.spread_m, 10 * kNoise);
  }
}

TEST(OrbitClass, DeformedEllipseIsARing) {
  // 000 sec. 5.2's "deformed ellipse": a quasi-periodic orbit with a 30 % second harmonic,
  // x_n = A [cos(phi_n) + 0.3 cos(2 phi_n + 1)], phi_n = 2 pi nu n. Sorted by phase it is a
  // smooth curve: with 2.5 % noise its phase dispersion measured 0.056-0.063 over 106 maps,
  // against the 0.2 limit.
  const double a = 2e-5;
  const double nu = 0.6180339887498949;
  Eigen::VectorXd x(400);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double phi = kTwoPi * nu * static_cast<double>(i);
    x[i] = a * (std::cos(phi) + 0.3 * std::cos(2 * phi + 1));
  }
  const Eigen::VectorXd depth = Eigen::VectorXd::Constant(x.size(), 2 * kMm);
  for (const Eigen::Index centre : {50, 170, 333}) {
    const OrbitClass c = classify_orbit(poincare_map_at_revolution(depth, x, centre), kNoise);
    EXPECT_EQ(c.shape, OrbitShape::kRing) << centre << ": " << c.phase_dispersion;
    EXPECT_LT(c.phase_dispersion, 0.1);
  }
}

TEST(OrbitClass, FourClustersWithTwoOnTheTrendArePeriodFour) {
  // (A, 0, -A, 0): x_n - x_(n-2) = (2A, 0, -2A, 0) is zero half the time, which a median-based
  // scale would take for period two; the upper quartile does not.
  Eigen::VectorXd x(100);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    x[i] = 2e-5 * std::cos(0.5 * kPi * static_cast<double>(i));
  }
  const Eigen::VectorXd depth = Eigen::VectorXd::Constant(x.size(), 2 * kMm);
  const OrbitClass c = classify_orbit(poincare_map_at_revolution(depth, x, 50), kNoise);
  EXPECT_EQ(c.shape, OrbitShape::kClusters);
  EXPECT_EQ(c.period, 4);
}

TEST(PoincareMap, BadInputIsNamed) {
  const Eigen::VectorXd depth = Eigen::VectorXd::LinSpaced(100, 0.0, 1e-3);
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(100);
  EXPECT_THROW(
      {
        try {
          poincare_map(depth, x, 2e-3);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "poincare: depth 2 mm: outside the run's depths [0, 1] mm");
          throw;
        }
      },
      InputError);
  EXPECT_THROW(
      {
        try {
          poincare_map(depth.head(20), x.head(20), 0.0);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(),
                       "poincare: run has 20 revolutions: a map of revolutions = 20 needs 21");
          throw;
        }
      },
      InputError);
  EXPECT_THROW(poincare_map(depth, x.head(99), 0.0), InputError);
  EXPECT_THROW(poincare_map_at_revolution(depth, x, 100), InputError);
  PoincareMapOptions one;
  one.revolutions = 1;
  EXPECT_THROW(poincare_map(depth, x, 0.0, one), InputError);
  const PoincareMap m = poincare_map(depth, x, 0.0);
  EXPECT_THROW(
      {
        try {
          classify_orbit(m, 0.0);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "orbit class: noise_floor_m = 0: must be > 0");
          throw;
        }
      },
      InputError);
}

}  // namespace
}  // namespace dynamics
}  // namespace chatterlab
