#include <gtest/gtest.h>

#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/dynamics/orbit_synth.h"

namespace chatterlab {
namespace dynamics {
namespace {

TEST(OrbitSynth, BuildsTheStatedTruth) {
  OrbitSpec spec;
  spec.revolutions = 1001;
  spec.start_depth_m = 1e-3;
  spec.end_depth_m = 2e-3;
  spec.offset_m = 2e-5;
  spec.drift_m_per_m = 1e-3;
  ChatterEpisodeSpec e;
  e.low_depth_m = 1.5e-3;
  e.high_depth_m = 1.8e-3;
  e.amplitude_m = 1e-5;
  e.ramp_depth_m = 0.1e-3;
  e.rotation_number = 0.5;
  spec.chatter.push_back(e);
  const SyntheticOrbit o = synthesize_orbit(spec);
  ASSERT_EQ(o.x_m.size(), 1001);
  // Depth: linear, 1 um per revolution here; exact to rounding.
  EXPECT_NEAR(o.depth_m[0], 1e-3, 1e-15);
  EXPECT_NEAR(o.depth_m[500], 1.5e-3, 1e-15);
  EXPECT_NEAR(o.depth_m[1000], 2e-3, 1e-15);
  // Envelope: 0 outside [1.5, 1.8] mm, half at 0.05 mm inside, full in the middle.
  EXPECT_EQ(o.amplitude_m[499], 0.0);
  EXPECT_NEAR(o.amplitude_m[550], 0.5e-5, 1e-12);
  EXPECT_NEAR(o.amplitude_m[650], 1e-5, 1e-12);
  EXPECT_NEAR(o.amplitude_m[750], 0.5e-5, 1e-12);
  EXPECT_EQ(o.amplitude_m[801], 0.0);
  // x = offset + drift b + A cos(pi n): exact without noise.
  for (Eigen::Index i : {0, 550, 650, 651, 1000}) {
    const double expected =
        2e-5 + 1e-3 * o.depth_m[i] + o.amplitude_m[i] * std::cos(kPi * static_cast<double>(i));
    EXPECT_NEAR(o.x_m[i], expected, 1e-15) << i;
  }
}

TEST(OrbitSynth, NoiseHasTheStatedStdAndIsSeeded) {
  OrbitSpec spec;
  spec.revolutions = 20000;
  spec.noise_sigma_m = 5e-7;
  spec.seed = 42;
  const SyntheticOrbit a = synthesize_orbit(spec);
  // Std of a 20,000-sample std: 0.5 %; tolerance 2 %.
  EXPECT_NEAR(std::sqrt(a.x_m.squaredNorm() / 20000) / 5e-7, 1.0, 0.02);
  EXPECT_EQ(a.x_m, synthesize_orbit(spec).x_m);
  spec.seed = 43;
  EXPECT_NE(a.x_m, synthesize_orbit(spec).x_m);
}

TEST(OrbitSynth, BadSpecIsNamed) {
  OrbitSpec spec;
  spec.revolutions = 1;
  EXPECT_THROW(
      {
        try {
          synthesize_orbit(spec);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "orbit.revolutions = 1: must be >= 2");
          throw;
        }
      },
      InputError);
  spec.revolutions = 10;
  ChatterEpisodeSpec e;
  e.low_depth_m = 2e-3;
  e.high_depth_m = 1e-3;
  spec.chatter.push_back(e);
  EXPECT_THROW(
      {
        try {
          synthesize_orbit(spec);
        } catch (const InputError& ex) {
          EXPECT_STREQ(ex.what(),
                       "orbit.chatter[0]: needs high_depth_m >= low_depth_m, amplitude_m >= 0 "
                       "and ramp_depth_m >= 0");
          throw;
        }
      },
      InputError);
}

}  // namespace
}  // namespace dynamics
}  // namespace chatterlab
