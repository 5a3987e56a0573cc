// Every error message a user of the estimators can meet, names and sizes of the variants, and
// results that cannot look like successes when nothing (or something broken) ran.
#include <gtest/gtest.h>

#include <string>

#include "analysis/common/summary.h"
#include "analysis/estimate/ekf_variants.h"
#include "analysis/estimate/modal_sequence.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab {
namespace estimate {
namespace {

using testing::table52_coefficients;
using testing::table52_modal;

// A short record (10 ms): the checks run before any filtering.
const MeasuredCut& cut() {
  static const MeasuredCut c = [] {
    testing::SyntheticCutSpec spec;
    spec.record_s = 0.01;
    spec.settle_revolutions = 2;
    return testing::synthetic_cut(spec);
  }();
  return c;
}

template <class F>
void expect_error(F f, const std::string& message) {
  try {
    f();
    FAIL() << "no error; expected: " << message;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(EstimatorNames, RoundTripAndSizes) {
  const std::vector<std::pair<EstimatorId, int>> all = {
      {EstimatorId::kModalX, 5},    {EstimatorId::kModalXy, 7}, {EstimatorId::kModalXyMk, 6},
      {EstimatorId::kModalXyMc, 6}, {EstimatorId::kCoeffXy, 6}, {EstimatorId::kCoeffXyPerTooth, 6}};
  for (const auto& [id, states] : all) {
    EXPECT_EQ(estimator_from_name(estimator_name(id)), id);
    EXPECT_EQ(estimator_states(id), states);
  }
  EXPECT_STREQ(estimator_name(EstimatorId::kCoeffXyPerTooth), "ekf-coeff-xy-per-tooth");
  expect_error([] { estimator_from_name("ukf-modal"); },
               "estimator = ukf-modal: unknown (ekf-modal-x, ekf-modal-xy, ekf-modal-xy-mk, "
               "ekf-modal-xy-mc, ekf-coeff-xy, ekf-coeff-xy-per-tooth, ukf-modal-x, ukf-modal-xy, "
               "ukf-modal-xy-mk, ukf-modal-xy-mc, ukf-coeff-xy, ukf-coeff-xy-per-tooth, "
               "ekf-coeff-xy-feedback)");
}

TEST(EkfOptions, ValidationNamesFieldValueAndRule) {
  ModalEkfOptions m;
  m.r_m2 = -1.0;
  expect_error([&] { validate(m); }, "ekf.r_m2 = -1: must be finite and > 0");
  m = ModalEkfOptions{};
  m.q_force_N2 = -2.0;
  expect_error([&] { validate(m); }, "ekf.q_force_N2 = -2: must be finite and >= 0");
  m = ModalEkfOptions{};
  m.p0_stiffness_N2_m2 = 0.0;
  expect_error([&] { validate(m); }, "ekf.p0_stiffness_N2_m2 = 0: must be finite and > 0");
  m = ModalEkfOptions{};
  m.history_points = 1;
  expect_error([&] { validate(m); }, "ekf.history_points = 1: must be >= 2");
  CoeffEkfOptions c;
  c.p0_Kt = -1.0;
  expect_error([&] { validate(c); }, "ekf.p0_Kt = -1: must be finite and > 0");
  c = CoeffEkfOptions{};
  c.gate = static_cast<ToothGate>(7);
  expect_error([&] { validate(c); }, "ekf.gate = 7: unknown gate");
  c = CoeffEkfOptions{};
  c.discretization = static_cast<Discretization>(9);
  expect_error([&] { validate(c); }, "ekf.discretization = 9: unknown discretization");
  EXPECT_NO_THROW(validate(modal_options_000()));
  EXPECT_NO_THROW(validate(coeff_options_000()));
}

TEST(EkfInputs, ModalInputsAreChecked) {
  ModalEkfInputs in{table52_coefficients(), table52_modal()};
  in.coefficients.pop_back();
  expect_error([&] { ekf_modal_xy(cut(), CutSetup{}, in); },
               "inputs.coefficients.size() = 1: must equal setup.teeth = 2 (one Kt, Kr per tooth)");
  in = {table52_coefficients(), table52_modal()};
  in.coefficients[1].Kr_N_m2 = std::nan("");
  expect_error([&] { ekf_modal_xy(cut(), CutSetup{}, in); },
               "inputs.coefficients[1].Kr_N_m2 = nan: must be finite");
  in = {table52_coefficients(), table52_modal()};
  in.start.m_kg = 0.0;
  expect_error([&] { ekf_modal_x(cut(), CutSetup{}, in); }, "inputs.start.m_kg = 0: must be > 0");
  in = {table52_coefficients(), table52_modal()};
  in.start.c_kg_s = -1.0;
  expect_error([&] { ekf_modal_xy_mk(cut(), CutSetup{}, in); },
               "inputs.start.c_kg_s = -1: must be >= 0");
  in = {table52_coefficients(), table52_modal()};
  in.start.k_N_m = -5.0;
  expect_error([&] { ekf_modal_xy_mc(cut(), CutSetup{}, in); },
               "inputs.start.k_N_m = -5: must be > 0");
  expect_error([&] { ekf_modal(EstimatorId::kCoeffXy, cut(), CutSetup{}, {}); },
               "estimator = ekf-coeff-xy: is not a modal-parameter filter");
  ModalSequenceOptions s;
  s.passes = 0;
  expect_error(
      [&] {
        modal_mk_then_mc(cut(), CutSetup{}, {table52_coefficients(), table52_modal()}, {}, s);
      },
      "sequence.passes = 0: must be >= 1");
  ModalEkfOptions o;
  o.r_m2 = 0.0;
  expect_error(
      [&] {
        ekf_modal_xy(cut(), CutSetup{}, {table52_coefficients(), table52_modal()}, o);
      },
      "ekf.r_m2 = 0: must be finite and > 0");
}

TEST(EkfInputs, CoefficientInputsAreChecked) {
  CoeffEkfInputs in{table52_modal(), table52_coefficients()};
  expect_error([&] { ekf_coeff_xy(cut(), CutSetup{}, in); },
               "inputs.start.size() = 2: must be 1 for ekf-coeff-xy (one Kt, Kr for every tooth)");
  in.start.push_back({1e9, 1e9});
  expect_error([&] { ekf_coeff_xy_per_tooth(cut(), CutSetup{}, in); },
               "inputs.start.size() = 3: must equal setup.teeth = 2 for ekf-coeff-xy-per-tooth");
  in = {table52_modal(), table52_coefficients()};
  in.modal.k_N_m = 0.0;
  expect_error([&] { ekf_coeff_xy_per_tooth(cut(), CutSetup{}, in); },
               "inputs.modal.k_N_m = 0: must be > 0");
  in = {table52_modal(), table52_coefficients()};
  in.modal.c_kg_s = -1.0;
  expect_error([&] { ekf_coeff_xy_per_tooth(cut(), CutSetup{}, in); },
               "inputs.modal.c_kg_s = -1: must be >= 0");
  in = {table52_modal(), table52_coefficients()};
  in.start[0].Kt_N_m2 = std::nan("");
  expect_error([&] { ekf_coeff_xy_per_tooth(cut(), CutSetup{}, in); },
               "inputs.start[0].Kt_N_m2 = nan: must be finite");
  expect_error([&] { ekf_coeff(EstimatorId::kModalX, cut(), CutSetup{}, {}); },
               "estimator = ekf-modal-x: is not a cutting-coefficient filter");
  // Cut errors come from CutChips (estimate_cut_input_test.cpp has them all).
  MeasuredCut bad = cut();
  bad.time_step_s = -1.0;
  expect_error(
      [&] {
        ekf_coeff_xy_per_tooth(bad, CutSetup{}, {table52_modal(), table52_coefficients()});
      },
      "cut.time_step_s = -1: must be finite and > 0");
}

TEST(EkfResults, NothingRunIsNotASuccess) {
  const EkfResult r;
  EXPECT_FALSE(r.summary.ok());
  EXPECT_EQ(r.summary.message, "not run");
  EXPECT_TRUE(std::isnan(r.value("m_kg")));
  const ModalSequenceResult s;
  EXPECT_FALSE(s.summary.ok());
}

TEST(EkfResults, ADivergingFilterFailsWithTheStep) {
  // A start mass of 1e-300 kg makes T / m overflow at the first step.
  ModalEkfInputs in{table52_coefficients(), table52_modal()};
  in.start.m_kg = 1e-300;
  const EkfResult r = ekf_modal_xy(cut(), CutSetup{}, in);
  EXPECT_FALSE(r.summary.ok());
  EXPECT_EQ(r.summary.message.rfind("the estimate became non-finite at step ", 0), 0u)
      << r.summary.message;
  EXPECT_LT(r.steps, 10);
  CoeffEkfInputs ci{table52_modal(), {{1e300, 1e300}, {1e300, 1e300}}};
  ci.modal.m_kg = 1e-300;
  const EkfResult c = ekf_coeff_xy_per_tooth(cut(), CutSetup{}, ci);
  EXPECT_FALSE(c.summary.ok());
  EXPECT_EQ(c.summary.message.rfind("the estimate became non-finite at step ", 0), 0u)
      << c.summary.message;
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
