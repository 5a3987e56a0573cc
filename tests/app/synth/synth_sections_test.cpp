// synth's spec sections belong to the test kinds (TestKind::synth_section, app/synth/synth.h):
// each registered kind's section is read by it, a spec error names the file and key and stops
// synth before anything is written, an unknown key is a warning naming the key, and truth.yaml's
// campaign-wide `modal` follows the rule of docs/format/synth-spec.md (the cut's in-cut values
// replace the first x mode of the tap tests).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <set>
#include <string>

#include "analysis/common/summary.h"
#include "app/pipeline/registry.h"
#include "app/synth/synth.h"
#include "tests/support/synth_spec.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::SynthSpecText;
using chatterlab::testing::TempDir;

const char* kOneCut =
    "    - {name: c, axial_depth_mm: 0.5, duration_s: 0.01, offset_angle_deg: 10}\n";

// The message of the InputError synth throws for `spec` ("" when it throws none).
std::string synth_error(const TempDir& d, const std::string& spec) {
  try {
    synthesize_campaign(d.write("spec.yaml", spec), d.path() / "out");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(SynthSections, EveryRegisteredSectionIsReadByItsKind) {
  std::set<std::string> sections;
  for (const auto& k : builtin_kinds().kinds()) {
    if (!k->synth_section().empty()) sections.insert(k->synth_section());
  }
  EXPECT_EQ(sections, (std::set<std::string>{"tap", "dyno", "cut", "grinding", "sifs", "spindle",
                                             "era", "forcerec"}));
  TempDir d;
  SynthSpecText t;
  t.cut_tests = kOneCut;
  const SynthSummary s = synthesize_campaign(d.write("spec.yaml", t.text()), d.path() / "out");
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  EXPECT_EQ(s.tests_written, 2 + 3 + 1);  // tap x, y; three feeds; one cut
  for (const char* test : {"tap/x", "tap/y", "dyno/f050", "dyno/f100", "dyno/f150", "cuts/c"}) {
    EXPECT_TRUE(std::filesystem::exists(d.path() / "out" / test / "test.yaml")) << test;
  }
}

TEST(SynthSections, CampaignModalIsTheCutsElseTheFirstTapMode) {
  TempDir d;
  SynthSpecText t;
  synthesize_campaign(d.write("a.yaml", t.text()), d.path() / "tap-only");
  const YAML::Node tap_only = YAML::LoadFile((d.path() / "tap-only" / "truth.yaml").string());
  EXPECT_DOUBLE_EQ(tap_only["modal"]["k_N_m"].as<double>(), 1.023e6);  // tap x, first mode
  EXPECT_FALSE(tap_only["coefficients"]);

  t.cut_tests = kOneCut;
  synthesize_campaign(d.write("b.yaml", t.text()), d.path() / "with-cut");
  const YAML::Node with_cut = YAML::LoadFile((d.path() / "with-cut" / "truth.yaml").string());
  EXPECT_DOUBLE_EQ(with_cut["modal"]["k_N_m"].as<double>(), 9.84e5);  // the cut section's
  EXPECT_DOUBLE_EQ(with_cut["coefficients"]["Kt2_N_m2"].as<double>(), 6.641e9);
  // The tap tests' own modes stay under their entries.
  EXPECT_DOUBLE_EQ(with_cut["tests"]["tap/x"]["modes"][0]["k_N_m"].as<double>(), 1.023e6);
  EXPECT_DOUBLE_EQ(with_cut["tests"]["cuts/c"]["offset_angle_deg"].as<double>(), 10.0);
}

TEST(SynthSections, ErrorsNameTheKeyAndWriteNothing) {
  SynthSpecText t;
  t.cut_tests = kOneCut;
  const std::string good = t.text();
  struct Case {
    std::string spec, key;
  };
  const Case cases[] = {
      {replaced(good, "tool: {teeth: 2, radius_mm: 6.35}\n", ""), "spec.yaml: key 'tool'"},
      {replaced(good, "teeth: 2", "teeth: 2.5"), "tool.teeth"},
      {replaced(good, "radius_mm: 6.35", "radius_mm: -1"), "tool.radius_mm"},
      // Three teeth, coefficients for two.
      {replaced(good, "teeth: 2", "teeth: 3"), "cut.coefficients"},
      // 100 kHz at 14,000 rpm: 428.57 samples per revolution.
      {replaced(good, "spindle_rpm: 15000", "spindle_rpm: 14000"), "cut.sample_rate_hz"},
      {replaced(good, "feeds_mm: [0.05, 0.10, 0.15]", "feeds_mm: [0.05]"), "dyno.feeds_mm"},
      {replaced(good, "hits: 3", "hits: 0"), "tap.hits"},
  };
  for (const auto& c : cases) {
    TempDir d;
    const std::string e = synth_error(d, c.spec);
    EXPECT_NE(e.find(c.key), std::string::npos) << c.key << ": " << e;
    EXPECT_FALSE(std::filesystem::exists(d.path() / "out")) << c.key;
  }
  // A missing tool is reported once per section that needs it.
  TempDir d;
  const std::string e = synth_error(d, cases[0].spec);
  EXPECT_NE(e.find("`dyno` section"), std::string::npos) << e;
  EXPECT_NE(e.find("`cut` section"), std::string::npos) << e;
}

TEST(SynthSections, UnknownKeysAreWarningsNamingTheKey) {
  TempDir d;
  SynthSpecText t;
  const std::string spec = replaced(replaced(t.text(), "hits: 3", "hits: 3\n  noise_percent: 2"),
                                    "seed: 1\n", "seed: 1\ncuts: {}\n");
  const SynthSummary s = synthesize_campaign(d.write("spec.yaml", spec), d.path() / "out");
  ASSERT_EQ(s.warnings.size(), 2u);
  const auto has = [&](const std::string& key) {
    return std::any_of(s.warnings.begin(), s.warnings.end(),
                       [&](const std::string& w) { return w.find(key) != std::string::npos; });
  };
  EXPECT_TRUE(has("spec.yaml: key 'tap.noise_percent'")) << s.warnings[0] << "\n" << s.warnings[1];
  EXPECT_TRUE(has("spec.yaml: key 'cuts'")) << s.warnings[0] << "\n" << s.warnings[1];
  EXPECT_EQ(s.tests_written, 5);  // the spec's other parts are written
}

}  // namespace
}  // namespace chatterlab::app
