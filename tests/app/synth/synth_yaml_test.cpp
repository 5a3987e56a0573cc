// synth writes its YAML with yaml-cpp's emitter: text that YAML gives a meaning to (": ", "#",
// quotes, several lines) comes back from the campaign loader as it was written in the spec, and
// truth.yaml holds the numbers used.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <sstream>
#include <string>

#include "app/cli/validate.h"
#include "app/core/campaign.h"
#include "app/synth/synth.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::TempDir;

// Strings that plain concatenation wrote into campaign.yaml unquoted, where ": " starts a
// mapping and " #" a comment: the campaign then failed to load (`validate` rejected it).
const char* kWorkpiece = "Al 6061-T6511: 30-deg Uncoated A";
const char* kMachine = "Haas VF-2 #3 'spindle B'";

std::string spec() {
  return std::string(
             "format: chatterlab-synth/1\n"
             "name: yaml-emitter\n"
             "description: |\n"
             "  First line: with a colon.\n"
             "  Second line # not a comment.\n"
             "seed: 3\n"
             "tool: {teeth: 2, radius_mm: 6.35}\n"
             "workpiece: '") +
         kWorkpiece + "'\nmachine: \"" + kMachine +
         "\"\n"
         "tap:\n"
         "  sample_rate_hz: 25600\n"
         "  hits: 2\n"
         "  hit_spacing_s: 0.5\n"
         "  axes:\n"
         "    x: {modes: [{m_kg: 0.03211, c_kg_s: 13.39, k_N_m: 1.023e6}]}\n";
}

TEST(SynthYaml, TextWithYamlSyntaxLoadsAsWritten) {
  TempDir d;
  const auto spec_file = d.write("spec.yaml", spec());
  synthesize_campaign(spec_file, d.path() / "c");
  CampaignSpec c = load_campaign(d.path() / "c");
  ASSERT_TRUE(c.errors.empty()) << c.errors.front();
  EXPECT_EQ(c.name, "yaml-emitter");
  EXPECT_EQ(c.workpiece, kWorkpiece);
  EXPECT_EQ(c.machine, kMachine);
  EXPECT_EQ(c.description, "First line: with a colon.\nSecond line # not a comment.\n");
  ASSERT_TRUE(c.tool.has_value());
  EXPECT_EQ(c.tool->teeth, 2);
  EXPECT_DOUBLE_EQ(c.tool->radius_m, 6.35e-3);
  ASSERT_EQ(c.tests.size(), 1u);
  EXPECT_TRUE(c.tests[0].usable()) << c.tests[0].errors.front();
  // `chatterlab validate` accepts the campaign (exit code 0).
  std::ostringstream out;
  EXPECT_EQ(validate_campaign(c, out), 0) << out.str();
}

TEST(SynthYaml, TruthHoldsTheNumbersUsed) {
  TempDir d;
  synthesize_campaign(d.write("spec.yaml", spec()), d.path() / "c");
  const YAML::Node truth = YAML::LoadFile((d.path() / "c" / "truth.yaml").string());
  // The tap modes at 10 significant digits (docs/synth.md); m, c, k as given, and
  // fn = sqrt(k / m) / (2 pi) = 898.3339144 Hz.
  const YAML::Node mode = truth["tests"]["tap/x"]["modes"][0];
  EXPECT_EQ(mode["m_kg"].as<double>(), 0.03211);
  EXPECT_EQ(mode["c_kg_s"].as<double>(), 13.39);
  EXPECT_EQ(mode["k_N_m"].as<double>(), 1.023e6);
  EXPECT_EQ(mode["fn_hz"].as<double>(), 898.3339144);
  EXPECT_EQ(truth["modal"]["k_N_m"].as<double>(), 1.023e6);  // no cut tests: the tap's mode
}

}  // namespace
}  // namespace chatterlab::app
