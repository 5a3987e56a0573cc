#include "analysis/milling/simulation_options.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "analysis/common/summary.h"
#include "analysis/milling/force_model.h"

namespace chatterlab {
namespace milling {
namespace {

SimulationOptions valid() {
  SimulationOptions o;
  o.modal_x = {0.03134, 22.21, 9.840e5};
  o.coefficients = {cutting_coefficients(0.2483e9, 0.2196e9),
                    cutting_coefficients(6.641e9, 4.154e9)};
  return o;
}

std::string error_of(const std::function<void(SimulationOptions&)>& change) {
  SimulationOptions o = valid();
  change(o);
  try {
    validate(o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "valid";
}

TEST(SimulationOptions, DefaultsAreThe000Section52Incline) {
  const SimulationGrid g = simulation_grid(valid());
  EXPECT_EQ(g.steps_per_revolution, 1600);
  EXPECT_DOUBLE_EQ(g.time_step_s, 2.5e-6);  // 000 sec. 5.2
  EXPECT_EQ(g.revolutions, 7740);
  EXPECT_EQ(g.steps, 12384000);
  EXPECT_DOUBLE_EQ(g.depth_at_step(0), 0.0);
  EXPECT_NEAR(g.depth_at_step(1290 * 1600), 1e-3, 1e-15);
  EXPECT_NEAR(g.depth_at_step(g.steps), 6e-3, 1e-15);
  EXPECT_EQ(g.depth_at_step(g.steps + 5000), 6e-3);  // clamped at the end of the ramp
}

TEST(SimulationOptions, DeclineAndConstantDepth) {
  SimulationOptions o = valid();
  o.depth = DepthProfile::ramp(6e-3, 2e-3, 1290.0);  // 000 table 5.1 decline (6 to 2 mm)
  SimulationGrid g = simulation_grid(o);
  EXPECT_EQ(g.revolutions, 5160);
  EXPECT_NEAR(g.depth_at_step(1290 * 1600), 5e-3, 1e-15);
  EXPECT_EQ(revolution_at_depth(o, 5e-3), 1290);
  EXPECT_EQ(revolution_at_depth(o, 9e-3), 0);  // clamped
  o.depth = DepthProfile::constant(2e-3, 30);
  g = simulation_grid(o);
  EXPECT_EQ(g.revolutions, 30);
  EXPECT_EQ(g.depth_at_step(12345), 2e-3);
  EXPECT_EQ(revolution_at_depth(o, 1e-3), 29);
  EXPECT_EQ(revolution_at_depth(valid(), 1e-3), 1290);
  EXPECT_EQ(revolution_at_depth(valid(), 1.0001e-3), 1290);
}

TEST(SimulationOptions, ValidationNamesFieldValueAndRule) {
  EXPECT_EQ(error_of([](SimulationOptions&) {}), "valid");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.teeth = 0; }),
            "simulation.teeth = 0: must be in [1, 32]");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.radius_m = -1; }),
            "simulation.radius_m = -1: must be finite and > 0");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.modal_x.m_kg = 0; }),
            "simulation.modal_x.m_kg = 0: must be finite and > 0");
  EXPECT_EQ(error_of([](SimulationOptions& o) {
              o.modal_y = AxisModal{0.03, -1.0, 1e6};
            }),
            "simulation.modal_y.c_kg_s = -1: must be finite and >= 0");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.modal_x = AxisModal{}; }),
            "simulation.modal_x.m_kg = nan: must be finite and > 0");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.coefficients.resize(3, o.coefficients[0]); }),
            "simulation.coefficients.size() = 3: must equal teeth = 2 (one entry per tooth)");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.coefficients[1].Kte_N_m = NAN; }),
            "simulation.coefficients[1].Kte_N_m = nan: must be finite and >= 0 (0 for no edge "
            "force)");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.coefficients[0].Kr_N_m2 = -2; }),
            "simulation.coefficients[0].Kr_N_m2 = -2: must be finite and >= 0");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.spindle_rpm = 0; }),
            "simulation.spindle_rpm = 0: must be finite and > 0");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.feed_per_tooth_m = -1e-5; }),
            "simulation.feed_per_tooth_m = -1e-05: must be finite and >= 0");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.radial_immersion_m = 0.02; }),
            "simulation.radial_immersion_m = 0.02: must satisfy 0 < r_i <= 2 radius_m = 0.012700");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.depth.end_m = 0.0; }),
            "simulation.depth.end_m = 0: must differ from depth.start_m for a ramp (use "
            "DepthProfile::constant)");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.depth.revolutions_per_mm = 0; }),
            "simulation.depth.revolutions_per_mm = 0: must be finite and > 0");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.depth = DepthProfile::constant(1e-3, 0); }),
            "simulation.depth.revolutions = 0: must be >= 1");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.depth = DepthProfile::constant(-1e-3, 5); }),
            "simulation.depth.start_m = -0.001: must be finite and >= 0");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.steps_per_tooth = 4; }),
            "simulation.steps_per_tooth = 4: must be >= 8");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.steps_per_tooth = 200000; }),
            "simulation.steps_per_tooth = 200000: gives more than 2^31 steps for the run "
            "(revolutions * teeth * steps_per_tooth)");
  EXPECT_EQ(error_of([](SimulationOptions& o) {
              o.switching = SwitchingRule::kAngleOnly;
              o.chip_model = ChipModel::kNumerical;
            }),
            "simulation.switching = angle-only: angle-only switching applies to the traditional "
            "chip model only (the numerical model cuts exactly when it finds a positive chip)");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.inertial.eccentricity_m = -1e-5; }),
            "simulation.inertial.eccentricity_m = -1e-05: must be finite and >= 0");
  EXPECT_EQ(error_of([](SimulationOptions& o) {
              o.inertial.enabled = true;
              o.modal_y = AxisModal{0.05, 22.21, 9.84e5};
            }),
            "simulation.modal_y.m_kg = 0.05: must equal modal_x.m_kg when inertial forces are "
            "enabled (000 eq. 7.1: m = m_x = m_y)");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.sample_angle_rad = INFINITY; }),
            "simulation.sample_angle_rad = inf: must be finite");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.numerical.sharp_change_fraction_of_feed = 0; }),
            "simulation.numerical.sharp_change_fraction_of_feed = 0: must be finite and > 0");
  EXPECT_EQ(error_of([](SimulationOptions& o) { o.numerical.long_window_revolutions = 0.5; }),
            "simulation.numerical.long_window_revolutions = 0.5: must be in [1, 10]");
}

// Edge terms default to 0 through the helper; the added force-model functions by hand.
TEST(SimulationOptions, CuttingCoefficientsHelperAndSignedToothForce) {
  const CuttingCoefficients k = cutting_coefficients(6e8, 2e8);
  EXPECT_EQ(k.Kte_N_m, 0.0);
  EXPECT_EQ(k.Kre_N_m, 0.0);
  // tooth_force_signed: F = K b w + K_e b for any w. b = 2 mm, w = -0.05 mm, Kte = 1e4,
  // Kre = 1.5e4: F_t = -60 + 20 = -40 N, F_r = -20 + 30 = 10 N (tooth_force gives 0 here).
  const CuttingCoefficients e{6e8, 2e8, 1e4, 1.5e4};
  const ToothForce f = tooth_force_signed(e, -5e-5, 2e-3, true);
  EXPECT_NEAR(f.tangential_N, -40.0, 1e-12);
  EXPECT_NEAR(f.radial_N, 10.0, 1e-12);
  EXPECT_EQ(tooth_force(e, -5e-5, 2e-3, true).tangential_N, 0.0);
  EXPECT_EQ(tooth_force_signed(e, -5e-5, 2e-3, false).radial_N, 0.0);
  // For positive chips it equals tooth_force.
  EXPECT_EQ(tooth_force_signed(e, 5e-5, 2e-3, true).tangential_N,
            tooth_force(e, 5e-5, 2e-3, true).tangential_N);
  // The sin/cos overload equals the angle version.
  for (double th : {0.0, 0.3, 2.0, 4.5}) {
    const Eigen::Vector2d a = tooth_force_xy_N(f, th);
    const Eigen::Vector2d b = tooth_force_xy_N(f, std::sin(th), std::cos(th));
    EXPECT_EQ(a, b);
  }
}

}  // namespace
}  // namespace milling
}  // namespace chatterlab
