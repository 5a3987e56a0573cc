// The identification sequence end to end (docs/identification.md): campaigns written by
// `chatterlab synth` with the hammer test at rest differing from the cut's modal parameters as
// in 000 sec. 5.1, unequal teeth (000 table 5.2), runout, 5e-7 m noise and an offset angle drawn
// from the seed, through the pipeline; the identified values against truth.yaml.
//
// Acceptance: offset within 0.5 deg (modulo the tooth pitch: the tooth labels follow the
// offset), m and k within 2 %, c within 10 % in every run; the per-tooth coefficients after 0.2 s
// of data within 2 % as the median over the seeds, and within 4 % in every run. The coefficient
// error depends on the noise realisation: over seeds 1-30 its median is 1.0-1.3 %, its 90th
// percentile 1.8-2.5 % and its largest value 3.5 %; all four coefficients are within 2 % in 21
// of the 30 (docs/identification.md, "Accuracy over noise realisations").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "app/core/campaign.h"
#include "app/kinds/cut/cut_kind.h"
#include "app/pipeline/pipeline.h"
#include "app/report/truth.h"
#include "app/synth/synth.h"
#include "tests/support/record_property.h"
#include "tests/support/synth_spec.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::SynthSpecText;
using chatterlab::testing::TempDir;

constexpr double kOffsetToleranceDeg = 0.5;
constexpr double kCoefficientTolerance = 0.02;    // median over the seeds; K / k too
constexpr double kCoefficientBoundPerRun = 0.04;  // each run
constexpr double kMassStiffnessTolerance = 0.02;
constexpr double kDampingTolerance = 0.10;

// Tap tests at the hammer values of 000 sec. 5.1, a three-feed dyno group, one constant-depth
// cut of 0.35 s (20 settling revolutions, then 0.2 s of data) with no offset given.
std::string spec(int seed, const std::string& cut_tests,
                 const std::string& cut_modal = SynthSpecText{}.cut_modal,
                 const std::string& cut_coefficients = SynthSpecText{}.cut_coefficients) {
  SynthSpecText t;
  t.name = "ident-" + std::to_string(seed);
  t.seed = seed;
  t.cut_modal = cut_modal;
  t.cut_coefficients = cut_coefficients;
  t.cut_tests = cut_tests;
  return t.text();
}

CampaignResults synth_and_run(const TempDir& d, const std::string& spec_text,
                              const std::string& estimation_yaml) {
  const auto spec_file = d.write("spec.yaml", spec_text);
  const auto campaign = d.path() / "campaign";
  synthesize_campaign(spec_file, campaign);
  if (!estimation_yaml.empty()) {
    std::ofstream(campaign / "campaign.yaml", std::ios::app) << estimation_yaml;
  }
  return run_campaign(load_campaign(campaign), {});
}

// quantity -> |error| in percent, from the truth comparison of one test.
std::map<std::string, double> errors_of(const TruthComparison& c, const std::string& test) {
  std::map<std::string, double> e;
  for (const auto& row : c.rows) {
    if (row.source == test) e[row.quantity] = std::abs(row.error_pct);
  }
  return e;
}

int joint_intervals = 0, joint_covered = 0;

// One seed: the per-run acceptance; returns the four coefficients' errors in percent.
std::vector<double> identify_one(int seed) {
  std::vector<double> coefficient_errors;
  TempDir d;
  const CampaignResults r = synth_and_run(
      d, spec(seed, "    - {name: constant, axial_depth_mm: 1.0, duration_s: 0.35}\n"),
      "estimation: {repeat_runs: 0}\n");
  const TestOutcome* cut = nullptr;
  for (const auto& t : r.tests) {
    if (t.spec->id == "cuts/constant") cut = &t;
  }
  EXPECT_NE(cut, nullptr);
  if (cut == nullptr) return coefficient_errors;
  EXPECT_TRUE(cut->status.ok()) << cut->status.message;
  if (!cut->status.ok()) return coefficient_errors;
  const CutEstimation& e = cut->result_as<CutOutcome>()->estimation;
  EXPECT_TRUE(e.summary.ok()) << e.summary.message;
  if (!e.summary.ok()) return coefficient_errors;
  EXPECT_EQ(identification_source(r), cut);

  const TruthComparison truth = compare_with_truth(r);
  const auto err = errors_of(truth, "cuts/constant");
  EXPECT_TRUE(err.count("offset_angle_deg"));
  const TruthRow* offset_row = nullptr;
  for (const auto& row : truth.rows) {
    if (row.source == "cuts/constant" && row.quantity == "offset_angle_deg") offset_row = &row;
  }
  const double offset_error_deg = std::abs(offset_row->estimate - offset_row->truth);
  const std::string s = "seed" + std::to_string(seed) + "_";
  chatterlab::testing::record_and_print(s + "truth_offset_deg", offset_row->truth);
  chatterlab::testing::record_and_print(s + "offset_error_deg", offset_error_deg);
  chatterlab::testing::record_and_print(s + "passes", static_cast<double>(e.passes.size()));
  EXPECT_LT(offset_error_deg, kOffsetToleranceDeg);
  for (const char* k :
       {"Kt1_N_m2", "Kr1_N_m2", "Kt2_N_m2", "Kr2_N_m2", "m_kg", "k_N_m", "c_kg_s"}) {
    const std::string q = std::string("identified.") + k;
    EXPECT_TRUE(err.count(q)) << q;
    if (!err.count(q)) return coefficient_errors;
    chatterlab::testing::record_and_print(s + k + "_error_pct", err.at(q));
  }
  for (const char* k : {"Kt1_N_m2", "Kr1_N_m2", "Kt2_N_m2", "Kr2_N_m2"}) {
    coefficient_errors.push_back(err.at(std::string("identified.") + k));
    EXPECT_LT(coefficient_errors.back(), 100 * kCoefficientBoundPerRun) << k;
  }
  EXPECT_LT(err.at("identified.m_kg"), 100 * kMassStiffnessTolerance);
  EXPECT_LT(err.at("identified.k_N_m"), 100 * kMassStiffnessTolerance);
  EXPECT_LT(err.at("identified.c_kg_s"), 100 * kDampingTolerance);
  // The scale-free combinations (docs/identification.md, "Scale").
  chatterlab::testing::record_and_print(s + "fn_error_pct", err.at("identified.fn_hz"));
  chatterlab::testing::record_and_print(s + "zeta_error_pct", err.at("identified.zeta"));
  EXPECT_LT(err.at("identified.fn_hz"), 100 * kMassStiffnessTolerance);
  EXPECT_LT(err.at("identified.zeta"), 100 * kDampingTolerance);
  for (const char* k : {"Kt1", "Kr1", "Kt2", "Kr2"}) {
    const std::string q = std::string("identified.") + k + "_over_k_per_m";
    chatterlab::testing::record_and_print(s + k + "_over_k_error_pct", err.at(q));
    EXPECT_LT(err.at(q), 100 * kCoefficientBoundPerRun) << q;
  }
  // The hammer values are far from the cut's (c by -40 %): the sequence moved them.
  EXPECT_GT(e.passes.size(), 1u);

  // The joint estimate from the sequence's values (issue 13): the same goals, and its 95 %
  // intervals contain the truth of the values it identifies, pooled over the seeds
  // (joint_covered / joint_intervals; estimate_joint_test measures the coverage on 50 cuts).
  EXPECT_TRUE(e.joint.summary.ok()) << e.joint.summary.message;
  if (e.joint.summary.ok()) {
    std::map<std::string, const TruthRow*> joint_rows;
    for (const auto& row : truth.rows) {
      if (row.source == "cuts/constant" && row.quantity.rfind("joint.", 0) == 0) {
        joint_rows[row.quantity.substr(6)] = &row;
      }
    }
    EXPECT_TRUE(joint_rows.count("offset_deg") && joint_rows.count("c_kg_s"));
    if (!joint_rows.count("offset_deg") || !joint_rows.count("c_kg_s")) return coefficient_errors;
    const double joint_offset_error =
        std::abs(joint_rows["offset_deg"]->estimate - joint_rows["offset_deg"]->truth);
    chatterlab::testing::record_and_print(s + "joint_offset_error_deg", joint_offset_error);
    chatterlab::testing::record_and_print(s + "joint_c_error_pct", joint_rows["c_kg_s"]->error_pct);
    EXPECT_LT(joint_offset_error, kOffsetToleranceDeg);
    EXPECT_LT(std::abs(joint_rows["c_kg_s"]->error_pct), 100 * kDampingTolerance);
    // The scale-free values do not depend on the held k (the sequence's scale).
    for (const auto& [key, iv] : keyed_intervals(e.joint)) {
      if (key.find("_over_k") == std::string::npos && key != "fn_hz" && key != "zeta") continue;
      EXPECT_TRUE(joint_rows.count(key)) << key;
      if (!joint_rows.count(key)) continue;
      ++joint_intervals;
      joint_covered += iv->contains(joint_rows[key]->truth);
    }
  }

  // Every variant ran, with 000 sec. 4.5's observability ranks at the operating point (an
  // unscented variant's are its model's, the EKF twin's).
  const std::map<std::string, std::pair<int, int>> ranks = {
      {"ekf-modal-x", {3, 5}},          {"ekf-modal-xy", {6, 7}},
      {"ekf-modal-xy-mk", {6, 6}},      {"ekf-modal-xy-mc", {6, 6}},
      {"ekf-coeff-xy", {6, 6}},         {"ekf-coeff-xy-per-tooth", {6, 6}},
      {"ukf-modal-x", {3, 5}},          {"ukf-modal-xy", {6, 7}},
      {"ukf-modal-xy-mk", {6, 6}},      {"ukf-modal-xy-mc", {6, 6}},
      {"ukf-coeff-xy", {6, 6}},         {"ukf-coeff-xy-per-tooth", {6, 6}},
      {"ekf-coeff-xy-feedback", {6, 6}}};
  EXPECT_EQ(e.variants.size(), ranks.size());
  for (const auto& v : e.variants) {
    EXPECT_TRUE(v.run.summary.ok()) << v.run.estimator << ": " << v.run.summary.message;
    EXPECT_TRUE(v.observability_status.ok()) << v.observability_status.message;
    EXPECT_EQ(v.observability.rank, ranks.at(v.run.estimator).first) << v.run.estimator;
    EXPECT_EQ(v.observability.states, ranks.at(v.run.estimator).second) << v.run.estimator;
    EXPECT_GT(v.run.steps, 390000) << v.run.estimator;  // 0.2 s at 5e-7 s, less one delay
  }
  return coefficient_errors;
}

// Seeds 1-8 (the first eight of the 30 measured above, none chosen).
TEST(Identification, RecoversTruthFromSynthCutsOverSeeds) {
  std::vector<std::vector<double>> per_coefficient(4);
  for (int seed = 1; seed <= 8; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const std::vector<double> errors = identify_one(seed);
    ASSERT_EQ(errors.size(), 4u);
    for (std::size_t k = 0; k < 4; ++k) per_coefficient[k].push_back(errors[k]);
  }
  const char* names[] = {"Kt1_N_m2", "Kr1_N_m2", "Kt2_N_m2", "Kr2_N_m2"};
  for (std::size_t k = 0; k < 4; ++k) {
    std::vector<double> v = per_coefficient[k];
    std::sort(v.begin(), v.end());
    const double median = 0.5 * (v[3] + v[4]);
    chatterlab::testing::record_and_print(std::string("median_") + names[k] + "_error_pct", median);
    EXPECT_LT(median, 100 * kCoefficientTolerance) << names[k];
  }
  // 8 seeds x 6 scale-free values: at 95 % coverage, 41 or more inside with 98 % probability.
  chatterlab::testing::record_and_print("joint_scale_free_covered", joint_covered);
  EXPECT_EQ(joint_intervals, 48);
  EXPECT_GE(joint_covered, 41);
}

// docs/identification.md, "Scale": a tool whose in-cut m, k lie 7 % below the hammer test's.
// Deflections cannot fix the common scale of m, c, k and the coefficients, so the identified
// values may be off by a common factor (here m +4.4 %, k alike); the scale-free fn, zeta and
// K / k still hold (fn 0.3 %, K / k 2 %, zeta 10 %), as does the offset (0.5 deg).
TEST(IdentificationScale, ScaleFreeValuesHoldWhenTheHammerScaleIsOff) {
  TempDir d;
  const CampaignResults r =
      synth_and_run(d,
                    spec(41, "    - {name: constant, axial_depth_mm: 0.8, duration_s: 0.35}\n",
                         "{m_kg: 0.030, c_kg_s: 18.0, k_N_m: 9.5e5}",
                         "{Kt_N_m2: [7.0e8, 9.0e8], Kr_N_m2: [2.5e8, 3.5e8]}"),
                    "estimation: {repeat_runs: 0}\n");
  std::map<std::string, double> signed_err;
  double offset_error_deg = 1e9;
  for (const auto& row : compare_with_truth(r).rows) {
    if (row.source != "cuts/constant") continue;
    signed_err[row.quantity] = row.error_pct;
    if (row.quantity == "offset_angle_deg") offset_error_deg = std::abs(row.estimate - row.truth);
  }
  ASSERT_TRUE(signed_err.count("identified.m_kg"));
  EXPECT_LT(offset_error_deg, kOffsetToleranceDeg);
  EXPECT_LT(std::abs(signed_err.at("identified.fn_hz")), 0.3);
  EXPECT_LT(std::abs(signed_err.at("identified.zeta")), 100 * kDampingTolerance);
  const double scale = signed_err.at("identified.m_kg");
  chatterlab::testing::record_and_print("common_scale_error_pct", scale);
  for (const char* k : {"Kt1", "Kr1", "Kt2", "Kr2"}) {
    const std::string q = std::string("identified.") + k;
    EXPECT_LT(std::abs(signed_err.at(q + "_over_k_per_m")), 100 * kCoefficientTolerance) << q;
  }
}

// A bad campaign.yaml estimation block skips the identification of every cut test with the key
// named, while the rest of the cut analysis (offset angle) still runs.
TEST(IdentificationInput, BadEstimationBlockSkipsOnlyTheEstimation) {
  TempDir d;
  const CampaignResults r =
      synth_and_run(d, spec(5, "    - {name: constant, axial_depth_mm: 1.0, duration_s: 0.35}\n"),
                    "estimation: {window_s: -0.2, repeat_runs: 1}\n");
  for (const auto& t : r.tests) {
    if (t.spec->id != "cuts/constant") continue;
    ASSERT_TRUE(t.status.ok()) << t.status.message;
    EXPECT_TRUE(t.result_as<CutOutcome>()->offset_status.ok());
    const StepSummary& s = t.result_as<CutOutcome>()->estimation.summary;
    EXPECT_FALSE(s.ok());
    EXPECT_NE(s.message.find("estimation.window_s"), std::string::npos) << s.message;
    EXPECT_NE(s.message.find("estimation.repeat_runs"), std::string::npos) << s.message;
  }
  EXPECT_EQ(identification_source(r), nullptr);
}

// A cut too short for the window after settling (23.75 revolutions: enough for the offset
// angle's 23, not for 20 settling revolutions plus four): skipped with the reason.
TEST(IdentificationInput, ShortCutSaysWhy) {
  TempDir d;
  const CampaignResults r =
      synth_and_run(d, spec(6, "    - {name: short, axial_depth_mm: 1.0, duration_s: 0.095}\n"),
                    "estimation: {repeat_runs: 0}\n");
  for (const auto& t : r.tests) {
    if (t.spec->id != "cuts/short") continue;
    ASSERT_TRUE(t.status.ok()) << t.status.message;
    EXPECT_TRUE(t.result_as<CutOutcome>()->offset_status.ok())
        << t.result_as<CutOutcome>()->offset_status.message;
    const StepSummary& s = t.result_as<CutOutcome>()->estimation.summary;
    EXPECT_FALSE(s.ok());
    EXPECT_NE(s.message.find("cuts/short/test.yaml: estimation window"), std::string::npos)
        << s.message;
    EXPECT_NE(s.message.find("four revolutions"), std::string::npos) << s.message;
  }
}

}  // namespace
}  // namespace chatterlab::app
