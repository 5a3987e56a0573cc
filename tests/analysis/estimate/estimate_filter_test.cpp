// Properties of the filter step shared by every variant, extended and unscented: the covariance
// stays symmetric positive semi-definite along a run, a step allocates nothing, a measurement
// pulls the estimate towards it, the parameter hold leaves the parameters alone.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <type_traits>

#include "analysis/estimate/ekf.h"
#include "analysis/estimate/ekf_options.h"
#include "synthetic_cut.h"
#include "tests/support/count_allocations.h"

namespace chatterlab {
namespace estimate {
namespace {

// A short record (0.02 s, five revolutions) of the tests' cut: enough for every variant to
// pass through many engagements.
const MeasuredCut& short_cut() {
  static const MeasuredCut cut = [] {
    testing::SyntheticCutSpec spec;
    spec.record_s = 0.02;
    spec.settle_revolutions = 10;
    return testing::synthetic_cut(spec);
  }();
  return cut;
}

// A model and the filter that steps it.
template <class ModelT, bool kUnscented>
struct Variant {
  using Model = ModelT;
  using Filter = std::conditional_t<kUnscented, ToolUkf<Model>, ToolEkf<Model>>;
  static constexpr bool unscented = kUnscented;
};

template <class V>
typename V::Filter make_filter(const typename V::Model& model) {
  using Model = typename V::Model;
  const ModalEkfOptions mo;
  const CoeffEkfOptions co;
  typename Model::State x0 = Model::State::Zero();
  typename Model::StateMatrix P0 = Model::StateMatrix::Zero();
  typename Model::Noise q;
  for (int a = 0; a < Model::kAxes; ++a) {
    P0(2 * a, 2 * a) = mo.p0_deflection_m2;
    P0(2 * a + 1, 2 * a + 1) = mo.p0_velocity_m2_s2;
    q[a] = mo.q_force_N2;
  }
  const int w0 = Model::kAxes - Model::kFirstParameter;
  // 000 sec. 6.1's randomized starts.
  if constexpr (Model::kMass >= 0) {
    x0[Model::kMass] = 0.02270;
    P0(Model::kMass, Model::kMass) = mo.p0_mass_kg2;
    q[Model::kMass + w0] = mo.q_mass;
  }
  if constexpr (Model::kDamping >= 0) {
    x0[Model::kDamping] = 40.56;
    P0(Model::kDamping, Model::kDamping) = mo.p0_damping_kg2_s2;
    q[Model::kDamping + w0] = mo.q_damping;
  }
  if constexpr (Model::kStiffness >= 0) {
    x0[Model::kStiffness] = 1.162e6;
    P0(Model::kStiffness, Model::kStiffness) = mo.p0_stiffness_N2_m2;
    q[Model::kStiffness + w0] = mo.q_stiffness;
  }
  if constexpr (Model::kKt >= 0) {
    x0[Model::kKt] = 2.2e9;
    x0[Model::kKr] = 1.7e9;
    P0(Model::kKt, Model::kKt) = co.p0_Kt;
    P0(Model::kKr, Model::kKr) = co.p0_Kr;
    q[Model::kKt + w0] = co.q_Kt;
    q[Model::kKr + w0] = co.q_Kr;
  }
  if constexpr (V::unscented) {
    // The modal UKFs' physically scaled P0 (ekf_options.h).
    for (int i = Model::kFirstParameter; i < Model::kStates && Model::kKt < 0; ++i) {
      P0(i, i) = std::pow(mo.ukf_p0_relative_sd * x0[i], 2);
    }
    return make_tool_ukf(model, x0, P0, q, Model::Measurement::Constant(mo.r_m2), mo.ukf);
  } else {
    return make_tool_ekf(model, x0, P0, q, Model::Measurement::Constant(mo.r_m2));
  }
}

template <class Model>
ForceInput input_for(const StepChips& c) {
  ForceInput u;
  if constexpr (Model::kKt >= 0) {
    for (int p = 0; p < c.teeth; ++p) {
      u.regressor_m2 += tooth_regressor_m2(c.tooth[static_cast<std::size_t>(p)]);
    }
  } else {
    u.known_N = cutting_force_N(c, testing::table52_coefficients());
  }
  return u;
}

template <class Model>
typename Model::Measurement measured(const MeasuredCut& cut, Eigen::Index k) {
  typename Model::Measurement z;
  z[0] = cut.x_m[k];
  if constexpr (Model::kMeasurements == 2) z[1] = cut.y_m[k];
  return z;
}

template <class V>
class FilterProperties : public ::testing::Test {};

using Models = ::testing::Types<Variant<ModalXModel, false>, Variant<ModalXyModel, false>,
                                Variant<ModalXyMkModel, false>, Variant<ModalXyMcModel, false>,
                                Variant<CoeffXyModel, false>, Variant<ModalXModel, true>,
                                Variant<ModalXyModel, true>, Variant<ModalXyMkModel, true>,
                                Variant<ModalXyMcModel, true>, Variant<CoeffXyModel, true>>;
TYPED_TEST_SUITE(FilterProperties, Models);

TYPED_TEST(FilterProperties, CovarianceStaysSymmetricPositiveSemidefinite) {
  // Checked every 500 steps in coordinates scaled by the square root of P's diagonal (a
  // correlation matrix), where entries are <= 1 whatever the states' units: eigenvalues
  // >= -1e-9 (rounding of a 7 x 7 eigen-solve is ~1e-15; 1e-9 still flags any real loss of
  // definiteness).
  using Model = typename TypeParam::Model;
  const MeasuredCut& cut = short_cut();
  const CutChips chips(cut, CutSetup{});
  const Model model(cut.time_step_s, Discretization::kSymplecticEuler, testing::table52_modal());
  auto f = make_filter<TypeParam>(model);
  double smallest = 1.0;
  for (Eigen::Index k = chips.first_step(); k + 1 < chips.samples(); ++k) {
    f.predict(input_for<Model>(chips.chips(k)));
    f.update(measured<Model>(cut, k + 1));
    if ((k - chips.first_step()) % 500 != 0) continue;
    const typename Model::StateMatrix& P = f.covariance();
    ASSERT_EQ(P, P.transpose()) << "step " << k;
    ASSERT_TRUE((P.diagonal().array() > 0.0).all()) << "step " << k;
    const typename Model::State d = P.diagonal().cwiseSqrt().cwiseInverse();
    const typename Model::StateMatrix C = d.asDiagonal() * P * d.asDiagonal();
    // Dynamic size: one instantiation for every model (fixed sizes cost GCC long compiles).
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(C),
                                                             Eigen::EigenvaluesOnly);
    smallest = std::min(smallest, eig.eigenvalues().minCoeff());
    ASSERT_GE(eig.eigenvalues().minCoeff(), -1e-9) << "step " << k;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", smallest);
  ::testing::Test::RecordProperty("smallest_correlation_eigenvalue", buf);
}

TYPED_TEST(FilterProperties, AStepAllocatesNothing) {
  if (!kCountingMalloc) GTEST_SKIP() << "malloc is not counted under AddressSanitizer";
  using Model = typename TypeParam::Model;
  const MeasuredCut& cut = short_cut();
  const CutChips chips(cut, CutSetup{});
  const Model model(cut.time_step_s, Discretization::kSymplecticEuler, testing::table52_modal());
  auto f = make_filter<TypeParam>(model);
  const std::vector<ToothCoefficients> K = testing::table52_coefficients();
  chatterlab::testing::g_allocations = 0;
  chatterlab::testing::g_counting = true;
  for (Eigen::Index k = chips.first_step(); k + 1 < chips.samples(); ++k) {
    const StepChips c = chips.chips(k);
    ForceInput u;
    if constexpr (Model::kKt >= 0) {
      u.regressor_m2 = tooth_regressor_m2(c.tooth[0]) + tooth_regressor_m2(c.tooth[1]);
    } else {
      u.known_N = cutting_force_N(c, K);
    }
    f.predict(u);
    if ((k & 1) == 0) {
      f.update(measured<Model>(cut, k + 1));
    } else {
      f.update_consider(measured<Model>(cut, k + 1), parameter_states<Model>());
    }
  }
  chatterlab::testing::g_counting = false;
  EXPECT_EQ(chatterlab::testing::g_allocations, 0);
}

TYPED_TEST(FilterProperties, ParameterHoldLeavesParametersAndTheirCovariance) {
  // The Schmidt update (update_consider with the parameter states) corrects deflections only; P's
  // parameter block is what the prediction left.
  using Model = typename TypeParam::Model;
  const MeasuredCut& cut = short_cut();
  const CutChips chips(cut, CutSetup{});
  const Model model(cut.time_step_s, Discretization::kSymplecticEuler, testing::table52_modal());
  auto f = make_filter<TypeParam>(model);
  constexpr int P = Model::kParameters;
  for (Eigen::Index k = chips.first_step(); k < chips.first_step() + 3000; ++k) {
    f.predict(input_for<Model>(chips.chips(k)));
    const typename Model::State before = f.state();
    const typename Model::StateMatrix P_before = f.covariance();
    f.update_consider(measured<Model>(cut, k + 1), parameter_states<Model>());
    ASSERT_TRUE((f.state().template tail<P>() == before.template tail<P>()));
    ASSERT_TRUE((f.covariance().template bottomRightCorner<P, P>() ==
                 P_before.template bottomRightCorner<P, P>()));
  }
}

TEST(FilterUpdate, ScalarCaseMatchesTheKalmanFormulas) {
  // One update of the x-only filter by hand (000 eqs 4.7-4.9 with H = [1 0 0 0 0], M = 1):
  // K = P e1 / (P11 + R), x+ = x- + K (z - x1), P+ = P - P e1 e1^T P / (P11 + R).
  const ModalXModel model(5e-7, Discretization::kForwardEuler, {});
  ModalXModel::State x0;
  x0 << 1e-5, 0.01, 0.03, 20.0, 1e6;
  ModalXModel::StateMatrix P0;
  P0.setIdentity();
  P0(0, 1) = P0(1, 0) = 0.3;
  P0(0, 4) = P0(4, 0) = -0.2;
  ToolEkf<ModalXModel> f = make_tool_ekf(model, x0, P0, ModalXModel::Noise::Zero(),
                                         ModalXModel::Measurement::Constant(2.0));
  f.update(ModalXModel::Measurement::Constant(4.0));
  const ModalXModel::State K = P0.col(0) / (P0(0, 0) + 2.0);
  EXPECT_LT((f.state() - (x0 + K * (4.0 - x0[0]))).norm(), 1e-12 * x0.norm());
  const ModalXModel::StateMatrix P1 = P0 - P0.col(0) * P0.row(0) / (P0(0, 0) + 2.0);
  EXPECT_LT((f.covariance() - P1).cwiseAbs().maxCoeff(), 1e-15);
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
