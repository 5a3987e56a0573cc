// Modal-parameter EKFs (000 secs 4.3, 5.1, 6.1) on a simulated cut with known truth.
//
// Conditions (tests/support/synthetic_cuts.h): 000 table 5.2 incline-1 parameters (truth m =
// 0.03134 kg, c = 22.21 kg/s, k = 9.840e5 N/m; known Kt, Kr per tooth), 15,000 rpm, h = 0.0635 mm,
// r_i = 0.382 mm, r = 6.35 mm, two teeth, up-milling, constant depth 1 mm; simulated at 5e-7 s,
// acquired at 100 kHz with 5e-7 m white noise on x and y, resampled by not-a-knot cubic spline
// to 5e-7 s; 0.2 s of data (396,000 filter steps after the first tooth period). Initial
// estimates: 000 sec. 6.1's randomized values (m = 0.02270 kg, c = 40.56 kg/s,
// k = 1.162e6 N/m: -28 %, +83 %, +18 %).
//
// Acceptance (the brief): m and k within 2 %, c within 10 %.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "analysis/estimate/ekf_variants.h"
#include "analysis/estimate/modal_sequence.h"
#include "tests/support/record_property.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab {
namespace estimate {
namespace {

using testing::dissertation_start_modal;
using testing::hammer_modal;
using testing::table52_coefficients;
using testing::table52_modal;

constexpr double kMassStiffnessTolerance = 0.02;  // the brief: within 2 %
constexpr double kDampingTolerance = 0.10;        // the brief: within 10 %

void record(const std::string& key, double value) {
  chatterlab::testing::record_and_print(key, value);
}

const MeasuredCut& cut() {
  static const MeasuredCut c = testing::synthetic_cut(testing::SyntheticCutSpec{});
  return c;
}

double error(const EkfResult& r, const std::string& key, double truth) {
  return r.value(key) / truth - 1.0;
}

// Records the relative errors, steps and runtime of a run under `name`.
void report(const std::string& name, const EkfResult& r) {
  const ModalParameters t = table52_modal();
  for (const Estimate& e : r.estimates) {
    const double truth = e.key == "m_kg" ? t.m_kg : e.key == "c_kg_s" ? t.c_kg_s : t.k_N_m;
    record(name + "_" + e.key + "_error_pct", 100.0 * (e.value / truth - 1.0));
  }
  record(name + "_steps", static_cast<double>(r.steps));
  record(name + "_runtime_s", r.runtime_s);
}

TEST(EkfModal, XOnlyFilterRecoversAllThree) {
  // 000 fig. 6.1 (rank 3 of 5 at any instant, yet the time-varying forcing identifies all three).
  const EkfResult r =
      ekf_modal_x(cut(), CutSetup{}, {table52_coefficients(), dissertation_start_modal()});
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  report("modal_x", r);
  const ModalParameters t = table52_modal();
  EXPECT_NEAR(error(r, "m_kg", t.m_kg), 0.0, kMassStiffnessTolerance);
  EXPECT_NEAR(error(r, "k_N_m", t.k_N_m), 0.0, kMassStiffnessTolerance);
  EXPECT_NEAR(error(r, "c_kg_s", t.c_kg_s), 0.0, kDampingTolerance);
  EXPECT_EQ(r.steps, 396000);  // 400,001 samples less the 4,000-sample delay and one
  EXPECT_EQ(r.estimator, "ekf-modal-x");
}

TEST(EkfModal, XyFilterRecoversAllThree) {
  // 000 fig. 6.2 (rank 6 of 7).
  const EkfResult r =
      ekf_modal_xy(cut(), CutSetup{}, {table52_coefficients(), dissertation_start_modal()});
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  report("modal_xy", r);
  const ModalParameters t = table52_modal();
  EXPECT_NEAR(error(r, "m_kg", t.m_kg), 0.0, kMassStiffnessTolerance);
  EXPECT_NEAR(error(r, "k_N_m", t.k_N_m), 0.0, kMassStiffnessTolerance);
  EXPECT_NEAR(error(r, "c_kg_s", t.c_kg_s), 0.0, kDampingTolerance);
}

TEST(EkfModal, MkAndMcWithTheTrueHeldValue) {
  // 000 figs 6.5 and 6.7: damping (stiffness) held at the value of the simulation.
  ModalEkfInputs mk{table52_coefficients(), dissertation_start_modal()};
  mk.start.c_kg_s = table52_modal().c_kg_s;
  const EkfResult a = ekf_modal_xy_mk(cut(), CutSetup{}, mk);
  ASSERT_TRUE(a.summary.ok()) << a.summary.message;
  report("modal_xy_mk_true_c", a);
  EXPECT_EQ(a.estimates.size(), 2u);
  EXPECT_NEAR(error(a, "m_kg", table52_modal().m_kg), 0.0, kMassStiffnessTolerance);
  EXPECT_NEAR(error(a, "k_N_m", table52_modal().k_N_m), 0.0, kMassStiffnessTolerance);
  EXPECT_TRUE(std::isnan(a.value("c_kg_s")));

  ModalEkfInputs mc{table52_coefficients(), dissertation_start_modal()};
  mc.start.k_N_m = table52_modal().k_N_m;
  const EkfResult b = ekf_modal_xy_mc(cut(), CutSetup{}, mc);
  ASSERT_TRUE(b.summary.ok()) << b.summary.message;
  report("modal_xy_mc_true_k", b);
  EXPECT_NEAR(error(b, "m_kg", table52_modal().m_kg), 0.0, kMassStiffnessTolerance);
  EXPECT_NEAR(error(b, "c_kg_s", table52_modal().c_kg_s), 0.0, kDampingTolerance);
}

TEST(EkfModal, MkThenMcFromTheHammerDamping) {
  // 000 sec. 5.1: m and k with the hammer test's damping (13.39 kg/s, 40 % low), then m and c
  // with that stiffness. Acceptance on the default two passes; the single pass of 000 is
  // reported (and held to 2.5 %: it carries the damping error into m and k, +1.3..2.2 % over
  // six noise seeds, docs/estimators.md).
  ModalEkfInputs in{table52_coefficients(), dissertation_start_modal()};
  in.start.c_kg_s = hammer_modal().c_kg_s;
  const ModalParameters t = table52_modal();

  ModalSequenceOptions one;
  one.passes = 1;
  const ModalSequenceResult s1 = modal_mk_then_mc(cut(), CutSetup{}, in, {}, one);
  ASSERT_TRUE(s1.summary.ok()) << s1.summary.message;
  ASSERT_EQ(s1.runs.size(), 2u);
  record("sequence_1pass_m_error_pct", 100.0 * (s1.identified.m_kg / t.m_kg - 1.0));
  record("sequence_1pass_c_error_pct", 100.0 * (s1.identified.c_kg_s / t.c_kg_s - 1.0));
  record("sequence_1pass_k_error_pct", 100.0 * (s1.identified.k_N_m / t.k_N_m - 1.0));
  EXPECT_NEAR(s1.identified.m_kg / t.m_kg, 1.0, 0.025);
  EXPECT_NEAR(s1.identified.k_N_m / t.k_N_m, 1.0, 0.025);
  EXPECT_NEAR(s1.identified.c_kg_s / t.c_kg_s, 1.0, kDampingTolerance);

  const ModalSequenceResult s2 = modal_mk_then_mc(cut(), CutSetup{}, in);
  ASSERT_TRUE(s2.summary.ok()) << s2.summary.message;
  ASSERT_EQ(s2.runs.size(), 4u);
  record("sequence_2pass_m_error_pct", 100.0 * (s2.identified.m_kg / t.m_kg - 1.0));
  record("sequence_2pass_c_error_pct", 100.0 * (s2.identified.c_kg_s / t.c_kg_s - 1.0));
  record("sequence_2pass_k_error_pct", 100.0 * (s2.identified.k_N_m / t.k_N_m - 1.0));
  EXPECT_NEAR(s2.identified.m_kg / t.m_kg, 1.0, kMassStiffnessTolerance);
  EXPECT_NEAR(s2.identified.k_N_m / t.k_N_m, 1.0, kMassStiffnessTolerance);
  EXPECT_NEAR(s2.identified.c_kg_s / t.c_kg_s, 1.0, kDampingTolerance);
  // The second mk run held the first mc run's damping.
  EXPECT_DOUBLE_EQ(s2.runs[2].value("m_kg"), s2.identified.m_kg);
}

TEST(EkfModal, OverNoiseSeeds) {
  // Six other noise draws of the same cut: ekf-modal-xy (all three from 000's start) and the
  // one-pass mk-then-mc sequence from the hammer damping.
  const ModalParameters t = table52_modal();
  double worst_mk = 0.0, worst_c = 0.0, worst_seq_mk = 0.0, worst_seq_c = 0.0;
  for (unsigned seed = 1; seed <= 6; ++seed) {
    testing::SyntheticCutSpec spec;
    spec.seed = seed;
    const MeasuredCut c = testing::synthetic_cut(spec);
    const EkfResult r =
        ekf_modal_xy(c, CutSetup{}, {table52_coefficients(), dissertation_start_modal()});
    ASSERT_TRUE(r.summary.ok()) << r.summary.message;
    worst_mk = std::max(
        {worst_mk, std::abs(error(r, "m_kg", t.m_kg)), std::abs(error(r, "k_N_m", t.k_N_m))});
    worst_c = std::max(worst_c, std::abs(error(r, "c_kg_s", t.c_kg_s)));
    ModalEkfInputs in{table52_coefficients(), dissertation_start_modal()};
    in.start.c_kg_s = hammer_modal().c_kg_s;
    ModalSequenceOptions one;
    one.passes = 1;
    const ModalSequenceResult s = modal_mk_then_mc(c, CutSetup{}, in, {}, one);
    ASSERT_TRUE(s.summary.ok()) << s.summary.message;
    worst_seq_mk = std::max({worst_seq_mk, std::abs(s.identified.m_kg / t.m_kg - 1.0),
                             std::abs(s.identified.k_N_m / t.k_N_m - 1.0)});
    worst_seq_c = std::max(worst_seq_c, std::abs(s.identified.c_kg_s / t.c_kg_s - 1.0));
  }
  record("seeds_modal_xy_worst_m_k_pct", 100.0 * worst_mk);
  record("seeds_modal_xy_worst_c_pct", 100.0 * worst_c);
  record("seeds_sequence_1pass_worst_m_k_pct", 100.0 * worst_seq_mk);
  record("seeds_sequence_1pass_worst_c_pct", 100.0 * worst_seq_c);
  EXPECT_LT(worst_mk, kMassStiffnessTolerance);
  EXPECT_LT(worst_c, kDampingTolerance);
  EXPECT_LT(worst_seq_mk, 0.025);
  EXPECT_LT(worst_seq_c, kDampingTolerance);
}

TEST(EkfModal, ForwardEulerOf000BiasesTheDamping) {
  // 000 eq. 4.3's forward Euler adds a negative damping k T = 0.49 kg/s (2.2 % of c) that the
  // filter absorbs into c (ekf_options.h); symplectic Euler (the default) does not.
  ModalEkfOptions o;
  o.discretization = Discretization::kForwardEuler;
  const EkfResult fwd =
      ekf_modal_xy(cut(), CutSetup{}, {table52_coefficients(), dissertation_start_modal()}, o);
  const EkfResult sym =
      ekf_modal_xy(cut(), CutSetup{}, {table52_coefficients(), dissertation_start_modal()});
  ASSERT_TRUE(fwd.summary.ok() && sym.summary.ok());
  report("modal_xy_forward_euler", fwd);
  const double shift = (fwd.value("c_kg_s") - sym.value("c_kg_s")) / table52_modal().c_kg_s;
  record("forward_minus_symplectic_c_pct", 100.0 * shift);
  const double predicted = table52_modal().k_N_m * cut().time_step_s / table52_modal().c_kg_s;
  EXPECT_NEAR(shift, predicted, 0.5 * predicted);
}

TEST(EkfModal, TuningOf000DoesNotConvergeHere) {
  // 000 eqs 6.1-6.6 (modal_options_000): P0 of k (5e13) is negligible next to the force noise
  // (Q = 1e14 N^2), so k never leaves its initial value; m and c wander or diverge.
  const EkfResult r = ekf_modal_xy_mk(
      cut(), CutSetup{}, {table52_coefficients(), {0.02270, 22.21, 1.162e6}}, modal_options_000());
  record("modal_xy_mk_000_k_change_pct", 100.0 * (r.value("k_N_m") / 1.162e6 - 1.0));
  EXPECT_NEAR(r.value("k_N_m") / 1.162e6, 1.0, 1e-3);
}

TEST(EkfModal, HistoryIsDecimatedAndEndsAtTheFinalEstimate) {
  ModalEkfOptions o;
  o.history_points = 500;
  const EkfResult r =
      ekf_modal_xy(cut(), CutSetup{}, {table52_coefficients(), dissertation_start_modal()}, o);
  ASSERT_TRUE(r.summary.ok());
  const EstimateHistory& h = r.history;
  ASSERT_EQ(h.columns, (std::vector<std::string>{"x_m", "vx_m_s", "y_m", "vy_m_s", "m_kg", "c_kg_s",
                                                 "k_N_m"}));
  EXPECT_LE(h.time_s.size(), 500);
  EXPECT_GE(h.time_s.size(), 400);
  EXPECT_EQ(h.values.rows(), h.time_s.size());
  // First row: the initial estimate at the first filtered sample (one tooth period in).
  EXPECT_DOUBLE_EQ(h.time_s[0], 4000 * 5e-7);
  EXPECT_DOUBLE_EQ(h.values(0, 4), dissertation_start_modal().m_kg);
  // Last row: the final state at the last sample (0.2 s).
  EXPECT_NEAR(h.time_s[h.time_s.size() - 1], 0.2, 1e-12);
  EXPECT_EQ(h.values.row(h.values.rows() - 1).transpose(), r.final_state);
  for (Eigen::Index i = 1; i < h.time_s.size(); ++i) EXPECT_GT(h.time_s[i], h.time_s[i - 1]);
  EXPECT_EQ(r.covariance_diagonal.size(), 7);
  EXPECT_GT(r.estimates[0].variance, 0.0);
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
