// Bad input to kinds sweep-frf and spindle-current (format section 5): each broken test is
// skipped with a message naming its file and key, and the rest of the campaign runs. The base
// campaign is synth's `spindle` section with one cut; the broken tests are copies of its cut
// and sweep with one thing changed each, and one cut written as another tool would: the
// format's own test.yaml example keys over a CSV current file.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "app/cli/validate.h"
#include "app/core/campaign.h"
#include "app/core/signals.h"
#include "app/report/report.h"
#include "app/synth/synth.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::TempDir;
using nlohmann::json;

const char* kSpec =
    "format: chatterlab-synth/1\n"
    "name: sysid-errors\n"
    "seed: 4\n"
    "tool: {teeth: 2, radius_mm: 6.0, helix_deg: 30}\n"
    "spindle:\n"
    "  sweep: {duration_s: 8}\n"
    "  cuts: {rpm: [5000]}\n";

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

class SysidErrors : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const fs::path c = dir_->path() / "campaign";
    synthesize_campaign(dir_->write("spec.yaml", kSpec), c);
    const std::string cut = read_text(c / "spindle/cut-n05000/test.yaml");
    const std::string sweep = read_text(c / "spindle/sweep/test.yaml");
    const auto copy_cut = [&](const std::string& name, const std::string& yaml) {
      fs::create_directories(c / "bad" / name);
      fs::copy_file(c / "spindle/cut-n05000/current.f32", c / "bad" / name / "current.f32");
      fs::copy_file(c / "spindle/cut-n05000/dyno.csv", c / "bad" / name / "dyno.csv");
      dir_->write("campaign/bad/" + name + "/test.yaml", yaml);
    };
    copy_cut("not-a-model", replaced(cut, "model: spindle/sweep", "model: spindle/cut-n05000"));
    copy_cut("overlap", replaced(cut, "air_window_s: [0.02, 0.3]", "air_window_s: [0.02, 0.6]"));
    copy_cut("no-resolution", replaced(cut, "current_resolution_A: 0.01\n", ""));
    copy_cut("short-dyno", cut);
    // The dynamometer stops at 0.1 s, before the air window ends.
    dir_->write("campaign/bad/short-dyno/dyno.csv", [] {
      std::string t = "t,torque\n";
      for (int k = 0; k < 2560; ++k) t += std::to_string(k / 25600.0) + ",0.01\n";
      return t;
    }());
    fs::create_directories(c / "bad/wide-band");
    fs::copy_file(c / "spindle/sweep/sweep.f32", c / "bad/wide-band/sweep.f32");
    dir_->write("campaign/bad/wide-band/test.yaml",
                replaced(sweep, "sweep_band_hz: [5, 3000]", "sweep_band_hz: [5, 6000]"));
    // Another tool's cut: the format's example keys, the current as CSV in counts.
    {
      DataSpec d;
      d.file = c / "spindle/cut-n05000/current.f32";
      d.relative_file = "current.f32";
      d.channels = {"current", "speed"};
      const Eigen::VectorXd counts = SignalTable::open(d, "current.f32").channel("current");
      std::string csv = "current\n";
      for (Eigen::Index k = 0; k < counts.size(); ++k) {
        csv += std::to_string(static_cast<long>(std::lround(counts[k]))) + "\n";
      }
      dir_->write("campaign/other/cut/current.csv", csv);
      fs::copy_file(c / "spindle/cut-n05000/dyno.csv", c / "other/cut/dyno.csv");
      dir_->write("campaign/other/cut/test.yaml",
                  "kind: spindle-current\n"
                  "sample_rate_hz: 10000\n"
                  "data: {file: current.csv}\n"
                  "channels: {current: {scale: 0.01}}\n"
                  "current_resolution_A: 0.01\n"
                  "model: spindle/sweep\n"
                  "spindle_rpm: 5000\n"
                  "operation: up-milling\n"
                  "radial_immersion_mm: 12.0\n"
                  "axial_depth_mm: 2.0\n"
                  "feed_per_tooth_mm: 0.1\n"
                  "Ktc_N_m2: 7.976e+8\n"
                  "Kte_N_m: 2.57e+4\n"
                  "air_window_s: [0.02, 0.3]\n"
                  "cut_window_s: [0.5, 1.55]\n"
                  "dynamometer: {file: dyno.csv, sample_rate_hz: 25600}\n");
    }
    ReportOptions o;
    o.pdf = false;
    o.jobs = 2;
    std::ostringstream log;
    run_report(c, dir_->path() / "report", o, log);
    log_ = log.str();
    results_ = new json(json::parse(read_text(dir_->path() / "report/results.json")));
  }
  static void TearDownTestSuite() {
    delete results_;
    delete dir_;
    results_ = nullptr;
    dir_ = nullptr;
  }
  static std::string reason(const std::string& id) {
    const json& t = results_->at("tests").at(id);
    EXPECT_NE(t.at("status"), "ok") << id;
    return t.value("skip_reason", std::string());
  }
  static TempDir* dir_;
  static std::string log_;
  static json* results_;
};
TempDir* SysidErrors::dir_ = nullptr;
std::string SysidErrors::log_;
json* SysidErrors::results_ = nullptr;

TEST_F(SysidErrors, EachBrokenTestNamesItsFileAndKey) {
  const std::string not_model = reason("bad/not-a-model");
  EXPECT_NE(not_model.find("bad/not-a-model/test.yaml"), std::string::npos) << not_model;
  EXPECT_NE(not_model.find("'model' names 'spindle/cut-n05000', a spindle-current test"),
            std::string::npos)
      << not_model;
  const std::string overlap = reason("bad/overlap");
  EXPECT_NE(overlap.find("air_window_s"), std::string::npos) << overlap;
  EXPECT_NE(overlap.find("overlaps cut_window_s"), std::string::npos) << overlap;
  const std::string missing = reason("bad/no-resolution");
  EXPECT_NE(missing.find("current_resolution_A"), std::string::npos) << missing;
  EXPECT_NE(missing.find("is missing"), std::string::npos) << missing;
  const std::string shorter = reason("bad/short-dyno");
  EXPECT_NE(shorter.find("bad/short-dyno/dyno.csv"), std::string::npos) << shorter;
  EXPECT_NE(shorter.find("before the end of air_window_s or cut_window_s"), std::string::npos)
      << shorter;
  const std::string wide = reason("bad/wide-band");
  EXPECT_NE(wide.find("sweep_band_hz"), std::string::npos) << wide;
  EXPECT_NE(wide.find("above half the sample rate"), std::string::npos) << wide;
}

// The dynamometer record and the windows' lengths are checked before computing
// (SpindleCurrentKind::check_record, which `validate` and `report` both run): validate finds
// the short dynamometer record that report skips the test for, with the same message.
TEST_F(SysidErrors, ValidateFindsTheShortDynamometerRecord) {
  CampaignSpec c = load_campaign(dir_->path() / "campaign");
  std::ostringstream said;
  EXPECT_EQ(validate_campaign(c, said), 1);
  const std::string reported = reason("bad/short-dyno");
  for (const TestSpec& t : c.tests) {
    if (t.id != "bad/short-dyno") continue;
    ASSERT_EQ(t.errors.size(), 1u) << said.str();
    EXPECT_NE(t.errors[0].find("bad/short-dyno/dyno.csv: ends at 0.1 s, before the end of "
                               "air_window_s or cut_window_s"),
              std::string::npos)
        << t.errors[0];
    EXPECT_NE(reported.find(t.errors[0]), std::string::npos) << reported;
  }
  EXPECT_NE(said.str().find("UNUSABLE bad/short-dyno"), std::string::npos) << said.str();
}

TEST_F(SysidErrors, TheRestOfTheCampaignRuns) {
  for (const char* id : {"spindle/sweep", "spindle/cut-n05000", "other/cut"}) {
    EXPECT_EQ(results_->at("tests").at(id).at("status"), "ok") << id << log_;
  }
  // The other tool's cut (CSV, the format's example keys) gives the synth cut's torque: the same
  // current in the same counts, the same model; only the feed differs (0.1 mm, as synth's).
  const json& a = results_->at("tests").at("other/cut");
  const json& b = results_->at("tests").at("spindle/cut-n05000");
  EXPECT_NEAR(a.at("torque_mean_Nm").get<double>(), b.at("torque_mean_Nm").get<double>(), 1e-9);
}

}  // namespace
}  // namespace chatterlab::app
