// The stability-lobe spec of EXPERIMENT_FORMAT.md "Stability lobe specs" (docs/format/lobes.md).
#include "app/lobes/lobes_spec.h"

#include <gtest/gtest.h>

#include "analysis/common/summary.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::TempDir;

// The format's example, as written there.
const char* kSpec =
    "format: chatterlab-lobes/1\n"
    "tool: {teeth: 2, radius_mm: 6.35}\n"
    "modal: {m_kg: 0.03134, c_kg_s: 22.21, k_N_m: 9.84e5}\n"
    "coefficients: {Kt_N_m2: [2.483e8, 6.641e9], Kr_N_m2: [2.196e8, 4.154e9]}\n"
    "cut: {operation: up-milling, radial_immersion_mm: 0.382}\n"
    "spindle_rpm: [10000, 26000]\n"
    "speeds: 200\n"
    "max_depth_mm: 10\n"
    "methods: [semi-discretization, zoa]\n";

std::string with(std::string spec, const std::string& from, const std::string& to) {
  spec.replace(spec.find(from), from.size(), to);
  return spec;
}

std::string error_of(const std::string& text) {
  TempDir d;
  try {
    load_lobes_spec(d.write("spec.yaml", text));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(LobesSpec, ReadsTheFormatExample) {
  TempDir d;
  const LobesSpec s = load_lobes_spec(d.write("spec.yaml", kSpec));
  const lobes::LobesInput& in = s.input;
  EXPECT_EQ(in.teeth, 2);
  EXPECT_DOUBLE_EQ(in.radius_m, 6.35e-3);
  ASSERT_EQ(in.x_modes.size(), 1u);  // `modal` applies to both axes
  ASSERT_EQ(in.y_modes.size(), 1u);
  EXPECT_DOUBLE_EQ(in.y_modes[0].c_kg_s, 22.21);
  EXPECT_DOUBLE_EQ(in.Kt_N_m2[1], 6.641e9);
  EXPECT_DOUBLE_EQ(in.Kr_N_m2[0], 2.196e8);
  EXPECT_EQ(in.operation, milling::Operation::kUpMilling);
  EXPECT_DOUBLE_EQ(in.radial_immersion_m, 0.382e-3);
  ASSERT_EQ(in.spindle_rpm.size(), 200u);  // ends included
  EXPECT_DOUBLE_EQ(in.spindle_rpm.front(), 10000.0);
  EXPECT_DOUBLE_EQ(in.spindle_rpm.back(), 26000.0);
  EXPECT_NEAR(in.spindle_rpm[1] - in.spindle_rpm[0], 16000.0 / 199, 1e-9);
  EXPECT_DOUBLE_EQ(in.max_depth_m, 10e-3);
  EXPECT_TRUE(s.semi_discretization);
  EXPECT_TRUE(s.zoa);
  EXPECT_EQ(s.steps_per_tooth, 0);  // automatic
  EXPECT_TRUE(s.warnings.empty());
}

TEST(LobesSpec, ModesPerAxisRigidAxisAndDefaults) {
  const std::string spec =
      "format: chatterlab-lobes/1\n"
      "tool: {teeth: 4, radius_mm: 10}\n"
      "modal:\n"
      "  x: {modes: [{m_kg: 0.04, c_kg_s: 5, k_N_m: 1.3e6}, {m_kg: 0.1, c_kg_s: 40, k_N_m: 3e7}]}\n"
      "  y: {modes: []}\n"
      "coefficients: {Kt_N_m2: 6e8, Kr_N_m2: 2e8}\n"
      "cut: {operation: down-milling, radial_immersion_mm: 1}\n"
      "spindle_rpm: 12000\n";
  TempDir d;
  const LobesSpec s = load_lobes_spec(d.write("spec.yaml", spec));
  EXPECT_EQ(s.input.x_modes.size(), 2u);
  EXPECT_TRUE(s.input.y_modes.empty());                     // rigid
  EXPECT_EQ(s.input.Kt_N_m2, std::vector<double>(4, 6e8));  // one number: every tooth
  EXPECT_EQ(s.input.operation, milling::Operation::kDownMilling);
  EXPECT_EQ(s.input.spindle_rpm, std::vector<double>{12000.0});  // one speed
  EXPECT_DOUBLE_EQ(s.input.max_depth_m, 10e-3);                  // default
  // An axis written as one mode (as a simulation spec does): beyond the contract.
  const LobesSpec one = load_lobes_spec(
      d.write("one.yaml", with(spec, "y: {modes: []}", "y: {m_kg: 0.05, c_kg_s: 6, k_N_m: 2e6}")));
  ASSERT_EQ(one.input.y_modes.size(), 1u);
  EXPECT_DOUBLE_EQ(one.input.y_modes[0].k_N_m, 2e6);
  // An absent axis is rigid, as an empty list (docs/format/lobes.md).
  const LobesSpec absent =
      load_lobes_spec(d.write("absent.yaml", with(spec, "  y: {modes: []}\n", "")));
  EXPECT_EQ(absent.input.x_modes.size(), 2u);
  EXPECT_TRUE(absent.input.y_modes.empty());
  const LobesSpec only = load_lobes_spec(d.write(
      "only.yaml", with(spec, "spindle_rpm: 12000\n", "spindle_rpm: 12000\nmethods: [zoa]\n")));
  EXPECT_FALSE(only.semi_discretization);
  EXPECT_TRUE(only.zoa);
}

TEST(LobesSpec, ErrorsNameFileAndKey) {
  EXPECT_NE(error_of(with(kSpec, "chatterlab-lobes/1", "chatterlab-lobes/2"))
                .find("spec.yaml: key 'format' 'chatterlab-lobes/2': must be 'chatterlab-lobes/1'"),
            std::string::npos)
      << error_of(with(kSpec, "chatterlab-lobes/1", "chatterlab-lobes/2"));
  EXPECT_NE(error_of(with(kSpec, "[10000, 26000]", "[26000, 10000]"))
                .find("key 'spindle_rpm' must be [low, high] with low < high"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSpec, "speeds: 200", "speeds: 1e9")).find("key 'speeds'"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSpec, "methods: [semi-discretization, zoa]", "methods: [fdm]"))
                .find("key 'methods' 'fdm': must be semi-discretization or zoa"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSpec, "radial_immersion_mm: 0.382", "radial_immersion_mm: 13"))
                .find("key 'cut.radial_immersion_mm' must not exceed the tool diameter"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSpec, "[2.483e8, 6.641e9]", "[1e8, 2e8, 3e8]"))
                .find("key 'coefficients.Kt_N_m2' has 3 values: give one number or one per tooth "
                      "(2)"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSpec, "speeds: 200", "speeds: 1"))
                .find("key 'speeds' must be at least 2 for a range of spindle_rpm"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSpec, "max_depth_mm: 10", "max_depth_mm: 1e9"))
                .find("key 'max_depth_mm' must be > 0 and at most 1000 mm"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSpec, "max_depth_mm: 10",
                          "max_depth_mm: 10\nsteps_per_tooth: 2000\n"
                          "tool_note: x"))
                .find("no error"),
            std::string::npos);  // 2 modes: 4,004 <= 8,192
  EXPECT_NE(error_of(with(kSpec, "modal: {m_kg: 0.03134, c_kg_s: 22.21, k_N_m: 9.84e5}",
                          "modal: {x: {modes: [{m_kg: 1, c_kg_s: 1, k_N_m: 1}, {m_kg: 1, c_kg_s: "
                          "1, k_N_m: 1}, {m_kg: 1, c_kg_s: 1, k_N_m: 1}]}, y: {modes: [{m_kg: 1, "
                          "c_kg_s: 1, k_N_m: 1}, {m_kg: 1, c_kg_s: 1, k_N_m: 1}]}}") +
                     "steps_per_tooth: 2000\n")
                .find("key 'steps_per_tooth' 2000 intervals with 5 modes"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSpec, "max_depth_mm: 10", "max_depth_mm: -1"))
                .find("key 'max_depth_mm' must be > 0"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSpec, "teeth: 2", "teeth: 1e300")).find("key 'tool.teeth'"),
            std::string::npos);
  std::string modes;
  for (int i = 0; i < 9; ++i)
    modes += std::string(i ? ", " : "") + "{m_kg: 1, c_kg_s: 1, k_N_m: 1}";
  EXPECT_NE(error_of(with(kSpec, "modal: {m_kg: 0.03134, c_kg_s: 22.21, k_N_m: 9.84e5}",
                          "modal: {x: {modes: [" + modes + "]}}"))
                .find("key 'modal.x.modes' has 9 modes: at most 8"),
            std::string::npos);
  EXPECT_NE(error_of(with(kSpec, "modal: {m_kg: 0.03134, c_kg_s: 22.21, k_N_m: 9.84e5}",
                          "modal: {x: {modes: []}, y: {modes: []}}"))
                .find("key 'modal' has no mode on either axis"),
            std::string::npos);
}

TEST(LobesSpec, UnknownKeysAreWarningsWithASuggestion) {
  TempDir d;
  const LobesSpec s =
      load_lobes_spec(d.write("spec.yaml", with(kSpec, "max_depth_mm: 10", "max_dept_mm: 10")));
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("max_dept_mm"), std::string::npos) << s.warnings[0];
  EXPECT_NE(s.warnings[0].find("max_depth_mm"), std::string::npos) << s.warnings[0];
  EXPECT_DOUBLE_EQ(s.input.max_depth_m, 10e-3);  // the default, as the key was not read
}

}  // namespace
}  // namespace chatterlab::app
