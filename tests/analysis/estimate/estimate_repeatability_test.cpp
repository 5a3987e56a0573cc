// Repeatability over randomized initial estimates (000 sec. 6.2, figs 6.19-6.20): ten runs
// from starts drawn uniformly within +-50 % of a reference, on the tests' cut
// (estimate_coeff_test.cpp's conditions).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "analysis/estimate/repeatability.h"
#include "tests/support/record_property.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab {
namespace estimate {
namespace {

using testing::table52_coefficients;
using testing::table52_modal;

void record(const std::string& key, double value) {
  chatterlab::testing::record_and_print(key, value);
}

const MeasuredCut& cut() {
  static const MeasuredCut c = testing::synthetic_cut(testing::SyntheticCutSpec{});
  return c;
}

TEST(Repeatability, PerToothCoefficientsFromStartsWithin50Percent) {
  // Reference: the truth (000 draws around its identified values). Every run must end within
  // 2 % of the truth; the spread (range / mean) is reported.
  const RepeatabilityResult r = repeat_coeff(EstimatorId::kCoeffXyPerTooth, cut(), CutSetup{},
                                             {table52_modal(), table52_coefficients()});
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  ASSERT_EQ(r.runs.size(), 10u);
  ASSERT_EQ(r.keys, (std::vector<std::string>{"Kt1_N_m2", "Kr1_N_m2", "Kt2_N_m2", "Kr2_N_m2"}));
  const std::vector<double> truth = {2.483e8, 2.196e8, 6.641e9, 4.154e9};
  double widest_draw = 0.0;
  for (Eigen::Index j = 0; j < 4; ++j) {
    const std::string k = r.keys[static_cast<std::size_t>(j)];
    record(k + "_mean_error_pct", 100.0 * (r.mean[j] / truth[static_cast<std::size_t>(j)] - 1.0));
    record(k + "_std_pct", 100.0 * r.std_dev[j] / r.mean[j]);
    record(k + "_range_pct", 100.0 * r.range[j] / r.mean[j]);
    for (Eigen::Index run = 0; run < 10; ++run) {
      const double t = truth[static_cast<std::size_t>(j)];
      EXPECT_NEAR(r.finals(run, j) / t, 1.0, 0.02) << k << " run " << run + 1;
      const double draw = r.initial(run, j) / t - 1.0;
      EXPECT_LE(std::abs(draw), 0.5);
      widest_draw = std::max(widest_draw, std::abs(draw));
    }
    EXPECT_LT(r.range[j] / r.mean[j], 0.01);  // the runs agree to within 1 %
  }
  record("widest_draw_pct", 100.0 * widest_draw);
  EXPECT_GT(widest_draw, 0.3);                      // the draws do spread over the interval
  EXPECT_GT(r.runs[0].history.time_s.size(), 100);  // histories for figs 6.19-6.20
}

TEST(Repeatability, ModalMassAndStiffness) {
  // ekf-modal-xy-mk with the true damping held: m and k from +-50 % starts.
  RepeatabilityOptions o;
  o.runs = 5;
  const RepeatabilityResult r = repeat_modal(EstimatorId::kModalXyMk, cut(), CutSetup{},
                                             {table52_coefficients(), table52_modal()}, {}, o);
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  ASSERT_EQ(r.keys, (std::vector<std::string>{"m_kg", "k_N_m"}));
  for (Eigen::Index j = 0; j < 2; ++j) {
    record(r.keys[static_cast<std::size_t>(j)] + "_range_pct", 100.0 * r.range[j] / r.mean[j]);
    EXPECT_LT(r.range[j] / r.mean[j], 0.01);
  }
  EXPECT_NEAR(r.mean[0] / table52_modal().m_kg, 1.0, 0.02);
  EXPECT_NEAR(r.mean[1] / table52_modal().k_N_m, 1.0, 0.02);
  // The held damping was not drawn.
  for (const EkfResult& run : r.runs) EXPECT_TRUE(std::isnan(run.value("c_kg_s")));
}

TEST(Repeatability, SameSeedSameDrawsOtherSeedOtherDraws) {
  RepeatabilityOptions o;
  o.runs = 2;
  // A record just long enough for the filter: only the draws matter here.
  testing::SyntheticCutSpec spec;
  spec.record_s = 0.004;
  spec.settle_revolutions = 2;
  const MeasuredCut c = testing::synthetic_cut(spec);
  const CoeffEkfInputs ref{table52_modal(), table52_coefficients()};
  const RepeatabilityResult a =
      repeat_coeff(EstimatorId::kCoeffXyPerTooth, c, CutSetup{}, ref, {}, o);
  const RepeatabilityResult b =
      repeat_coeff(EstimatorId::kCoeffXyPerTooth, c, CutSetup{}, ref, {}, o);
  o.seed = 2;
  const RepeatabilityResult d =
      repeat_coeff(EstimatorId::kCoeffXyPerTooth, c, CutSetup{}, ref, {}, o);
  EXPECT_EQ(a.initial, b.initial);
  EXPECT_NE(a.initial, d.initial);
  EXPECT_NE(a.initial.row(0), a.initial.row(1));
}

TEST(Repeatability, RejectsBadOptions) {
  RepeatabilityOptions o;
  o.runs = 1;
  try {
    repeat_coeff(EstimatorId::kCoeffXy, cut(), CutSetup{}, {table52_modal(), {{1e9, 1e9}}}, {}, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "repeat.runs = 1: must be >= 2");
  }
  o = RepeatabilityOptions{};
  o.spread = 1.0;
  try {
    repeat_coeff(EstimatorId::kCoeffXy, cut(), CutSetup{}, {table52_modal(), {{1e9, 1e9}}}, {}, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "repeat.spread = 1: must be in [0, 1)");
  }
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
