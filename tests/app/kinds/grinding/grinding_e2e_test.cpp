// Kind grinding end to end: `synth` writes grinding tests from a spec's `grinding` section (a true
// G1 away from the nominal, a dressing whose true depth differs from the commanded one, missing
// and late inspections), truth.yaml holds the contract's layout, `report` runs them through
// run_campaign, writes each estimator's trajectory beside results.json (sum of n_i + 1 rows) and
// a results.json that validates against docs/results.schema.json, with NEES and the truth
// comparison. Spec errors name the key.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "analysis/common/summary.h"
#include "analysis/grinding/multirate_ekf.h"
#include "app/report/report.h"
#include "app/synth/synth.h"
#include "tests/support/results_schema.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
namespace g = chatterlab::grinding;
using chatterlab::testing::TempDir;
using nlohmann::json;

// Short cycles (n_i = 120) keep the test fast; the second series uses the default schedule.
const char* kSpec =
    "format: chatterlab-synth/1\n"
    "name: grinding-e2e\n"
    "seed: 11\n"
    "grinding:\n"
    "  schedule: [{u_mm_s: 0.0254, rows: 70}, {u_mm_s: 0.002, rows: 25}, {u_mm_s: 0, rows: 25}]\n"
    "  tests:\n"
    "    - name: series-a\n"
    "      cycles: 14\n"
    "      G1: 14.1\n"
    "      ds_start_mm: 50.0004\n"
    "      R0_start_um: 3.1\n"
    "      uninspected: [3]\n"
    "      ds_unmeasured: [5]\n"
    "      Ra_unmeasured: [6]\n"
    "      late: [[7, 9], [13, 15]]\n"
    "      dressings: [{before_cycle: 9, depth_mm: 0.040, true_depth_mm: 0.0412}]\n"
    "    - {name: series-b, cycles: 10}\n";

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

int count_lines(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) ++n;
  return n;
}

class GrindingE2E : public ::testing::Test {
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
};
TempDir* GrindingE2E::dir_ = nullptr;
fs::path GrindingE2E::campaign_, GrindingE2E::report_;
SynthSummary GrindingE2E::summary_;
int GrindingE2E::rc_ = -1;
std::string GrindingE2E::log_;
json GrindingE2E::results_;

TEST_F(GrindingE2E, SynthWritesTheTestsAndTheContractsTruth) {
  EXPECT_EQ(summary_.tests_written, 2);
  EXPECT_TRUE(summary_.warnings.empty());
  const YAML::Node truth = YAML::LoadFile((campaign_ / "truth.yaml").string());
  const YAML::Node a = truth["tests"]["grinding/series-a"];
  ASSERT_TRUE(a) << read_text(campaign_ / "truth.yaml");
  EXPECT_EQ(a["kind"].as<std::string>(), "grinding");
  EXPECT_EQ(a["cycles"].as<int>(), 14);
  EXPECT_EQ(a["G1"].as<double>(), 14.1);
  EXPECT_EQ(a["ds_start_mm"].as<double>(), 50.0004);
  EXPECT_EQ(a["R0_start_um"].as<double>(), 3.1);
  for (const char* k :
       {"cycle", "n", "Vw_mm2", "v_mm_s", "ds_mm", "R0_um", "Ra_um", "roundness_um"}) {
    EXPECT_EQ(a["per_cycle"][k].size(), 14u) << k;
  }
  EXPECT_EQ(a["dressings"][0]["before_cycle"].as<int>(), 9);
  EXPECT_EQ(a["dressings"][0]["depth_mm"].as<double>(), 0.0412);  // the true depth
  // The trajectory: j = 0, 10, ..., 120 (= n_i): 13 rows per cycle and a header.
  const fs::path traj = campaign_ / a["trajectory"]["file"].as<std::string>();
  EXPECT_EQ(count_lines(traj), 14 * 13 + 1);
  // test.yaml holds the lab's nominal G1 and the commanded depth.
  const YAML::Node t = YAML::LoadFile((campaign_ / "grinding/series-a/test.yaml").string());
  EXPECT_EQ(t["model"]["G1"].as<double>(), 13.0);
  EXPECT_EQ(t["dressings"][0]["depth_mm"].as<double>(), 0.04);
  // Inspections: cycle 3 has no row, 5 no d_s, 6 no R_a, 7 and 13 late (13 never usable).
  const std::string insp = read_text(campaign_ / "grinding/series-a/inspections.csv");
  EXPECT_EQ(insp.find("\n3,"), std::string::npos);
  EXPECT_NE(insp.find("\n5,5,,"), std::string::npos) << insp;
  EXPECT_NE(insp.find("\n7,9,"), std::string::npos) << insp;
  EXPECT_NE(insp.find("\n13,15,"), std::string::npos) << insp;
}

TEST_F(GrindingE2E, ReportRunsEveryEstimatorAgainstTheTruth) {
  ASSERT_EQ(rc_, 0) << log_;
  const json& a = results_["tests"]["grinding/series-a"];
  ASSERT_EQ(a["status"], "ok") << a.dump(2).substr(0, 2000);
  EXPECT_EQ(a["cycles"], 14);
  const YAML::Node truth = YAML::LoadFile((campaign_ / "truth.yaml").string());
  const YAML::Node pc = truth["tests"]["grinding/series-a"]["per_cycle"];
  const double ds_true = pc["ds_mm"][13].as<double>();
  for (const auto& info : g::kGrindingEstimators) {
    const json& e = a["estimators"][info.name];
    ASSERT_TRUE(e.contains("per_cycle")) << info.name << ": " << e.dump();
    EXPECT_TRUE(e["nees_per_dof"].is_number()) << info.name;
    EXPECT_EQ(e["steps"], 14 * 121);
    const double ds = e["per_cycle"]["ds_mm"][13].get<double>();
    const double s3 = e["per_cycle"]["ds_3sigma_mm"][13].get<double>();
    EXPECT_NEAR(e["ds_final_error_vs_truth_um"].get<double>(), (ds - ds_true) * 1e3, 1e-9);
    if (info.uses_ds) {
      // With the inspected d_s the wheel is tracked within its band; a few um at most.
      EXPECT_LT(std::abs(ds - ds_true), s3) << info.name;
      EXPECT_LT(std::abs(ds - ds_true), 0.005) << info.name;
      EXPECT_TRUE(e["nis_end_per_dof"].is_number());
    } else {
      EXPECT_TRUE(e["nis_end_per_dof"].is_null());
    }
    // The trajectory beside results.json: one row per instant (sum of n_i + 1) and a header.
    EXPECT_EQ(count_lines(report_ / e["trajectory_csv"].get<std::string>()), 14 * 121 + 1);
    EXPECT_EQ(e["trajectory_csv"], "grinding/series-a/" + std::string(info.name) + ".csv");
    // Fast-only NIS near 1: the synthesized noise is the filter's R.
    EXPECT_NEAR(e["nis_fast_per_dof"].get<double>(), 1.0, 0.15) << info.name;
  }
  // 002 table I: in-process only, d_s is not observable; with R_a, R0 is.
  EXPECT_EQ(a["estimators"]["multirate-ekf-x-inprocess"]["observability_rank"], 2);
  EXPECT_EQ(a["estimators"]["multirate-ekf-x"]["observability_rank"], 3);
  EXPECT_EQ(a["estimators"]["multirate-ekf-xr-inprocess"]["observability_rank"], 3);
  EXPECT_EQ(a["estimators"]["multirate-ekf-xr"]["observability_rank"], 4);
  EXPECT_LT(
      std::abs(a["estimators"]["multirate-ekf-xr"]["R0_final_error_vs_truth_um"].get<double>()),
      0.15);
  // The truth comparison: d_s of every id and R0 of the xr ids, per test.
  int rows = 0;
  for (const auto& row : results_["truth_comparison"]) {
    if (row["source"] == "grinding/series-a") ++rows;
  }
  EXPECT_EQ(rows, 4 + 2);
  EXPECT_EQ(results_["tests"]["grinding/series-b"]["status"], "ok");
  EXPECT_TRUE(results_["settings"]["grinding"]["tests"].contains("grinding/series-a"));
  // The report section and its figures.
  const std::string html = read_text(report_ / "index.html");
  EXPECT_NE(html.find("<section id=\"grinding\">"), std::string::npos);
  EXPECT_TRUE(fs::exists(report_ / "figures/grinding-grinding-series-a-ds.svg"));
  EXPECT_TRUE(fs::exists(report_ / "figures/grinding-grinding-series-a-r0.svg"));
}

TEST_F(GrindingE2E, ResultsValidateAgainstTheSchema) {
  ASSERT_EQ(rc_, 0) << log_;
  const auto check = chatterlab::testing::check_results_schema(report_ / "results.json");
  EXPECT_TRUE(check.valid) << check.output;
}

TEST(GrindingSynth, SpecErrorsNameTheKey) {
  const auto error = [](const std::string& section) {
    TempDir d;
    try {
      synthesize_campaign(
          d.write("spec.yaml", "format: chatterlab-synth/1\nname: x\ngrinding:\n" + section),
          d.path() / "out");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error("  tests: [{name: a, cycles: 0}]\n"),
            "spec.yaml: key 'grinding.tests[0].cycles' must be a whole number >= 1");
  EXPECT_EQ(error("  tests: []\n"),
            "spec.yaml: key 'grinding.tests' must be a non-empty list of {name, cycles, ...}");
  EXPECT_EQ(error("  tests: [{name: a, cycles: 5, late: [[4, 3]]}]\n"),
            "spec.yaml: key 'grinding.tests[0].late' [4, 3]: needs 1 <= cycle <= cycles and "
            "available_cycle >= cycle");
  EXPECT_EQ(
      error("  tests: [{name: a, cycles: 5, dressings: [{before_cycle: 6, depth_mm: 0.01}]}]\n"),
      "spec.yaml: key 'grinding.tests[0].dressings[0].before_cycle' must be in 2..5");
  EXPECT_EQ(error("  model: {G1: -1}\n  tests: [{name: a}]\n"),
            "spec.yaml: key 'grinding.model.G1' must be > 0");
}

}  // namespace
}  // namespace chatterlab::app
