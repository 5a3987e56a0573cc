// A spindle-sensor campaign as another tool would write it to EXPERIMENT_FORMAT section 6: the
// records as CSV with a time column and the channels in another order, taps with `hits: auto`,
// a cut with neither a dynamometer nor a filter rate (the filter runs at the record's 12.8 kHz)
// and the steady-state gain. The campaign is the synth one rewritten file by file, so its truth
// still holds: every test is analysed, the cut's results carry no reference numbers, and the
// compensated tooth-passing harmonic still matches the true force.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

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

constexpr double kTpfTruthTol = 0.05;  // as in sifs_e2e_test

const char* kSpec =
    "format: chatterlab-synth/1\n"
    "name: sifs-other-tool\n"
    "seed: 9\n"
    "tool: {teeth: 4, radius_mm: 9.525}\n"
    "sifs:\n"
    "  cuts: {rpm: [9000], duration_s: 2.6}\n";

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Rewrites one test: its record as record.csv (a t column, then the channels in reverse order)
// and test.yaml through `edit`.
template <class Edit>
void rewrite(const TestSpec& t, Edit edit) {
  const SignalTable table = SignalTable::open(t.data, t.id);
  std::vector<std::string> names{"t"};
  std::vector<Eigen::VectorXd> cols;
  const auto n = static_cast<Eigen::Index>(table.samples());
  cols.push_back(Eigen::VectorXd::LinSpaced(n, 0.0, static_cast<double>(n - 1) / t.sample_rate_hz));
  for (auto it = t.data.channels.rbegin(); it != t.data.channels.rend(); ++it) {
    names.push_back(*it);
    cols.push_back(table.channel(*it));  // raw values: test.yaml keeps its scales
  }
  std::vector<const Eigen::VectorXd*> ptrs;
  for (const auto& c : cols) ptrs.push_back(&c);
  write_signals(t.folder / "record.csv", names, ptrs);
  fs::remove(t.data.file);
  YAML::Node y = YAML::LoadFile((t.folder / "test.yaml").string());
  y["data"] = YAML::Load("{file: record.csv}");
  edit(y);
  std::ofstream(t.folder / "test.yaml") << y << "\n";
}

TEST(SifsOtherTools, ContractCampaignWithOptionalKeysRuns) {
  TempDir d;
  const fs::path campaign = d.path() / "campaign", report = d.path() / "report";
  synthesize_campaign(d.write("spec.yaml", kSpec), campaign);
  const CampaignSpec c = load_campaign(campaign);
  for (const auto& t : c.tests) {
    ASSERT_TRUE(t.usable()) << t.id;
    rewrite(t, [&](YAML::Node& y) {
      if (t.kind == "sifs-tap") y["hits"] = "auto";
      if (t.kind == "sifs-cut") {
        y.remove("dynamometer");
        y.remove("filter_rate_hz");
        y["gain"] = "steady-state";
        y["band_hz"] = YAML::Load("[10, 3000]");
      }
    });
  }
  ReportOptions o;
  o.pdf = false;
  o.jobs = 2;
  std::ostringstream log;
  ASSERT_EQ(run_report(campaign, report, o, log), 0) << log.str();
  const json r = json::parse(read_text(report / "results.json"));
  for (const auto& [id, t] : r["tests"].items()) EXPECT_EQ(t["status"], "ok") << id << t.dump();
  const json& cut = r["tests"]["sifs/cut-n09000"];
  EXPECT_EQ(cut["filter_rate_hz"], 12800.0);
  const YAML::Node truth = YAML::LoadFile((campaign / "truth.yaml").string());
  const YAML::Node h = truth["tests"]["sifs/cut-n09000"]["harmonics"];
  for (const char* axis : {"x", "y"}) {
    const json& ax = cut["axes"][axis];
    EXPECT_EQ(ax["gain"], "steady-state");
    EXPECT_TRUE(ax["spectral_rmse_N"].is_null());
    EXPECT_FALSE(ax.contains("cut_rmse_curve_N"));
    double true_amp = std::nan("");
    for (std::size_t i = 0; i < h["h"].size(); ++i) {
      if (h["h"][i].as<int>() == 4) {
        true_amp = std::hypot(h[std::string(axis) + "_re_N"][i].as<double>(),
                              h[std::string(axis) + "_im_N"][i].as<double>());
      }
    }
    double est = std::nan(""), last_f = 0;
    for (const auto& e : ax["harmonics"]) {
      EXPECT_FALSE(e.contains("reference_amp_N"));
      if (e["h"] == 4) est = e["compensated_amp_N"].get<double>();
      last_f = e["freq_hz"].get<double>();
    }
    EXPECT_LE(last_f, 3000.0);
    EXPECT_NEAR(est, true_amp, kTpfTruthTol * true_amp) << axis;
  }
  // Taps found by `hits: auto`: as many as the synth wrote.
  EXPECT_EQ(r["tests"]["sifs/tap-x"]["hits"], 5);
}

}  // namespace
}  // namespace chatterlab::app

namespace chatterlab::app {
namespace {

// A filter rate whose Nyquist frequency (2 kHz) lies below the taps' third mode (2.4 kHz): the
// cut is skipped with a message naming the tap test, the mode and the fix; the taps still run.
TEST(SifsOtherTools, TapModeAboveTheFilterNyquistSkipsTheCut) {
  TempDir d;
  const fs::path campaign = d.path() / "campaign", report = d.path() / "report";
  synthesize_campaign(d.write("spec.yaml", kSpec), campaign);
  const fs::path cut_yaml = campaign / "sifs/cut-n09000/test.yaml";
  YAML::Node y = YAML::LoadFile(cut_yaml.string());
  y["filter_rate_hz"] = 4000;
  std::ofstream(cut_yaml) << y << "\n";
  ReportOptions o;
  o.pdf = false;
  o.jobs = 2;
  std::ostringstream log;
  run_report(campaign, report, o, log);
  const json r = json::parse(read_text(report / "results.json"));
  const json& cut = r["tests"]["sifs/cut-n09000"];
  EXPECT_EQ(cut["status"], "skipped");
  const std::string why = cut["skip_reason"].get<std::string>();
  EXPECT_NE(why.find("the sensor model of sifs/tap-x has a mode at 2399"), std::string::npos)
      << why;
  EXPECT_NE(why.find("raise filter_rate_hz"), std::string::npos) << why;
  EXPECT_EQ(r["tests"]["sifs/tap-x"]["status"], "ok");
}

}  // namespace
}  // namespace chatterlab::app
