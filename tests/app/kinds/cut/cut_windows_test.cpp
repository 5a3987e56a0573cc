// A cut test's windows (cut_window_s, air_window_s, estimation_window_s) must lie inside its
// record (docs/format/test-kinds.md, "kind: cut"): one outside is an input error naming the file
// and key, found by the check `validate` and `report` both run, so validate fails and report
// skips that test while the rest of the campaign is analysed (issue 16: a ramped cut starting
// before 0 s read outside the record).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>

#include "app/cli/validate.h"
#include "app/core/campaign.h"
#include "app/kinds/cut/cut_step.h"
#include "app/report/report.h"
#include "app/synth/synth.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::TempDir;
using nlohmann::json;

// Cut tests only (no tap test or dyno group: the offset angle and everything after it are
// skipped with the reason, which keeps the run short): one at constant depth, and ramps whose
// windows the tests below move.
const char* kSpec =
    "format: chatterlab-synth/1\n"
    "name: cut-windows\n"
    "seed: 3\n"
    "tool: {teeth: 2, radius_mm: 6.35}\n"
    "cut:\n"
    "  sample_rate_hz: 100000\n"
    "  spindle_rpm: 15000\n"
    "  modal: {m_kg: 0.03134, c_kg_s: 22.21, k_N_m: 9.84e5}\n"
    "  coefficients: {Kt_N_m2: [2.483e8, 6.641e9], Kr_N_m2: [2.196e8, 4.154e9]}\n"
    "  air_revolutions: 10\n"
    "  tests:\n"
    "    - {name: constant, axial_depth_mm: 1.0, duration_s: 0.04, offset_angle_deg: 147.0}\n"
    "    - {name: ramp-a, axial_depth_mm: [0.5, 1.0], revolutions_per_mm: 40}\n"
    "    - {name: ramp-b, axial_depth_mm: [0.5, 1.0], revolutions_per_mm: 40}\n"
    "    - {name: ramp-c, axial_depth_mm: [0.5, 1.0], revolutions_per_mm: 40}\n"
    "    - {name: ramp-d, axial_depth_mm: [0.5, 1.0], revolutions_per_mm: 40}\n";

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Replaces the line `key: ...` of a test.yaml by `key: value`.
void set_key(const std::filesystem::path& yaml, const std::string& key, const std::string& value) {
  const std::string text = read_text(yaml);
  const std::regex line("(^|\n)" + key + ": [^\n]*");
  ASSERT_TRUE(std::regex_search(text, line)) << key << " not in " << yaml;
  std::ofstream(yaml, std::ios::binary)
      << std::regex_replace(text, line, "$1" + key + ": " + value);
}

// The record's duration as the messages print it: samples (3 float channels) / 100 kHz.
std::string duration_text(const std::filesystem::path& signals) {
  const double samples = static_cast<double>(std::filesystem::file_size(signals)) / (3 * 4);
  return window_text(samples / 100000.0);
}

class CutWindows : public ::testing::Test {
 protected:
  void SetUp() override {
    d_.write("spec.yaml", kSpec);
    synthesize_campaign(d_.path() / "spec.yaml", campaign());
    record_ = duration_text(campaign() / "cuts/ramp-a/signals.f32");
  }
  std::filesystem::path campaign() const { return d_.path() / "c"; }
  std::filesystem::path yaml(const std::string& test) const {
    return campaign() / "cuts" / test / "test.yaml";
  }
  // The messages of a window before the record, as validate and report print them.
  std::string before(const std::string& test, const std::string& key,
                     const std::string& start) const {
    return "cuts/" + test + "/test.yaml: key '" + key + "' starts at " + start +
           " s, before the record (0 .. " + record_ + " s)";
  }

  TempDir d_;
  std::string record_;
};

TEST_F(CutWindows, RampStartingBeforeTheRecordFailsValidateAndIsSkippedByReport) {
  set_key(yaml("ramp-a"), "cut_window_s", "[-0.5, 0.06]");
  set_key(yaml("ramp-b"), "cut_window_s", "[-1e6, 0.06]");
  {
    CampaignSpec c = load_campaign(campaign());
    std::ostringstream out;
    EXPECT_EQ(validate_campaign(c, out), 1) << out.str();
    EXPECT_NE(out.str().find(before("ramp-a", "cut_window_s", "-0.5")), std::string::npos)
        << out.str();
    EXPECT_NE(out.str().find(before("ramp-b", "cut_window_s", "-1e+06")), std::string::npos)
        << out.str();
    EXPECT_NE(out.str().find("5 tests found, 3 usable, 2 unusable"), std::string::npos)
        << out.str();
  }
  std::ostringstream log;
  ReportOptions opt;
  opt.pdf = false;
  ASSERT_EQ(run_report(campaign(), d_.path() / "out", opt, log), 0) << log.str();
  std::ifstream in(d_.path() / "out/results.json");
  const json r = json::parse(in);
  const json& t = r["tests"];
  EXPECT_EQ(t["cuts/ramp-a"]["status"], "skipped") << t["cuts/ramp-a"].dump();
  EXPECT_EQ(t["cuts/ramp-a"]["skip_reason"], before("ramp-a", "cut_window_s", "-0.5"));
  EXPECT_FALSE(t["cuts/ramp-a"].contains("bifurcation_depth_mm"));  // no number from it
  EXPECT_EQ(t["cuts/ramp-b"]["status"], "skipped") << t["cuts/ramp-b"].dump();
  EXPECT_EQ(t["cuts/ramp-b"]["skip_reason"], before("ramp-b", "cut_window_s", "-1e+06"));
  // The rest of the campaign is analysed: the constant cut and the untouched ramps.
  for (const char* id : {"cuts/constant", "cuts/ramp-c", "cuts/ramp-d"}) {
    EXPECT_EQ(t[id]["status"], "ok") << id << ": " << t[id].dump();
  }
}

TEST_F(CutWindows, EveryWindowKeyIsCheckedAgainstTheRecord) {
  set_key(yaml("ramp-a"), "air_window_s", "[-0.01, 0.03]");
  set_key(yaml("ramp-b"), "cut_window_s", "[0.04, 1e6]");
  set_key(yaml("ramp-c"), "air_window_s", "[0.0, 7.5]");
  std::ofstream(yaml("constant"), std::ios::app) << "estimation_window_s: [0.07, 0.1]\n";
  CampaignSpec c = load_campaign(campaign());
  std::ostringstream out;
  EXPECT_EQ(validate_campaign(c, out), 1) << out.str();
  const std::string text = out.str();
  const std::string record = "the record (0 .. " + record_ + " s)";
  EXPECT_NE(text.find(before("ramp-a", "air_window_s", "-0.01")), std::string::npos) << text;
  EXPECT_NE(text.find("cuts/ramp-b/test.yaml: key 'cut_window_s' ends at 1e+06 s, after " + record),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("cuts/ramp-c/test.yaml: key 'air_window_s' ends at 7.5 s, after " + record),
            std::string::npos)
      << text;
  // The estimation window is held inside cut_window_s (so inside the record) when read: the
  // constant cut's cut_window_s is [0.04, 0.08] s.
  EXPECT_NE(text.find("cuts/constant/test.yaml: key 'estimation_window_s' must be [start, end] "
                      "with end > start inside cut_window_s"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("5 tests found, 1 usable, 4 unusable"), std::string::npos) << text;
}

TEST_F(CutWindows, NonFiniteOrEmptyWindowsAreRefusedWhenRead) {
  set_key(yaml("ramp-a"), "cut_window_s", "[.nan, 0.06]");
  set_key(yaml("ramp-b"), "cut_window_s", "[0.04, .inf]");
  set_key(yaml("ramp-c"), "air_window_s", "[0.03, 0.03]");
  set_key(yaml("ramp-d"), "cut_window_s", "[0.06, 0.04]");
  CampaignSpec c = load_campaign(campaign());
  std::ostringstream out;
  EXPECT_EQ(validate_campaign(c, out), 1) << out.str();
  const std::string text = out.str();
  for (const std::string m :
       {"cuts/ramp-a/test.yaml: key 'cut_window_s' must be two finite numbers [start, end], got "
        "[nan, 0.06]",
        "cuts/ramp-b/test.yaml: key 'cut_window_s' must be two finite numbers [start, end], got "
        "[0.04, inf]",
        "cuts/ramp-c/test.yaml: key 'air_window_s' must be [start, end] with end > start, got "
        "[0.03, 0.03]",
        "cuts/ramp-d/test.yaml: key 'cut_window_s' must be [start, end] with end > start, got "
        "[0.06, 0.04]"}) {
    EXPECT_NE(text.find(m), std::string::npos) << m << "\n" << text;
  }
  EXPECT_NE(text.find("5 tests found, 1 usable, 4 unusable"), std::string::npos) << text;
}

// A caller that runs the step without the record check first (not the pipeline, which always
// checks): the step checks again and fails with the same message instead of reading outside
// the record.
TEST_F(CutWindows, TheStepItselfRefusesAWindowOutsideTheRecord) {
  set_key(yaml("ramp-a"), "cut_window_s", "[-1e6, 0.06]");
  const CampaignSpec c = load_campaign(campaign());
  const TestSpec* t = nullptr;
  for (const auto& s : c.tests) {
    if (s.id == "cuts/ramp-a") t = &s;
  }
  ASSERT_NE(t, nullptr);
  ASSERT_TRUE(t->usable()) << t->errors.front();  // parse alone does not know the record
  const CutOutcome out = run_cut_test(*t, {});
  EXPECT_FALSE(out.summary.ok());
  EXPECT_EQ(out.summary.message, before("ramp-a", "cut_window_s", "-1e+06"));
}

}  // namespace
}  // namespace chatterlab::app
