#include "app/simulate/simulation_spec.h"

#include <gtest/gtest.h>

#include "analysis/common/summary.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::TempDir;

const char* kSpec =
    "format: chatterlab-simulation/1\n"
    "tool: {teeth: 2, radius_mm: 6.35}\n"
    "modal: {m_kg: 0.03134, c_kg_s: 22.21, k_N_m: 9.84e5}\n"
    "coefficients: {Kt_N_m2: [2.483e8, 6.641e9], Kr_N_m2: 3.0e8}\n"
    "cut:\n"
    "  operation: up-milling\n"
    "  spindle_rpm: 15000\n"
    "  feed_per_tooth_mm: 0.0635\n"
    "  radial_immersion_mm: 0.382\n"
    "  axial_depth_mm: [0.0, 6.0]\n"
    "  revolutions_per_mm: 1290\n"
    "poincare_depths_mm: [1.0, 3.0]\n";

std::string error_of(const std::string& text) {
  TempDir d;
  try {
    load_simulation_spec(d.write("spec.yaml", text));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SimulationSpec, ReadsTheFormatExample) {
  TempDir d;
  const SimulationSpec s = load_simulation_spec(d.write("spec.yaml", kSpec));
  EXPECT_EQ(s.teeth, 2);
  EXPECT_DOUBLE_EQ(s.radius_m, 6.35e-3);
  EXPECT_DOUBLE_EQ(s.x.k_N_m, 9.84e5);
  EXPECT_DOUBLE_EQ(s.y.c_kg_s, 22.21);  // `modal` applies to both axes
  ASSERT_EQ(s.Kt_N_m2.size(), 2u);
  EXPECT_DOUBLE_EQ(s.Kt_N_m2[1], 6.641e9);
  ASSERT_EQ(s.Kr_N_m2.size(), 2u);  // one number fills every tooth
  EXPECT_DOUBLE_EQ(s.Kr_N_m2[0], 3.0e8);
  EXPECT_DOUBLE_EQ(s.depth_end_m, 6e-3);
  EXPECT_DOUBLE_EQ(*s.revolutions_per_mm, 1290.0);
  EXPECT_EQ(s.chip_model, "traditional");  // default
  EXPECT_EQ(s.steps_per_tooth, 800);       // default, 000 sec. 5.2
  EXPECT_EQ(s.poincare_depths_m.size(), 2u);
}

TEST(SimulationSpec, SeparateAxesAndConstantDepth) {
  std::string spec = kSpec;
  spec.replace(
      spec.find("modal: {m_kg: 0.03134, c_kg_s: 22.21, k_N_m: 9.84e5}"), 52,
      "modal: {x: {m_kg: 0.03, c_kg_s: 20, k_N_m: 1e6}, y: {m_kg: 0.04, c_kg_s: 25, k_N_m: 2e6}}");
  spec.replace(spec.find("axial_depth_mm: [0.0, 6.0]"), 26, "axial_depth_mm: 2.0");
  spec.replace(spec.find("revolutions_per_mm: 1290"), 24, "revolutions: 400");
  TempDir d;
  const SimulationSpec s = load_simulation_spec(d.write("spec.yaml", spec));
  EXPECT_DOUBLE_EQ(s.x.m_kg, 0.03);
  EXPECT_DOUBLE_EQ(s.y.k_N_m, 2e6);
  EXPECT_DOUBLE_EQ(s.depth_start_m, 2e-3);
  EXPECT_DOUBLE_EQ(s.depth_end_m, 2e-3);
  EXPECT_EQ(*s.revolutions, 400);
}

TEST(SimulationSpec, ErrorsNameFileAndKey) {
  std::string spec = kSpec;
  spec.replace(spec.find("revolutions_per_mm: 1290"), 24, "revs_per_mm: 1290");
  EXPECT_NE(error_of(spec).find("spec.yaml: key 'cut.revolutions_per_mm' is required when "
                                "axial_depth_mm changes"),
            std::string::npos);
  std::string three = kSpec;
  three.replace(three.find("[2.483e8, 6.641e9]"), 18, "[1e8, 2e8, 3e8]");
  EXPECT_NE(error_of(three).find("key 'coefficients.Kt_N_m2' has 3 values: give one number or one "
                                 "per tooth (2)"),
            std::string::npos);
  std::string chip = std::string(kSpec) + "chip_model: spline\n";
  EXPECT_NE(error_of(chip).find("key 'chip_model' must be traditional or numerical, got 'spline'"),
            std::string::npos);
  EXPECT_NE(error_of("format: chatterlab-simulation/2\n").find("must be 'chatterlab-simulation/1'"),
            std::string::npos);
  EXPECT_NE(error_of("format: chatterlab-simulation/1\n").find("key 'tool' must be"),
            std::string::npos);
}

// Keys nobody reads are warnings naming the file and key (the spec still loads);
// detector_noise_m is a key of the spec.
TEST(SimulationSpec, UnknownKeysAreWarningsAndDetectorNoiseIsRead) {
  TempDir d;
  const SimulationSpec s = load_simulation_spec(d.write(
      "spec.yaml", std::string(kSpec) + "detector_noise_m: 1.0e-6\nchip_modle: numerical\n"));
  EXPECT_DOUBLE_EQ(s.detector_noise_m, 1e-6);
  EXPECT_EQ(s.chip_model, "traditional");  // the misspelt key is not read
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0],
            "spec.yaml: key 'chip_modle' is not part of the format and is ignored (did you mean "
            "'chip_model'?)");
}

}  // namespace
}  // namespace chatterlab::app
