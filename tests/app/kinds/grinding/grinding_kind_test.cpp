// Kind grinding (EXPERIMENT_FORMAT section 7, app/kinds/grinding): test.yaml problems name their
// key; a campaign written by hand in the contract's format (a CSV with a `t` column, calibrated
// power and D_w, inspections with missing fields, a late row and an uninspected cycle, a
// dressing; a second inspections file without the available_cycle column) runs through
// run_campaign; its results.json block has the contract's keys; write_files writes one
// trajectory row per filter instant (sum of n_i + 1); bad series are skipped naming the file or
// key.
#include "app/kinds/grinding/grinding_kind.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>

#include "analysis/grinding/grinding_model.h"
#include "app/core/campaign.h"
#include "app/pipeline/pipeline.h"
#include "app/pipeline/registry.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace g = chatterlab::grinding;
using chatterlab::testing::TempDir;
using nlohmann::json;

const char* kCampaign = "format: chatterlab-campaign/1\nname: grinding-test\n";

const char* kModel =
    "model:\n"
    "  dw_mm: 70\n  ds0_mm: 50\n  vs_m_s: 37\n  vw_m_s: 0.533\n  tau_s: 1.5\n"
    "  Ks_W_s_mm: 2380\n  s0: 49.6\n  s1_per_mm2: 0.08\n  gamma: 0.2\n  Rg_um: 0.7\n"
    "  R0_um: 3.0\n  V0_mm2: 300\n  rm_um: 2.4\n  r0: 1.0\n  G1: 13\n  g: 0.9\n";
const char* kNoise =
    "noise: {power_sd: 100, Dw_sd_mm: 0.01, ds_sd_mm: 0.001, Ra_sd_um: 0.01, roundness_sd_um: "
    "0.1}\n";
const char* kFilter =
    "filter:\n"
    "  P0: {Vw_mm2: 10, v_mm_s: 1.0e-7, ds_mm: 1.0e-6, R0_um: 0.01}\n"
    "  Q: {Vw_mm2: 0.04, v_mm_s: 4.0e-11, ds_mm: 4.0e-9, R0_um: 1.6e-7}\n";

std::string test_yaml(const std::string& extra = "", const std::string& model = kModel,
                      const std::string& filter = kFilter) {
  return "kind: grinding\nsample_rate_hz: 50\ndata: {file: fast.csv}\n"
         "channels:\n  power: {scale: 1000.0, offset: -850.0}\n  Dw_mm: {scale: 0.001}\n"
         "inspections: {file: inspections.csv}\n" +
         model + kNoise + filter + extra;
}

// Three cycles of 40 fast steps (n_i = 40, 41 rows each) of the noise-free model at the
// format's example parameters, the wheel dressed by 0.01 mm before cycle 3: columns t (s),
// cycle, u_mm_s, power in volts (P = 1000 V - 850), D_w in um.
constexpr int kCycles = 3, kN = 40;
std::string fast_csv(double* ds_end = nullptr) {
  g::GrindingParameters p;
  p.vw_m_s = 0.533;
  p.rm_um = 2.4;
  p.r0 = 1.0;
  const double T = 0.02;
  std::ostringstream o;
  o.precision(12);
  o << "t,cycle,u_mm_s,power,Dw_mm\n";
  g::ProcessState X(0, 0, 50, 3.0);
  int row = 0;
  for (int c = 1; c <= kCycles; ++c) {
    X[g::kV] = 0;
    if (c == 3) {
      X[g::kVw] = 0;
      X[g::kDs] -= 0.01;
    }
    for (int j = 0; j <= kN; ++j, ++row) {
      const double u = j < 25 ? 0.0254 : j < 35 ? 0.002 : 0.0;
      const g::Outputs y = g::outputs(X, p);
      o << row * T << ',' << c << ',' << u << ',' << (y[g::kPower] + 850.0) / 1000.0 << ','
        << y[g::kDw] * 1000.0 << '\n';
      if (j < kN) X = g::euler_step(X, u, T, p);
    }
    if (ds_end && c == 1) *ds_end = X[g::kDs];
  }
  return o.str();
}

// Writes a campaign with one test `g` and returns its folder.
std::filesystem::path campaign(const TempDir& d, const std::string& yaml,
                               const std::string& inspections) {
  d.write("campaign.yaml", kCampaign);
  d.write("g/test.yaml", yaml);
  d.write("g/fast.csv", fast_csv());
  d.write("g/inspections.csv", inspections);
  return d.path();
}

// The errors of test `g` after loading (and checking its record, as run_campaign does).
std::vector<std::string> errors_of(
    const TempDir& d, const std::string& yaml,
    const std::string& inspections = "cycle,ds_mm,Ra_um,roundness_um\n") {
  CampaignSpec c = load_campaign(campaign(d, yaml, inspections));
  EXPECT_EQ(c.tests.size(), 1u);
  if (c.tests.empty()) return {};
  check_signals(c.tests[0]);
  return c.tests[0].errors;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(GrindingKind, AValidTestHasNoProblem) {
  TempDir d;
  EXPECT_TRUE(errors_of(d, test_yaml()).empty()) << errors_of(d, test_yaml()).front();
}

// The inspections table is read before computing (GrindingKind::check_files, which `validate`
// and `report` both run): a table the step would refuse makes the test unusable in both.
TEST(GrindingKind, ABadInspectionsTableIsFoundBeforeComputing) {
  TempDir d;
  EXPECT_EQ(errors_of(d, test_yaml(), "ds_mm\n49.9\n"),
            std::vector<std::string>{"g/inspections.csv: the header has no column 'cycle'"});
  TempDir e;
  EXPECT_EQ(errors_of(e, test_yaml(), "cycle,ds_mm\n1,abc\n"),
            std::vector<std::string>{"g/inspections.csv: line 2, column ds_mm: 'abc' is not a "
                                     "number (empty or nan: not measured)"});
}

TEST(GrindingKind, EveryParseProblemNamesItsKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {replaced(test_yaml(), "  gamma: 0.2\n", ""), "g/test.yaml: key 'model.gamma' is missing"},
      {test_yaml("", ""),
       "g/test.yaml: key 'model' is missing: it must be a mapping of the 002 model parameters"},
      {replaced(test_yaml(), "tau_s: 1.5", "tau_s: 0"),
       "g/test.yaml: key 'model.tau_s' = 0: must be a number > 0"},
      {replaced(test_yaml(), "power_sd: 100", "power_sd: -1"),
       "g/test.yaml: key 'noise.power_sd' = -1: must be a number > 0"},
      {replaced(test_yaml(), "Ra_sd_um: 0.01, ", ""),
       "g/test.yaml: key 'noise.Ra_sd_um' is missing"},
      {test_yaml("", kModel,
                 "filter:\n  P0: {Vw_mm2: 10, v_mm_s: 1.0e-7, ds_mm: 1.0e-6, R0_um: 0.01}\n"),
       "g/test.yaml: key 'filter.Q' is missing: it must be a mapping {Vw_mm2, v_mm_s, ds_mm, "
       "R0_um} of variances"},
      // P0 = 0 is a state known exactly; a negative variance is an error.
      {replaced(test_yaml(), "ds_mm: 1.0e-6", "ds_mm: -1.0e-6"),
       "g/test.yaml: key 'filter.P0.ds_mm' = -1.00000e-06: must be a number >= 0"},
      {test_yaml("dressings: [{before_cycle: 1, depth_mm: 0.04}]\n"),
       "g/test.yaml: key 'dressings[0].before_cycle' = 1: must be a number >= 2"},
      {test_yaml("dressings: [{before_cycle: 2.5, depth_mm: 0.04}]\n"),
       "g/test.yaml: key 'dressings[0].before_cycle' = 2.5: must be a whole number"},
      {test_yaml("dressings: {before_cycle: 2}\n"),
       "g/test.yaml: key 'dressings' must be a list of {before_cycle, depth_mm}"},
      {test_yaml("dress_sd_mm: -0.1\n"),
       "g/test.yaml: key 'dress_sd_mm' = -0.1: must be a number >= 0"},
      {test_yaml("filter2: 1\n", kModel, kFilter + std::string("  R0_cycle_var_um2: -1\n")),
       "g/test.yaml: key 'filter.R0_cycle_var_um2' = -1: must be a number >= 0"},
      {replaced(test_yaml(), "inspections: {file: inspections.csv}",
                "inspections: {file: nope.csv}"),
       "g/test.yaml: key 'inspections.file' 'nope.csv': file not found"},
      {replaced(test_yaml(), "inspections: {file: inspections.csv}",
                "inspections: {file: ../../outside.csv}"),
       "g/test.yaml: key 'inspections.file' '../../outside.csv': must lie inside the campaign "
       "folder"},
  };
  for (const auto& [yaml, message] : cases) {
    TempDir d;
    const auto errors = errors_of(d, yaml);
    ASSERT_EQ(errors.size(), 1u) << message
                                 << (errors.empty()
                                         ? ""
                                         : "\nfirst: " + errors[0] + "\nlast: " + errors.back());
    EXPECT_EQ(errors[0], message);
  }
}

TEST(GrindingKind, DefaultsAndOptionalKeys) {
  TempDir d;
  CampaignSpec c = load_campaign(campaign(d, test_yaml(), "cycle\n"));
  ASSERT_EQ(c.tests.size(), 1u);
  const auto& s = c.tests[0].kind_spec<GrindingSpec>();
  EXPECT_EQ(s.model.delta, 1.0);  // the contract's default
  EXPECT_EQ(s.filter.R0_cycle_var_um2, 0.0);
  EXPECT_EQ(s.filter.dress_sd_mm, 0.0);
  EXPECT_TRUE(s.dressings.empty());
  EXPECT_EQ(s.model.vw_m_s, 0.533);
  EXPECT_EQ(*s.roundness_sd_um, 0.1);
  // Without the optional model keys the roundness terms are absent, not zero.
  std::string yaml = test_yaml();
  for (const char* k : {"  vw_m_s: 0.533\n", "  rm_um: 2.4\n", "  r0: 1.0\n"})
    yaml = replaced(yaml, k, "");
  TempDir d2;
  CampaignSpec c2 = load_campaign(campaign(d2, yaml, "cycle\n"));
  ASSERT_TRUE(c2.tests[0].usable()) << c2.tests[0].errors.front();
  EXPECT_TRUE(std::isnan(c2.tests[0].kind_spec<GrindingSpec>().model.r0));
}

TEST(GrindingKind, RecordWithoutAChannelIsUnusable) {
  TempDir d;
  CampaignSpec c = load_campaign(campaign(d, test_yaml(), "cycle\n"));
  d.write("g/fast.csv", "cycle,u_mm_s,power\n1,0,0.85\n1,0,0.85\n");
  check_signals(c.tests[0]);
  ASSERT_EQ(c.tests[0].errors.size(), 1u);
  EXPECT_EQ(c.tests[0].errors[0],
            "g/fast.csv: channel 'Dw_mm' is required for a grinding test (channels: cycle, "
            "u_mm_s, power)");
}

TEST(GrindingKind, InspectionsFileRules) {
  TempDir d;
  std::vector<std::string> warnings;
  const auto read = [&](const std::string& text) {
    warnings.clear();
    return read_inspections(d.write("i.csv", text), "g/i.csv", warnings);
  };
  const auto ins = read(
      "cycle,available_cycle,ds_mm,Ra_um,roundness_um\n"
      "3,5,49.9,,NaN\n"
      "1,1,nan,0.8,2.5\r\n"
      "\n");
  ASSERT_EQ(ins.size(), 2u);
  EXPECT_EQ(ins[0].cycle, 1);  // sorted by cycle
  EXPECT_TRUE(std::isnan(ins[0].ds_mm));
  EXPECT_EQ(ins[0].Ra_um, 0.8);
  EXPECT_EQ(ins[1].available_cycle, 5);
  EXPECT_TRUE(std::isnan(ins[1].Ra_um));
  EXPECT_TRUE(std::isnan(ins[1].roundness_um));
  const auto on_time = read("cycle,ds_mm\n2,49.9\n");
  EXPECT_EQ(on_time[0].available_cycle, 2);  // no available_cycle column: on time
  const auto error = [&](const std::string& text) {
    try {
      read(text);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error("ds_mm\n49.9\n"), "g/i.csv: the header has no column 'cycle'");
  // A lab's own column is read past with a warning; an Excel byte-order mark is no column name.
  const auto extra = read(std::string("\xEF\xBB\xBF") + "cycle,operator,ds_mm\n1,Ann,49.9\n");
  ASSERT_EQ(extra.size(), 1u);
  EXPECT_EQ(extra[0].ds_mm, 49.9);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "g/i.csv: column 'operator' is not one of cycle, available_cycle, ds_mm, Ra_um, "
            "roundness_um and is ignored");
  // "Never" (format section 7: a result available after the last cycle is never used).
  const auto never = read("cycle,available_cycle,ds_mm\n1,inf,49.9\n2,1e10,49.8\n3,,49.7\n");
  EXPECT_EQ(never[0].available_cycle, std::numeric_limits<int>::max());
  EXPECT_EQ(never[1].available_cycle, std::numeric_limits<int>::max());
  EXPECT_EQ(never[2].available_cycle, 3);
  EXPECT_EQ(error("cycle,ds_mm\n1,abc\n"),
            "g/i.csv: line 2, column ds_mm: 'abc' is not a number (empty or nan: not measured)");
  EXPECT_EQ(error("cycle,ds_mm\n1.5,49\n"),
            "g/i.csv: line 2, column cycle: must be a whole cycle number");
  EXPECT_EQ(error("cycle,ds_mm\n1\n"), "g/i.csv: line 2 has 1 fields, the header 2");
}

// A series still being acquired: an inspection row and a dressing past the record's last cycle
// are left out with a warning naming them, and the test runs.
TEST(GrindingKind, InspectionsAndDressingsPastTheRecordAreLeftOut) {
  TempDir d;
  campaign(d, test_yaml("dressings:\n  - {before_cycle: 9, depth_mm: 0.010}\n"),
           "cycle,ds_mm\n1,49.99\n7,49.9\n");
  CampaignResults r = run_campaign(load_campaign(d.path()), {});
  ASSERT_EQ(r.tests.size(), 1u);
  const TestOutcome& t = r.tests[0];
  ASSERT_TRUE(t.status.ok()) << t.status.message;
  ASSERT_EQ(t.warnings.size(), 2u);
  EXPECT_NE(t.warnings[0].find("the dressing before cycle 9 is after the record's last cycle (3)"),
            std::string::npos)
      << t.warnings[0];
  EXPECT_EQ(
      t.warnings[1],
      "g/inspections.csv: 1 row(s) for cycles after the record's last cycle (3) are not used");
  EXPECT_EQ(t.result_of<GrindingResult>().inspections.size(), 1u);
}

// The hand-written campaign: cycle 1 inspected late (usable at the end of cycle 2) with d_s
// only, cycle 2 on time with R_a and roundness only, cycle 3 not inspected; dressing before 3.
const char* kInspections =
    "cycle,available_cycle,ds_mm,Ra_um,roundness_um\n"
    "1,2,49.99,nan,\n"
    "2,2,,0.8,2.5\n";

TEST(GrindingKind, HandWrittenCampaignRuns) {
  TempDir d;
  double ds1 = 0;
  fast_csv(&ds1);
  std::string insp = kInspections;
  insp = replaced(insp, "49.99", std::to_string(ds1));
  campaign(d, test_yaml("dressings:\n  - {before_cycle: 3, depth_mm: 0.010}\ndress_sd_mm: 0.002\n"),
           insp);
  // A second test whose inspections file has no available_cycle column (all on time).
  d.write("h/test.yaml", test_yaml());
  d.write("h/fast.csv", fast_csv());
  d.write("h/inspections.csv", "cycle,ds_mm,Ra_um,roundness_um\n2," + std::to_string(ds1) + ",,\n");
  PipelineOptions o;
  o.jobs = 2;
  CampaignResults r = run_campaign(load_campaign(d.path()), o);
  ASSERT_EQ(r.tests.size(), 2u);
  const GrindingKind kind;
  for (const auto& t : r.tests) {
    ASSERT_TRUE(t.status.ok()) << t.spec->id << ": " << t.status.message;
    const json j = kind.results(t);
    EXPECT_EQ(j["cycles"], kCycles);
    ASSERT_EQ(j["estimators"].size(), 4u);
    std::size_t k = 0;
    for (const auto& [name, e] : j["estimators"].items()) {
      (void)k;
      EXPECT_EQ(e["steps"], kCycles * (kN + 1)) << name;
      EXPECT_EQ(e["trajectory_csv"], t.spec->id + "/" + name + ".csv");
      EXPECT_EQ(e["per_cycle"]["cycle"], json({1, 2, 3}));
      EXPECT_EQ(e["per_cycle"]["ds_mm"].size(), 3u);
      EXPECT_FALSE(e.contains("nees_per_dof")) << "no truth.yaml: no NEES";
      EXPECT_TRUE(e["runtime_s"].is_number());
      EXPECT_TRUE(e["nis_fast_per_dof"].is_number());
      const bool xr = name.find("-xr") != std::string::npos;
      EXPECT_EQ(e["per_cycle"].contains("R0_um"), xr) << name;
      EXPECT_EQ(e["per_cycle"].contains("Ra_pred_um"), xr) << name;
      EXPECT_EQ(e["states"].size(), xr ? 4u : 3u);
    }
    EXPECT_TRUE(j["estimators"]["multirate-ekf-x-inprocess"]["nis_end_per_dof"].is_null());
    EXPECT_TRUE(j["estimators"]["multirate-ekf-x"]["nis_end_per_dof"].is_number());
  }
  // Test g: the late d_s of cycle 1 is replayed at the end of cycle 2; the estimate at cycle 1
  // is the fast-only one (causal); the dressing removes its depth before cycle 3.
  const json g1 = kind.results(r.tests[0])["estimators"]["multirate-ekf-x"];
  EXPECT_GT(g1["replayed_steps_count"].get<long>(), 0);
  EXPECT_TRUE(kind.results(r.tests[0])["inspections"]["ds_mm"][1].is_null());
  EXPECT_EQ(kind.results(r.tests[0])["inspections"]["available_cycle"], json({2, 2}));
  const auto& ds = g1["per_cycle"]["ds_mm"];
  EXPECT_LT(ds[2].get<double>(), ds[1].get<double>() - 0.009);
  const json h1 = kind.results(r.tests[1])["estimators"]["multirate-ekf-x"];
  EXPECT_EQ(h1["replayed_steps_count"], 0);
  // The inspections files are inputs (results.json inputs_sha256): a change to one shows.
  std::set<std::string> inputs;
  for (const auto& f : r.inputs) inputs.insert(f.relative_path);
  EXPECT_TRUE(inputs.count("g/inspections.csv")) << "g/inspections.csv";
  EXPECT_TRUE(inputs.count("h/inspections.csv")) << "h/inspections.csv";
}

TEST(GrindingKind, WriteFilesWritesOneRowPerInstant) {
  TempDir d;
  campaign(d, test_yaml(), kInspections);
  CampaignResults r = run_campaign(load_campaign(d.path()), {});
  ASSERT_TRUE(r.tests[0].status.ok()) << r.tests[0].status.message;
  const GrindingKind kind;
  const auto out = d.path() / "report";
  kind.write_files(r.tests[0], out);
  for (const auto& e : g::kGrindingEstimators) {
    std::ifstream in(out / "g" / (std::string(e.name) + ".csv"));
    ASSERT_TRUE(in) << e.name;
    std::string header, line, last;
    std::getline(in, header);
    EXPECT_EQ(header, e.estimates_R0 ? "cycle,j,Vw_mm2,Vw_3sigma_mm2,v_mm_s,v_3sigma_mm_s,ds_mm,"
                                       "ds_3sigma_mm,R0_um,R0_3sigma_um"
                                     : "cycle,j,Vw_mm2,Vw_3sigma_mm2,v_mm_s,v_3sigma_mm_s,ds_mm,"
                                       "ds_3sigma_mm");
    int rows = 0;
    while (std::getline(in, line)) {
      ++rows;
      last = line;
    }
    EXPECT_EQ(rows, kCycles * (kN + 1)) << e.name;  // sum of n_i + 1
    EXPECT_EQ(last.rfind("3,40,", 0), 0u) << last;
  }
}

TEST(GrindingKind, BadSeriesAreSkippedNamingTheFileOrKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"cycle,ds_mm\n0,49.9\n", "g/inspections.csv: cycle 0 is not in 1..3"},
      {"cycle,available_cycle,ds_mm\n2,1,49.9\n",
       "g/inspections.csv: cycle 2: available_cycle 1 is before the cycle"},
  };
  for (const auto& [insp, message] : cases) {
    TempDir d;
    campaign(d, test_yaml(), insp);
    CampaignResults r = run_campaign(load_campaign(d.path()), {});
    EXPECT_FALSE(r.tests[0].status.ok());
    EXPECT_EQ(r.tests[0].failure, Failure::kInput);
    EXPECT_EQ(r.tests[0].status.message, message);
  }
  CampaignResults r;
  TempDir e;
  campaign(e, test_yaml(), kInspections);
  e.write("g/fast.csv", "cycle,u_mm_s,power,Dw_mm\n1,0,0.85,0\n1.5,0,0.85,0\n");
  r = run_campaign(load_campaign(e.path()), {});
  EXPECT_EQ(r.tests[0].status.message, "g/fast.csv: row 2: cycle 1.5 is not a whole number");
}

}  // namespace
}  // namespace chatterlab::app
