// Kinds sifs-static, sifs-tap, sifs-cut end to end (EXPERIMENT_FORMAT section 6, docs/sifs.md):
// `synth` writes a spindle-sensor campaign (static loads on three axes with drift and
// cross-talk, taps on x and y, 4-flute cuts at 4500, 9000 and 11600 rpm whose harmonics approach
// the modes, unbalance, a rotated reference dynamometer), `report` runs it and the results are
// compared with truth.yaml: the calibration matrix, the tap-test modes, the unbalance, the
// compensated harmonics, and the harmonic errors against the dynamometer before and after
// compensation by the margins docs/sifs.md states; the compensated file has one row per filter
// step; results.json validates against the schema.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "app/report/report.h"
#include "app/synth/synth.h"
#include "tests/support/results_schema.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::TempDir;
using nlohmann::json;

const char* kSpec =
    "format: chatterlab-synth/1\n"
    "name: sifs-e2e\n"
    "seed: 5\n"
    "tool: {teeth: 4, radius_mm: 9.525, helix_deg: 30}\n"
    "sifs: {}\n";

// Tolerances (docs/sifs.md, "Measured figures"):
constexpr double kCalibrationTol = 0.005;  // max |C - C_true| / max |C_true|
constexpr double kFnTol = 0.005;           // relative, tap-test natural frequencies
constexpr double kZetaTol = 0.05;          // relative, damping ratios
constexpr double kAlphaTol = 0.03;         // relative, modal gains
constexpr double kUnbalanceTol = 0.10;     // relative, 1x unbalance amplitude
constexpr double kRmseRatio = 0.5;         // compensated spectral RMSE < this x uncompensated
constexpr double kTpfTruthTol = 0.05;      // compensated TPF amplitude against the true force's

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class SifsE2E : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    campaign_ = dir_->path() / "campaign";
    report_ = dir_->path() / "report";
    summary_ = synthesize_campaign(dir_->write("spec.yaml", kSpec), campaign_);
    ReportOptions o;
    o.pdf = false;
    o.jobs = 2;
    std::ostringstream log;
    rc_ = run_report(campaign_, report_, o, log);
    log_ = log.str();
    results_ = json::parse(read_text(report_ / "results.json"));
    truth_ = YAML::LoadFile((campaign_ / "truth.yaml").string());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static TempDir* dir_;
  static fs::path campaign_, report_;
  static SynthSummary summary_;
  static int rc_;
  static std::string log_;
  static json results_;
  static YAML::Node truth_;
};
TempDir* SifsE2E::dir_ = nullptr;
fs::path SifsE2E::campaign_, SifsE2E::report_;
SynthSummary SifsE2E::summary_;
int SifsE2E::rc_ = -1;
std::string SifsE2E::log_;
json SifsE2E::results_;
YAML::Node SifsE2E::truth_;

const char* kCuts[3] = {"sifs/cut-n04500", "sifs/cut-n09000", "sifs/cut-n11600"};

TEST_F(SifsE2E, EveryTestAndGroupIsAnalysed) {
  ASSERT_EQ(rc_, 0) << log_;
  EXPECT_EQ(summary_.tests_written, 8);
  const json& tests = results_["tests"];
  ASSERT_EQ(tests.size(), 8u) << tests.dump(1);
  for (const auto& [id, t] : tests.items()) EXPECT_EQ(t["status"], "ok") << id << ": " << t.dump();
  for (const char* g : {"sifs-static", "sifs-cut"}) {
    ASSERT_TRUE(results_["groups"].contains(g)) << results_["groups"].dump();
    EXPECT_FALSE(results_["groups"][g].contains("skip_reason")) << results_["groups"][g].dump();
  }
}

TEST_F(SifsE2E, CalibrationMatrixIsRecovered) {
  const json& C = results_["groups"]["sifs-static"]["calibration_matrix"];
  const YAML::Node Ct = truth_["calibration_matrix"];
  double err = 0, scale = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      const double t = Ct[i][j].as<double>();
      err = std::max(err, std::abs(C[i][j].get<double>() - t));
      scale = std::max(scale, std::abs(t));
    }
  }
  EXPECT_LT(err / scale, kCalibrationTol);
  RecordProperty("calibration_max_error_ratio", std::to_string(err / scale));
}

TEST_F(SifsE2E, TapModesAreRecovered) {
  for (const char* id : {"sifs/tap-x", "sifs/tap-y"}) {
    const json& modes = results_["tests"][id]["modes"];
    const YAML::Node tm = truth_["tests"][id]["modes"];
    ASSERT_EQ(modes.size(), tm.size()) << id;
    for (std::size_t i = 0; i < tm.size(); ++i) {
      const double fn = tm[i]["fn_hz"].as<double>();
      EXPECT_NEAR(modes[i]["fn_hz"].get<double>(), fn, kFnTol * fn) << id << " mode " << i;
      const double z = tm[i]["zeta"].as<double>();
      EXPECT_NEAR(modes[i]["zeta"].get<double>(), z, kZetaTol * z) << id << " mode " << i;
      const double a = tm[i]["alpha"].as<double>();
      EXPECT_NEAR(modes[i]["alpha"].get<double>(), a, kAlphaTol * a) << id << " mode " << i;
    }
    EXPECT_NEAR(results_["tests"][id]["static_gain"].get<double>(), 1.0, 1e-9);
    EXPECT_EQ(results_["tests"][id]["realization"], "scaled-modal");
    EXPECT_LT(results_["tests"][id]["cond_A"].get<double>(), 100.0);
  }
}

TEST_F(SifsE2E, UnbalanceIsIdentifiedInTheAirWindow) {
  for (const char* id : kCuts) {
    for (const char* axis : {"x", "y"}) {
      const double truth = truth_["tests"][id]["unbalance"][axis][0]["amp_N"].as<double>();
      const json& ub = results_["tests"][id]["axes"][axis]["unbalance"];
      ASSERT_GE(ub.size(), 1u);
      EXPECT_EQ(ub[0]["h"], 1);
      EXPECT_NEAR(ub[0]["amp_N"].get<double>(), truth, kUnbalanceTol * truth) << id << " " << axis;
    }
  }
}

// Against the dynamometer: the spectral RMSE over the analysed harmonics falls by the stated
// factor, and at the tooth-passing harmonics (where the force is) the mean absolute amplitude
// error falls too.
TEST_F(SifsE2E, CompensationBeatsTheRawSensorAgainstTheReference) {
  for (const char* id : kCuts) {
    for (const char* axis : {"x", "y"}) {
      const json& ax = results_["tests"][id]["axes"][axis];
      const double before = ax["spectral_rmse_N"]["measured"].get<double>();
      const double after = ax["spectral_rmse_N"]["compensated"].get<double>();
      EXPECT_LT(after, kRmseRatio * before) << id << " " << axis;
      double err_before = 0, err_after = 0;
      int n = 0;
      for (const auto& h : ax["harmonics"]) {
        if (h["h"].get<int>() % 4 != 0 || h["freq_hz"].get<double>() > 2500) continue;
        err_before += std::abs(h["measured_amp_err_pct"].get<double>());
        err_after += std::abs(h["amp_err_pct"].get<double>());
        ++n;
      }
      ASSERT_GT(n, 0);
      EXPECT_LT(err_after, err_before) << id << " " << axis;
      RecordProperty(std::string(id) + "/" + axis + "/rmse_N",
                     std::to_string(before) + " -> " + std::to_string(after));
    }
  }
}

// The compensated first tooth-passing harmonic against the true tip force's (truth.yaml
// `harmonics`, the continuous force's c_h).
TEST_F(SifsE2E, CompensatedToothPassingHarmonicMatchesTheTrueForce) {
  for (const char* id : kCuts) {
    const YAML::Node h = truth_["tests"][id]["harmonics"];
    for (const char* axis : {"x", "y"}) {
      double truth = std::nan("");
      for (std::size_t i = 0; i < h["h"].size(); ++i) {
        if (h["h"][i].as<int>() != 4) continue;
        truth = std::hypot(h[std::string(axis) + "_re_N"][i].as<double>(),
                           h[std::string(axis) + "_im_N"][i].as<double>());
      }
      ASSERT_TRUE(std::isfinite(truth));
      double est = std::nan("");
      for (const auto& e : results_["tests"][id]["axes"][axis]["harmonics"]) {
        if (e["h"] == 4) est = e["compensated_amp_N"].get<double>();
      }
      EXPECT_NEAR(est, truth, kTpfTruthTol * truth) << id << " " << axis;
    }
  }
}

TEST_F(SifsE2E, CompensatedFileHasOneRowPerFilterStep) {
  for (const char* id : kCuts) {
    const json& t = results_["tests"][id];
    const fs::path file = report_ / t["compensated_file"].get<std::string>();
    ASSERT_TRUE(fs::exists(file)) << file;
    std::ifstream in(file);
    std::string header;
    std::getline(in, header);
    EXPECT_EQ(header, "t,fx,fy");
    int rows = 0;
    std::string line;
    while (std::getline(in, line)) ++rows;
    // 3.5 s at 12.8 kHz resampled to 10 kHz: ceil(44800 x 25 / 32) rows.
    EXPECT_EQ(rows, 35000) << id;
    EXPECT_EQ(t["filter_rate_hz"], 10000.0);
  }
}

TEST_F(SifsE2E, GroupHoldsTheQTableAndTheTapMap) {
  const json& g = results_["groups"]["sifs-cut"];
  ASSERT_EQ(g["spindle_rpm"].size(), 3u) << g.dump();
  EXPECT_EQ(g["q_exponent_x"].size(), 3u);
  const json& map = g["tap_map"]["tap_x"];
  EXPECT_EQ(map["spindle_rpm"].size(), 48u);  // 47 grid speeds + 11600
  EXPECT_EQ(map["q_exponents"].size(), 30u);
  EXPECT_EQ(map["rmse_N"].size(), 48u);
  // The tap sweep the cut ran at its speed is the map's row at that speed.
  for (std::size_t c = 0; c < 3; ++c) {
    const double rpm = g["spindle_rpm"][c].get<double>();
    for (std::size_t i = 0; i < map["spindle_rpm"].size(); ++i) {
      if (map["spindle_rpm"][i].get<double>() != rpm) continue;
      EXPECT_EQ(map["best_q_exponent"][i], g["q_exponent_x"][c]) << rpm;
    }
  }
}

TEST_F(SifsE2E, ReportShowsTheSections) {
  const std::string html = read_text(report_ / "index.html");
  for (const char* s : {"<section id=\"sifs-static\">", "<section id=\"sifs-tap\">",
                        "<section id=\"sifs-cut\">", "<section id=\"sifs-q\">"}) {
    EXPECT_NE(html.find(s), std::string::npos) << s;
  }
  EXPECT_TRUE(fs::exists(report_ / "figures/sifs-static-calibration.svg"));
  EXPECT_TRUE(fs::exists(report_ / "figures/sifs-cut-q-map.svg"));
}

TEST_F(SifsE2E, ResultsValidateAgainstTheSchema) {
  ASSERT_EQ(rc_, 0) << log_;
  const auto check = chatterlab::testing::check_results_schema(report_ / "results.json");
  EXPECT_TRUE(check.valid) << check.output;
}

}  // namespace
}  // namespace chatterlab::app
