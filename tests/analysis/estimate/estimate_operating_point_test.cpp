// The observability operating point (operating_point.h) on a simulated cut with known truth
// (tests/support/synthetic_cuts.h, 000 table 5.2 incline 1 at 1 mm): the sample against a
// brute-force search, the states and inputs against their definitions, and the ranks 000 sec. 4.5
// reports (3 of 5 for ekf-modal-x, 6 of 7 for ekf-modal-xy, 6 of 6 for ekf-coeff-xy while a tooth
// cuts).
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "analysis/estimate/observability.h"
#include "analysis/estimate/operating_point.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab {
namespace estimate {
namespace {

using testing::table52_coefficients;
using testing::table52_modal;

constexpr double kExact = 0.0;  // the same arithmetic on the same samples

const MeasuredCut& cut() {
  static const MeasuredCut c = [] {
    testing::SyntheticCutSpec spec;
    spec.record_s = 0.01;  // 2.5 revolutions
    return testing::synthetic_cut(spec);
  }();
  return c;
}

// A run of `id` whose final estimates are the truth.
EkfResult truth_run(EstimatorId id) {
  EkfResult r;
  r.id = id;
  r.estimator = estimator_name(id);
  const ModalParameters m = table52_modal();
  const std::vector<ToothCoefficients> k = table52_coefficients();
  r.estimates = {{"m_kg", m.m_kg, 0.0},           {"c_kg_s", m.c_kg_s, 0.0},
                 {"k_N_m", m.k_N_m, 0.0},         {"Kt_N_m2", k[0].Kt_N_m2, 0.0},
                 {"Kr_N_m2", k[0].Kr_N_m2, 0.0},  {"Kt1_N_m2", k[0].Kt_N_m2, 0.0},
                 {"Kr1_N_m2", k[0].Kr_N_m2, 0.0}, {"Kt2_N_m2", k[1].Kt_N_m2, 0.0},
                 {"Kr2_N_m2", k[1].Kr_N_m2, 0.0}};
  r.summary.succeed();
  return r;
}

TEST(OperatingPoint, LargestForceSampleIsTheBruteForceMaximum) {
  const CutSetup setup;
  const std::vector<ToothCoefficients> k = table52_coefficients();
  const OperatingSample op = largest_force_sample(cut(), setup, k);
  // Second method: every admissible sample's force.
  const CutChips chips(cut(), setup);
  double largest = -1.0;
  Eigen::Index at = -1;
  for (Eigen::Index i = std::max<Eigen::Index>(chips.first_step(), 1); i + 1 < chips.samples();
       ++i) {
    const double f = cutting_force_N(chips.chips(i), k).norm();
    if (f > largest) {
      largest = f;
      at = i;
    }
  }
  EXPECT_EQ(op.k, at);
  EXPECT_GT(largest, 0.0);  // a tooth cuts there
  EXPECT_NEAR(cutting_force_N(op.chips, k).norm(), largest, kExact);
  const double T = cut().time_step_s;
  const Eigen::VectorXd& x = cut().x_m;
  const Eigen::VectorXd& y = cut().y_m;
  EXPECT_EQ(op.deflection[0], x[at]);
  EXPECT_NEAR(op.deflection[1], (x[at + 1] - x[at - 1]) / (2 * T), kExact);
  EXPECT_EQ(op.deflection[2], y[at]);
  EXPECT_NEAR(op.deflection[3], (y[at + 1] - y[at - 1]) / (2 * T), kExact);
}

TEST(OperatingPoint, StatesAndInputsFollowEachVariantsLayout) {
  const CutSetup setup;
  const std::vector<ToothCoefficients> k = table52_coefficients();
  const ModalParameters m = table52_modal();
  const OperatingSample op = largest_force_sample(cut(), setup, k);
  const Eigen::Vector2d force = cutting_force_N(op.chips, k);

  const OperatingState x = operating_state(truth_run(EstimatorId::kModalX), op, k, m);
  ASSERT_EQ(x.state.size(), 5);
  EXPECT_EQ(x.state.head<2>(), op.deflection.head<2>());
  EXPECT_EQ(x.state.tail<3>(), Eigen::Vector3d(m.m_kg, m.c_kg_s, m.k_N_m));
  EXPECT_EQ(x.input.known_N, force);
  EXPECT_EQ(x.input.regressor_m2, Eigen::Matrix2d::Zero());

  const OperatingState mk = operating_state(truth_run(EstimatorId::kModalXyMk), op, k, m);
  ASSERT_EQ(mk.state.size(), 6);
  EXPECT_EQ(mk.state.head<4>(), op.deflection);
  EXPECT_EQ(mk.state.tail<2>(), Eigen::Vector2d(m.m_kg, m.k_N_m));
  EXPECT_EQ(mk.held.c_kg_s, m.c_kg_s);

  const OperatingState mc = operating_state(truth_run(EstimatorId::kModalXyMc), op, k, m);
  EXPECT_EQ(mc.state.tail<2>(), Eigen::Vector2d(m.m_kg, m.c_kg_s));
  EXPECT_EQ(mc.held.k_N_m, m.k_N_m);

  // ekf-coeff-xy: the regressor of every tooth, nothing known.
  const OperatingState shared = operating_state(truth_run(EstimatorId::kCoeffXy), op, k, m);
  Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
  for (int p = 0; p < op.chips.teeth; ++p) sum += tooth_regressor_m2(op.chips.tooth[p]);
  EXPECT_EQ(shared.input.regressor_m2, sum);
  EXPECT_EQ(shared.input.known_N, Eigen::Vector2d::Zero());
  EXPECT_EQ(shared.state.tail<2>(), Eigen::Vector2d(k[0].Kt_N_m2, k[0].Kr_N_m2));

  // Per tooth: the filter of the tooth with the larger chip; its regressor times its
  // coefficients plus the other teeth's known force is the whole force.
  const OperatingState per = operating_state(truth_run(EstimatorId::kCoeffXyPerTooth), op, k, m);
  const int p = op.chips.tooth[1].bw_m2 > op.chips.tooth[0].bw_m2 ? 1 : 0;
  EXPECT_EQ(per.input.regressor_m2, tooth_regressor_m2(op.chips.tooth[p]));
  EXPECT_EQ(per.state.tail<2>(), Eigen::Vector2d(k[p].Kt_N_m2, k[p].Kr_N_m2));
  const Eigen::Vector2d whole = per.input.known_N + per.input.regressor_m2 * per.state.tail<2>();
  EXPECT_LT((whole - force).norm(), 1e-12 * force.norm());  // rounding of a sum of two terms
}

TEST(OperatingPoint, RanksAreThoseOf000Section4_5) {
  const CutSetup setup;
  const std::vector<ToothCoefficients> k = table52_coefficients();
  const ModalParameters m = table52_modal();
  const OperatingSample op = largest_force_sample(cut(), setup, k);
  const std::map<EstimatorId, std::pair<int, int>> ranks = {
      {EstimatorId::kModalX, {3, 5}},    {EstimatorId::kModalXy, {6, 7}},
      {EstimatorId::kModalXyMk, {6, 6}}, {EstimatorId::kModalXyMc, {6, 6}},
      {EstimatorId::kCoeffXy, {6, 6}},   {EstimatorId::kCoeffXyPerTooth, {6, 6}}};
  for (const auto& [id, expected] : ranks) {
    const OperatingState s = operating_state(truth_run(id), op, k, m);
    const ObservabilityResult o = observability(id, s.state, s.input, s.held, cut().time_step_s);
    EXPECT_EQ(o.rank, expected.first) << estimator_name(id);
    EXPECT_EQ(o.states, expected.second) << estimator_name(id);
  }
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
