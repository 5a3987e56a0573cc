// Issue 16, YAML input strictness: every YAML file is read by load_yaml_file (a size limit,
// every key a scalar name, no duplicate keys, a depth limit), numbers are finite, integers are
// whole and in a stated range, misspelt keys of a simulation spec are warnings with the closest
// known key, and a calibration under a channel name the file does not have is an error. A bad
// test.yaml makes its test unusable with a message naming the file and key, the other tests of
// the campaign are still analysed, and the input folder is not changed.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "app/core/campaign.h"
#include "app/core/hashing.h"
#include "app/core/yaml_load.h"
#include "app/core/yaml_reader.h"
#include "app/pipeline/pipeline.h"
#include "app/simulate/simulation_spec.h"
#include "app/synth/synth.h"
#include "tests/support/synth_spec.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::kCampaignYaml;
using chatterlab::testing::SynthSpecText;
using chatterlab::testing::TempDir;

bool any_contains(const std::vector<std::string>& v, const std::string& s) {
  return std::any_of(v.begin(), v.end(),
                     [&](const std::string& e) { return e.find(s) != std::string::npos; });
}

std::string all(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& e : v) s += e + "\n";
  return s;
}

const char* kTapYaml =
    "kind: tap\naxis: x\nsample_rate_hz: 1000\ndata: {file: hits.csv}\n"
    "response: acceleration\nhits: auto\n";

// The errors of test `t` of a campaign whose only test.yaml is `text`.
std::vector<std::string> test_errors(const std::string& text) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write("t/test.yaml", text);
  d.write("t/hits.csv", "force,response\n1,2\n");
  const CampaignSpec c = load_campaign(d.path());
  EXPECT_TRUE(c.errors.empty()) << all(c.errors);
  if (c.tests.size() != 1) return {"no test"};
  return c.tests[0].errors;
}

// ---- load_yaml_file / load_yaml_text -------------------------------------------------------

// The fuzzer's crash: a list as a channel name threw YAML::TypedBadConversion out of
// read_channels and ended the run. Now the file is refused with the line of the key.
TEST(YamlStrict, ListAsChannelNameRefusesTheFileWithoutThrowing) {
  std::vector<std::string> e;
  ASSERT_NO_THROW(e = test_errors("kind: tap\nchannels: {[a]: {scale: 2}}\n"));
  EXPECT_TRUE(any_contains(e, "t/test.yaml: a key under 'channels' (line 2) is a list, not a name"))
      << all(e);
}

// The same through check_keys: a mapping as a top-level key.
TEST(YamlStrict, MappingAsTopLevelKeyRefusesTheFile) {
  std::vector<std::string> e;
  ASSERT_NO_THROW(e = test_errors(std::string(kTapYaml) + "{a: 1}: 2\n"));
  EXPECT_TRUE(any_contains(e, "t/test.yaml: a key at the top level (line 7) is a mapping"))
      << all(e);
}

TEST(YamlStrict, NullAndEmptyKeysAreRefused) {
  std::vector<std::string> e;
  load_yaml_text("a: 1\n~: 2\n", "x.yaml", &e);
  EXPECT_TRUE(any_contains(e, "x.yaml: a key at the top level (line 2) is null")) << all(e);
  e.clear();
  load_yaml_text("a: {'': 2}\n", "x.yaml", &e);
  EXPECT_TRUE(any_contains(e, "x.yaml: a key under 'a' (line 1) is empty")) << all(e);
}

// YamlReader itself never throws on a tree with a non-scalar key (a tree not read through
// load_yaml_file): check_keys flags it, missing_message skips it.
TEST(YamlStrict, ReaderFlagsNonScalarKeysOfATreeItWasGiven) {
  const YAML::Node n = YAML::Load("{[a]: 1, {b: 2}: 3, scle: 4}");
  YamlReader r("x.yaml");
  ASSERT_NO_THROW(r.check_keys(n, {"scale"}, "channels.x"));
  ASSERT_NO_THROW(r.required_double(n, "scale", "channels.x"));
  EXPECT_TRUE(any_contains(r.errors(), "x.yaml: key 'channels.x' has a key that is not a name"))
      << all(r.errors());
  EXPECT_TRUE(any_contains(r.errors(), "key 'channels.x.scale' is missing (found 'scle'"))
      << all(r.errors());
}

TEST(YamlStrict, DuplicateKeyNamesKeyPathAndBothLines) {
  const auto e = test_errors(std::string(kTapYaml) + "data: {file: other.csv}\n");
  EXPECT_TRUE(any_contains(e,
                           "t/test.yaml: key 'data' appears twice in one mapping (lines 4 "
                           "and 7)"))
      << all(e);
  std::vector<std::string> n;
  load_yaml_text("a:\n  b: {c: 1, c: 2}\n", "x.yaml", &n);
  EXPECT_TRUE(any_contains(n, "x.yaml: key 'a.b.c' appears twice in one mapping (lines 2 and 2)"))
      << all(n);
}

std::string nested(int levels) {
  return "a: " + std::string(static_cast<size_t>(levels), '[') + "1" +
         std::string(static_cast<size_t>(levels), ']') + "\n";
}

TEST(YamlStrict, NestingBeyondTheLimitIsRefused) {
  std::vector<std::string> e;
  // The root mapping is level 0, the value of `a` level 1: kYamlMaxDepth lists fit.
  EXPECT_TRUE(load_yaml_text(nested(kYamlMaxDepth), "x.yaml", &e)) << all(e);
  EXPECT_TRUE(e.empty());
  EXPECT_FALSE(load_yaml_text(nested(kYamlMaxDepth + 1), "x.yaml", &e));
  EXPECT_TRUE(any_contains(e, "x.yaml: key 'a") && any_contains(e, "nests deeper than 64 levels"))
      << all(e);
  const auto t = test_errors(std::string(kTapYaml) + "extra: " + nested(200).substr(3));
  EXPECT_TRUE(any_contains(t, "t/test.yaml: key 'extra") &&
              any_contains(t, "nests deeper than 64 levels"))
      << all(t);
}

TEST(YamlStrict, FileLargerThanTheLimitIsNotRead) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  // A valid test.yaml padded with a comment to one byte over the limit.
  std::string text = std::string(kTapYaml) + "# ";
  text += std::string(static_cast<size_t>(kYamlMaxFileBytes) - text.size(), 'x') + "\n";
  ASSERT_EQ(text.size(), kYamlMaxFileBytes + 1);
  d.write("t/test.yaml", text);
  d.write("t/hits.csv", "force,response\n1,2\n");
  const CampaignSpec c = load_campaign(d.path());
  ASSERT_EQ(c.tests.size(), 1u);
  EXPECT_TRUE(any_contains(c.tests[0].errors,
                           "t/test.yaml: 1048577 bytes, more than the 1048576 "
                           "bytes (1 MiB) a YAML file may have; not read"))
      << all(c.tests[0].errors);
}

TEST(YamlStrict, FileOfExactlyTheLimitIsReadWhole) {
  // Read in 16 KiB blocks: the key after the 1 MiB of comment is still read.
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  std::string text = std::string(kTapYaml) + "# ";
  const std::string last = "\nnotes: tail\n";
  text += std::string(static_cast<size_t>(kYamlMaxFileBytes) - text.size() - last.size(), 'x');
  text += last;
  ASSERT_EQ(text.size(), kYamlMaxFileBytes);
  std::vector<std::string> errors;
  d.write("t/test.yaml", text);
  const YAML::Node n = load_yaml_file(d.path() / "t/test.yaml", "t/test.yaml", &errors);
  EXPECT_TRUE(errors.empty()) << all(errors);
  ASSERT_TRUE(n["notes"]);
  EXPECT_EQ(n["notes"].as<std::string>(), "tail");
}

TEST(YamlStrict, AliasExpansionIsBounded) {
  // Each level doubles the nodes reached through aliases: 2^25 leaves, a few hundred bytes.
  std::string text = "a0: &a0 [x, x]\n";
  for (int i = 1; i <= 25; ++i) {
    text += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [*a" + std::to_string(i - 1) +
            ", *a" + std::to_string(i - 1) + "]\n";
  }
  std::vector<std::string> e;
  EXPECT_FALSE(load_yaml_text(text, "bomb.yaml", &e));
  EXPECT_TRUE(any_contains(e, "bomb.yaml: more than 1000000 nodes once aliases are expanded"))
      << all(e);
}

TEST(YamlStrict, EveryProgramFileGoesThroughTheLoader) {
  // The simulation and synth specs refuse a duplicate key with the file and key named.
  TempDir d;
  try {
    load_simulation_spec(d.write("sim.yaml", "format: a\nformat: b\n"));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sim.yaml: key 'format' appears twice"), std::string::npos)
        << e.what();
  }
  try {
    synthesize_campaign(d.write("synth.yaml", "name: a\n[b]: c\n"), d.path() / "out");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("synth.yaml: a key at the top level (line 2) is a list"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(d.path() / "out"));
}

// ---- numbers and integers -------------------------------------------------------------------

TEST(YamlStrict, NonFiniteNumbersAreRefused) {
  for (const std::string v : {".inf", "-.inf", ".nan", "1e400"}) {
    const auto e = test_errors("kind: tap\naxis: x\nsample_rate_hz: " + v +
                               "\ndata: {file: hits.csv}\nresponse: acceleration\nhits: auto\n");
    EXPECT_TRUE(any_contains(
        e, "t/test.yaml: key 'sample_rate_hz' must be a finite number, got '" + v + "'"))
        << v << "\n"
        << all(e);
  }
  YamlReader r("x.yaml");
  const YAML::Node n = YAML::Load("{w: [0, .inf], s: -.inf, ok: 1.5e300}");
  EXPECT_FALSE(r.optional_pair(n, "w"));
  EXPECT_FALSE(r.optional_number_or_pair(n, "s"));
  EXPECT_EQ(r.optional_double(n, "ok"), 1.5e300);  // large and finite: a number
  EXPECT_TRUE(any_contains(
      r.errors(), "x.yaml: key 'w' must be two finite numbers [start, end], got [0, inf]"));
  EXPECT_TRUE(any_contains(r.errors(), "x.yaml: key 's' must be a finite number, got '-.inf'"));
}

TEST(YamlStrict, IntegerGettersStateTheRange) {
  YamlReader r("x.yaml");
  const YAML::Node n = YAML::Load("{a: 3, b: 2.5, c: 1e300, d: -1, e: seven, f: 4.0}");
  EXPECT_EQ(r.optional_int(n, "a", "p", 1, 10), 3L);
  EXPECT_EQ(r.optional_int(n, "f", "p", 1, 10), 4L);  // a whole number written with a point
  EXPECT_FALSE(r.optional_int(n, "absent", "p", 1, 10));
  EXPECT_TRUE(r.errors().empty());
  EXPECT_FALSE(r.optional_int(n, "b", "p", 1, 10));
  EXPECT_FALSE(r.optional_int(n, "c", "p", 1, 10));
  EXPECT_FALSE(r.required_int(n, "d", "p", 0, 10));
  EXPECT_FALSE(r.required_int(n, "e", "p", 0, 10));
  EXPECT_FALSE(r.required_int(n, "absent_key", "p", 0, 10));
  EXPECT_EQ(r.errors(), (std::vector<std::string>{
                            "x.yaml: key 'p.b' must be a whole number from 1 to 10, got '2.5'",
                            "x.yaml: key 'p.c' must be a whole number from 1 to 10, got '1e300'",
                            "x.yaml: key 'p.d' must be a whole number from 0 to 10, got '-1'",
                            "x.yaml: key 'p.e' must be a whole number from 0 to 10, got 'seven'",
                            "x.yaml: key 'p.absent_key' is missing"}));
}

TEST(YamlStrict, TeethOf1e300IsRefusedNotReadAsANegativeInteger) {
  TempDir d;
  d.write("campaign.yaml",
          "format: chatterlab-campaign/1\nname: t\ntool: {teeth: 1e300, "
          "radius_mm: 6.35}\n");
  const CampaignSpec c = load_campaign(d.path());
  EXPECT_FALSE(c.tool.has_value());
  EXPECT_TRUE(any_contains(c.errors,
                           "campaign.yaml: key 'tool.teeth' must be a whole number "
                           "from 1 to 500, got '1e300'"))
      << all(c.errors);
}

// The InputError synthesize_campaign gives on the default synth spec with `from` replaced by
// `to` (empty when none).
std::string synth_error(const std::string& from, const std::string& to) {
  TempDir d;
  std::string text = SynthSpecText().text();
  text.replace(text.find(from), from.size(), to);
  try {
    synthesize_campaign(d.write("spec.yaml", text), d.path() / "out");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(YamlStrict, SynthTeethOf1e300IsRefused) {
  const std::string e = synth_error("teeth: 2", "teeth: 1e300");
  EXPECT_NE(e.find("spec.yaml: key 'tool.teeth' must be a whole number from 1 to 500, got '1e300'"),
            std::string::npos)
      << e;
}

// The synth spec's campaign texts and seed: a list as description was yaml-cpp's "bad
// conversion" out of synth (exit 3, no key named); a seed of 1e300 was converted unchecked.
TEST(YamlStrict, SynthTextKeysAndSeedAreCheckedBeforeWriting) {
  const std::string e =
      synth_error("seed: 1", "seed: 1e300\ndescription: [a, b]\nworkpiece: {steel: 1}");
  for (const char* want :
       {"spec.yaml: key 'description' must be a string, got a list",
        "spec.yaml: key 'workpiece' must be a string, got a mapping",
        "spec.yaml: key 'seed' must be a whole number from 0 to 9007199254740992, got '1e300'"}) {
    EXPECT_NE(e.find(want), std::string::npos) << want << "\n" << e;
  }
}

// The suggestion is the closest known key (fewest edits), not the last one that looks alike:
// 'hitd' is one edit from 'hits' and two from 'kind'.
TEST(YamlStrict, TheSuggestionIsTheClosestKey) {
  YamlReader r("t.yaml");
  r.check_keys(YAML::Load("{hitd: auto}"), {"axis", "hits", "kind", "modes"});
  EXPECT_EQ(r.warnings(), std::vector<std::string>{"t.yaml: key 'hitd' is not part of the format "
                                                   "and is ignored (did you mean 'hits'?)"});
}

// A spec read whole or not at all gives its warnings with its errors: the misspelt key that
// is why a key is missing.
TEST(YamlStrict, ASpecWithErrorsGivesItsWarningsToo) {
  const std::string e = synth_error("name: synth-test", "nme: synth-test");
  EXPECT_NE(e.find("spec.yaml: key 'name' is missing"), std::string::npos) << e;
  EXPECT_NE(e.find("\nwarning: spec.yaml: key 'nme' is not part of the format and is ignored (did "
                   "you mean 'name'?)"),
            std::string::npos)
      << e;
}

// A feed that is no number threw YAML::TypedBadConversion out of synth (an internal error).
TEST(YamlStrict, SynthDynoFeedThatIsNoNumberIsAnInputError) {
  const std::string e = synth_error("feeds_mm: [0.05, 0.10, 0.15]", "feeds_mm: [0.05, abc, .inf]");
  EXPECT_NE(e.find("spec.yaml: key 'dyno.feeds_mm' must be a list of finite numbers"),
            std::string::npos)
      << e;
}

TEST(YamlStrict, RepeatRunsIsBounded) {
  TempDir d;
  d.write("campaign.yaml", std::string(kCampaignYaml) + "estimation: {repeat_runs: 999998}\n");
  const CampaignSpec c = load_campaign(d.path());
  EXPECT_TRUE(any_contains(c.errors_of_block("estimation"),
                           "campaign.yaml: key 'estimation.repeat_runs' must be 0 (no "
                           "repeatability runs) or a whole number >= 2 (at most 100), got "
                           "'999998'"))
      << all(c.errors_of_block("estimation"));
  TempDir ok;
  ok.write("campaign.yaml", std::string(kCampaignYaml) +
                                "estimation: {repeat_runs: 100, "
                                "max_passes: 100}\n");
  EXPECT_TRUE(load_campaign(ok.path()).errors_of_block("estimation").empty());
  TempDir passes;
  passes.write("campaign.yaml", std::string(kCampaignYaml) + "estimation: {max_passes: 1e9}\n");
  EXPECT_TRUE(any_contains(load_campaign(passes.path()).errors_of_block("estimation"),
                           "key 'estimation.max_passes' must be a whole number from 1 to 100"));
}

TEST(YamlStrict, TapModesIsAWholeNumberInRange) {
  const auto e = test_errors(std::string(kTapYaml) + "modes: 1e300\n");
  EXPECT_TRUE(
      any_contains(e, "t/test.yaml: key 'modes' must be a whole number from 1 to 20, got '1e300'"))
      << all(e);
  EXPECT_TRUE(test_errors(std::string(kTapYaml) + "modes: auto\n").empty());
  EXPECT_TRUE(test_errors(std::string(kTapYaml) + "modes: 3\n").empty());
}

// ---- simulation spec ---------------------------------------------------------------------------

const char* kSimSpec =
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
    "  revolutions_per_mm: 1290\n";

std::string sim_error(const std::string& text) {
  TempDir d;
  try {
    load_simulation_spec(d.write("spec.yaml", text));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(YamlStrict, MisspeltSimulationKeysAreWarnedWithTheClosestKey) {
  TempDir d;
  std::string text = kSimSpec;
  text.replace(text.find("radius_mm: 6.35}"), 16, "radius_mm: 6.35, helix_dg: 30}");
  text.replace(text.find("  operation:"), 0, "  spindle_rmp: 12000\n");
  text += "inertial: {enabled: false, eccentricity: 1e-6}\nsteps_per_toth: 100\n";
  const SimulationSpec s = load_simulation_spec(d.write("spec.yaml", text));
  EXPECT_EQ(s.steps_per_tooth, 800);  // the misspelt key is not read
  const std::vector<std::string> want = {
      "spec.yaml: key 'tool.helix_dg' is not part of the format and is ignored (did you mean "
      "'helix_deg'?)",
      "spec.yaml: key 'cut.spindle_rmp' is not part of the format and is ignored (did you mean "
      "'spindle_rpm'?)",
      "spec.yaml: key 'inertial.eccentricity' is not part of the format and is ignored (did you "
      "mean 'eccentricity_m'?)",
      "spec.yaml: key 'steps_per_toth' is not part of the format and is ignored (did you mean "
      "'steps_per_tooth'?)"};
  for (const auto& w : want)
    EXPECT_TRUE(any_contains(s.warnings, w)) << w << "\n" << all(s.warnings);
}

TEST(YamlStrict, SimulationCountsAreBounded) {
  std::string teeth = kSimSpec;
  teeth.replace(teeth.find("teeth: 2"), 8, "teeth: 1e300");
  EXPECT_NE(sim_error(teeth).find("spec.yaml: key 'tool.teeth' must be a whole number from 1 to "
                                  "500, got '1e300'"),
            std::string::npos)
      << sim_error(teeth);
  std::string spt = std::string(kSimSpec) + "steps_per_tooth: 2.5\n";
  EXPECT_NE(sim_error(spt).find("key 'steps_per_tooth' must be a whole number from 8 to 100000"),
            std::string::npos)
      << sim_error(spt);
  std::string steps = kSimSpec;
  steps.replace(steps.find("revolutions_per_mm: 1290"), 24, "revolutions_per_mm: 1e9");
  EXPECT_NE(sim_error(steps).find("integration steps (revolutions x teeth x steps_per_tooth): at "
                                  "most 1000000000 are simulated"),
            std::string::npos)
      << sim_error(steps);
  std::string inf = kSimSpec;
  inf.replace(inf.find("Kr_N_m2: 3.0e8"), 14, "Kr_N_m2: .inf");
  EXPECT_NE(sim_error(inf).find("key 'coefficients.Kr_N_m2' must be a finite number"),
            std::string::npos)
      << sim_error(inf);
}

// ---- calibration under a channel name the file does not have -----------------------------------

TEST(YamlStrict, CalibrationOfAnUnknownChannelIsAnErrorWithASuggestion) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write("t/test.yaml", std::string(kTapYaml) +
                             "channels: {forse: {scale: 2}, response: "
                             "{scale: 3}}\n");
  d.write("t/hits.csv", "force,response\n1,2\n");
  CampaignSpec c = load_campaign(d.path());
  ASSERT_EQ(c.tests.size(), 1u);
  ASSERT_TRUE(c.tests[0].usable()) << all(c.tests[0].errors);  // the keys are well formed
  check_signals(c.tests[0]);
  EXPECT_TRUE(any_contains(c.tests[0].errors,
                           "t/test.yaml: key 'channels.forse' names no channel of t/hits.csv "
                           "(channels: force, response) and no channel the test uses: its "
                           "calibration would be ignored (did you mean 'force'?)"))
      << all(c.tests[0].errors);
  // `response`, a channel of the file, is calibrated as written: no message about it.
  EXPECT_FALSE(any_contains(c.tests[0].errors, "channels.response")) << all(c.tests[0].errors);
}

// ---- a campaign with one bad test ---------------------------------------------------------------

// SHA-256 of every file below `root`, by relative path.
std::map<std::string, std::string> hashes(const fs::path& root) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (e.is_regular_file()) out[fs::relative(e.path(), root).generic_string()] = sha256_file(e);
  }
  return out;
}

// A synthetic tap campaign (tap/x, tap/y) whose tap/y test.yaml gets `extra` appended.
struct TapCampaign {
  TempDir d;
  fs::path root;
  explicit TapCampaign(const std::string& extra) {
    SynthSpecText spec;
    spec.tap_hits = 2;
    std::string text = spec.text();
    text = text.substr(0, text.find("dyno:"));  // tap tests only
    root = d.path() / "campaign";
    synthesize_campaign(d.write("spec.yaml", text), root);
    std::ofstream(root / "tap/y/test.yaml", std::ios::app) << "\n" << extra;
  }
};

void expect_other_test_analysed(const std::string& extra, const std::string& message) {
  TapCampaign tc(extra);
  const auto before = hashes(tc.root);
  CampaignResults r;
  ASSERT_NO_THROW(r = run_campaign(load_campaign(tc.root), {}));
  ASSERT_EQ(r.tests.size(), 2u);
  EXPECT_EQ(r.tests[0].spec->id, "tap/x");
  EXPECT_TRUE(r.tests[0].status.ok()) << r.tests[0].status.message;
  ASSERT_EQ(r.tests[1].spec->id, "tap/y");
  EXPECT_FALSE(r.tests[1].status.ok());
  EXPECT_FALSE(r.tests[1].spec->usable());
  EXPECT_TRUE(any_contains(r.tests[1].spec->errors, message)) << all(r.tests[1].spec->errors);
  EXPECT_EQ(hashes(tc.root), before);  // the input folder is never written
}

TEST(YamlStrictCampaign, NonScalarKeySkipsOnlyItsTest) {
  expect_other_test_analysed("channels: {[a]: {scale: 2}}\n",
                             "tap/y/test.yaml: a key under 'channels' (line");
}

TEST(YamlStrictCampaign, DuplicateKeySkipsOnlyItsTest) {
  expect_other_test_analysed("kind: tap\n", "tap/y/test.yaml: key 'kind' appears twice");
}

TEST(YamlStrictCampaign, NonFiniteNumberSkipsOnlyItsTest) {
  expect_other_test_analysed(
      "band_hz: [0, .inf]\n",
      "tap/y/test.yaml: key 'band_hz' must be two finite numbers [start, end], got [0, inf]");
}

TEST(YamlStrictCampaign, MisspeltCalibrationChannelSkipsOnlyItsTest) {
  expect_other_test_analysed("channels: {respons: {scale: 2}}\n",
                             "tap/y/test.yaml: key 'channels.respons' names no channel of "
                             "tap/y/hits.csv (channels: force, response) and no channel the test "
                             "uses: its calibration would be ignored (did you mean 'response'?)");
}

}  // namespace
}  // namespace chatterlab::app
