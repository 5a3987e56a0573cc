// Observability ranks of 000 sec. 4.5 (eq. 4.33): 3 of 5 (ekf-modal-x), 6 of 7 (ekf-modal-xy),
// 6 of 6 (ekf-coeff-xy while a tooth cuts), and the 6-state modal variants of 000 sec. 6.1,
// at the operating points of a simulated cut.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cstdio>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/estimate/observability.h"
#include "analysis/milling/simulation.h"

namespace chatterlab {
namespace estimate {
namespace {

constexpr double kT = 5e-7;  // 000 sec. 6.1
const ModalParameters kModal{0.03134, 22.21, 9.840e5};
const std::vector<ToothCoefficients> kCoefficients{{2.483e8, 2.196e8}, {6.641e9, 4.154e9}};

void record(const std::string& key, double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", value);
  ::testing::Test::RecordProperty(key, buf);
}

// One revolution of 000 table 5.2's incline-1 cut at 1 mm (800 steps per tooth), with the
// states and chips of every step.
const milling::RevolutionRecord& revolution() {
  static const milling::SimulationResult sim = [] {
    milling::SimulationOptions o;
    o.modal_x = {kModal.m_kg, kModal.c_kg_s, kModal.k_N_m};
    o.coefficients = {milling::cutting_coefficients(2.483e8, 2.196e8),
                      milling::cutting_coefficients(6.641e9, 4.154e9)};
    o.depth = milling::DepthProfile::constant(1e-3, 20);
    milling::RecordingRequest rq;
    rq.full_revolutions = {19};
    return milling::simulate(o, rq);
  }();
  return sim.records[0];
}

struct OperatingPoint {
  Eigen::Vector4d deflection;  // x, xdot, y, ydot
  ForceInput modal_input;      // the whole force (modal filters)
  ForceInput coeff_input;      // the regressor of both teeth (ekf-coeff-xy)
  bool cutting = false;
};

OperatingPoint point(int a) {
  const milling::RevolutionRecord& r = revolution();
  OperatingPoint p;
  p.deflection << r.x_m[a], r.vx_m_s[a], r.y_m[a], r.vy_m_s[a];
  StepChips c;
  c.teeth = 2;
  for (int t = 0; t < 2; ++t) {
    const double theta = r.theta1_rad[a] + t * kPi;
    ToothChip& tc = c.tooth[static_cast<std::size_t>(t)];
    tc.sin_theta = std::sin(theta);
    tc.cos_theta = std::cos(theta);
    tc.bw_m2 = r.depth_m[a] * r.chip_m(a, t);
    p.cutting = p.cutting || tc.bw_m2 > 0.0;
    p.coeff_input.regressor_m2 += tooth_regressor_m2(tc);
  }
  p.modal_input.known_N = cutting_force_N(c, kCoefficients);
  return p;
}

Eigen::VectorXd modal_state(EstimatorId id, const OperatingPoint& p) {
  Eigen::VectorXd s;
  if (id == EstimatorId::kModalX) {
    s.resize(5);
    s << p.deflection[0], p.deflection[1], kModal.m_kg, kModal.c_kg_s, kModal.k_N_m;
  } else if (id == EstimatorId::kModalXy) {
    s.resize(7);
    s << p.deflection, kModal.m_kg, kModal.c_kg_s, kModal.k_N_m;
  } else if (id == EstimatorId::kModalXyMk) {
    s.resize(6);
    s << p.deflection, kModal.m_kg, kModal.k_N_m;
  } else {
    s.resize(6);
    s << p.deflection, kModal.m_kg, kModal.c_kg_s;
  }
  return s;
}

// Expected rank (000 sec. 4.5; mk and mc: two parameters, two measurements) over every step of
// the revolution; records the smallest singular value counted and the largest one dropped.
void expect_rank_over_revolution(EstimatorId id, int expected, int expected_idle) {
  const int S = static_cast<int>(revolution().x_m.size());
  double smallest_kept = 1.0, largest_dropped = 0.0;
  for (int a = 0; a < S; ++a) {
    const OperatingPoint p = point(a);
    ObservabilityResult r;
    if (is_modal(id)) {
      r = observability(id, modal_state(id, p), p.modal_input, kModal, kT);
    } else {
      Eigen::VectorXd s(6);
      s << p.deflection, 2.483e8, 2.196e8;
      r = observability(id, s, p.coeff_input, kModal, kT);
    }
    const int want = p.cutting || is_modal(id) ? expected : expected_idle;
    ASSERT_EQ(r.rank, want) << estimator_name(id) << " at step " << a
                            << (p.cutting ? " (cutting)" : " (no tooth cuts)");
    smallest_kept = std::min(smallest_kept, r.singular_values[r.rank - 1]);
    if (r.rank < r.states) largest_dropped = std::max(largest_dropped, r.singular_values[r.rank]);
  }
  record(std::string(estimator_name(id)) + "_smallest_kept", smallest_kept);
  record(std::string(estimator_name(id)) + "_largest_dropped", largest_dropped);
  // The tolerance (1e-9) sits in a wide gap.
  EXPECT_GT(smallest_kept, 1e-6);
  EXPECT_LT(largest_dropped, 1e-12);
}

TEST(Observability, ModalXIsRank3Of5) { expect_rank_over_revolution(EstimatorId::kModalX, 3, 3); }
TEST(Observability, ModalXyIsRank6Of7) { expect_rank_over_revolution(EstimatorId::kModalXy, 6, 6); }
TEST(Observability, ModalXyMkIsRank6Of6) {
  expect_rank_over_revolution(EstimatorId::kModalXyMk, 6, 6);
}
TEST(Observability, ModalXyMcIsRank6Of6) {
  expect_rank_over_revolution(EstimatorId::kModalXyMc, 6, 6);
}
TEST(Observability, CoeffXyIsRank6Of6WhileCuttingAnd4Otherwise) {
  // 000 sec. 4.5: "the cutting force coefficients cease to be observable when no teeth are in
  // contact with the workpiece".
  expect_rank_over_revolution(EstimatorId::kCoeffXy, 6, 4);
  expect_rank_over_revolution(EstimatorId::kCoeffXyPerTooth, 6, 4);
}

TEST(Observability, Eq4_33ItselfGivesTheSameRanksAtTheFilterStep) {
  // O = [H; H F; ...] (000 eq. 4.33) against O_A at every 7th step of the revolution,
  // T = 5e-7 s. Eq. 4.33's parameter directions are (w_n T)^2 ~ 8e-6 weaker than O_A's, whose
  // smallest kept value is 1.8e-5: a tolerance of 1e-12 keeps them while the structural zeros
  // (rounding, < 1e-15) stay below it.
  ObservabilityOptions literal;
  literal.form = ObservabilityForm::kDiscreteEq4_33;
  literal.relative_tolerance = 1e-12;
  const int S = static_cast<int>(revolution().x_m.size());
  double smallest_kept = 1.0;
  for (int a = 0; a < S; a += 7) {
    const OperatingPoint p = point(a);
    for (EstimatorId id : {EstimatorId::kModalX, EstimatorId::kModalXy, EstimatorId::kModalXyMk,
                           EstimatorId::kModalXyMc}) {
      const Eigen::VectorXd s = modal_state(id, p);
      const ObservabilityResult r = observability(id, s, p.modal_input, kModal, kT, literal);
      ASSERT_EQ(r.rank, observability(id, s, p.modal_input, kModal, kT).rank)
          << estimator_name(id) << " at step " << a;
      smallest_kept = std::min(smallest_kept, r.singular_values[r.rank - 1]);
    }
    Eigen::VectorXd s(6);
    s << p.deflection, 2.483e8, 2.196e8;
    const ObservabilityResult r =
        observability(EstimatorId::kCoeffXy, s, p.coeff_input, kModal, kT, literal);
    ASSERT_EQ(r.rank, p.cutting ? 6 : 4) << "ekf-coeff-xy at step " << a;
  }
  record("eq4_33_smallest_kept", smallest_kept);
  EXPECT_GT(smallest_kept, 1e-11);
}

TEST(Observability, AtRestWithoutForceOnlyTheDeflectionsAreObservable) {
  // x = y = 0, v = 0, F = 0: every parameter column of F is zero (000 eqs 4.17, 4.21-4.22).
  Eigen::VectorXd s(7);
  s << 0.0, 0.0, 0.0, 0.0, kModal.m_kg, kModal.c_kg_s, kModal.k_N_m;
  EXPECT_EQ(observability(EstimatorId::kModalXy, s, ForceInput{}, kModal, kT).rank, 4);
}

TEST(Observability, RejectsBadInput) {
  try {
    observability(EstimatorId::kModalXy, Eigen::VectorXd::Zero(5), ForceInput{}, kModal, kT);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "observability: state.size() = 5: must be 7 for ekf-modal-xy");
  }
  Eigen::VectorXd s(6);
  s << 0.0, 0.0, 0.0, 0.0, -0.03, 20.0;
  try {
    observability(EstimatorId::kModalXyMc, s, ForceInput{}, kModal, kT);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "observability: m = -0.03: must be > 0");
  }
  try {
    observability(EstimatorId::kCoeffXy, Eigen::VectorXd::Ones(6), ForceInput{}, kModal, 0.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "observability: time_step_s = 0: must be > 0");
  }
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
