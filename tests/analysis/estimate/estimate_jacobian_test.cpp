// Every analytic Jacobian of the EKF models against central finite differences, at random
// states, inputs and noises (a property suite over all variants, after manif's evalRplusJac).
//
// Comparison in scaled coordinates: with S = diag(state scales) and S_w = diag(noise scales),
// S^-1 J_f_x S and S^-1 J_f_w S_w have entries of order 1 (or T w_n ~ 3e-3), so one absolute
// tolerance fits all entries. Central differences with relative step 1e-6 have truncation error
// ~1e-12 (f is rational in the state) and rounding error ~eps / 1e-6 ~ 2e-10 per unit entry;
// the tolerance 1e-7 sits far above both and far below any real slip (entries >= 1e-4).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

#include "analysis/estimate/tool_model.h"

namespace chatterlab {
namespace estimate {
namespace {

constexpr double kT = 5e-7;  // the filter step of 000 sec. 6.1
constexpr double kTolerance = 1e-7;
constexpr int kSamples = 200;  // random points per model and discretization

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
}

template <class Model>
struct Point {
  typename Model::State x, scale;
  typename Model::Noise w, w_scale;
  ForceInput u;
};

// Ranges around 000 table 5.2's values: deflections to 50 um, velocities to 0.3 m/s, forces to
// 200 N, m, c, k and Kt, Kr over a factor 3-100.
template <class Model>
Point<Model> random_point(std::mt19937_64& rng) {
  Point<Model> p;
  for (int a = 0; a < Model::kAxes; ++a) {
    p.x[2 * a] = uniform(rng, -5e-5, 5e-5);
    p.x[2 * a + 1] = uniform(rng, -0.3, 0.3);
    p.scale[2 * a] = 5e-5;
    p.scale[2 * a + 1] = 0.3;
    p.w[a] = uniform(rng, -20.0, 20.0);
    p.w_scale[a] = 20.0;
  }
  const auto param = [&](int i, double lo, double hi) {
    p.x[i] = uniform(rng, lo, hi);
    p.scale[i] = std::abs(p.x[i]);
  };
  if constexpr (Model::kMass >= 0) param(Model::kMass, 0.015, 0.05);
  if constexpr (Model::kDamping >= 0) param(Model::kDamping, 5.0, 50.0);
  if constexpr (Model::kStiffness >= 0) param(Model::kStiffness, 5e5, 2e6);
  if constexpr (Model::kKt >= 0) {
    param(Model::kKt, 1e8, 1e10);
    param(Model::kKr, 1e8, 1e10);
  }
  for (int i = 0; i < Model::kParameters; ++i) {
    // w_theta moves theta by T w per step: scale it so that T w ~ 1e-3 theta.
    p.w_scale[Model::kAxes + i] = 1e-3 * p.scale[Model::kFirstParameter + i] / kT;
    p.w[Model::kAxes + i] = uniform(rng, -1.0, 1.0) * p.w_scale[Model::kAxes + i];
  }
  p.u.known_N = Eigen::Vector2d(uniform(rng, -200.0, 200.0), uniform(rng, -200.0, 200.0));
  for (int i = 0; i < 4; ++i) p.u.regressor_m2(i / 2, i % 2) = uniform(rng, -3e-8, 3e-8);
  // The feedback chips' regenerative stiffness (ekf-coeff-xy-feedback), up to the tool's k.
  for (int i = 0; i < 4; ++i) p.u.stiffness_N_m(i / 2, i % 2) = uniform(rng, -1e6, 1e6);
  p.u.position_m = Eigen::Vector2d(uniform(rng, -1e-4, 1e-4), uniform(rng, -1e-4, 1e-4));
  return p;
}

template <class Model>
class ModelJacobians : public ::testing::Test {};

using Models =
    ::testing::Types<ModalXModel, ModalXyModel, ModalXyMkModel, ModalXyMcModel, CoeffXyModel>;
TYPED_TEST_SUITE(ModelJacobians, Models);

TYPED_TEST(ModelJacobians, StateJacobianMatchesCentralDifferences) {
  using Model = TypeParam;
  std::mt19937_64 rng(11);
  const ModalParameters held{0.03134, 22.21, 9.840e5};
  for (Discretization d : {Discretization::kForwardEuler, Discretization::kSymplecticEuler}) {
    const Model model(kT, d, held);
    double worst = 0.0;
    for (int s = 0; s < kSamples; ++s) {
      const Point<Model> p = random_point<Model>(rng);
      typename Model::StateMatrix J;
      model.propagate(p.x, p.u, p.w, &J);
      for (int j = 0; j < Model::kStates; ++j) {
        const double h = 1e-6 * p.scale[j];
        typename Model::State xp = p.x, xm = p.x;
        xp[j] += h;
        xm[j] -= h;
        const typename Model::State col =
            (model.propagate(xp, p.u, p.w) - model.propagate(xm, p.u, p.w)) / (2.0 * h);
        for (int i = 0; i < Model::kStates; ++i) {
          // Scaled entry: (S^-1 J S)_ij = J_ij s_j / s_i.
          const double e = std::abs(J(i, j) - col[i]) * p.scale[j] / p.scale[i];
          worst = std::max(worst, e);
          EXPECT_LT(e, kTolerance) << "J_f_x(" << i << ", " << j << "), discretization "
                                   << static_cast<int>(d) << ", sample " << s;
        }
      }
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", worst);
    ::testing::Test::RecordProperty(
        std::string("worst_scaled_error_") +
            (d == Discretization::kForwardEuler ? "forward_euler" : "symplectic_euler"),
        buf);
  }
}

TYPED_TEST(ModelJacobians, NoiseJacobianMatchesCentralDifferences) {
  using Model = TypeParam;
  std::mt19937_64 rng(12);
  const ModalParameters held{0.03134, 22.21, 9.840e5};
  for (Discretization d : {Discretization::kForwardEuler, Discretization::kSymplecticEuler}) {
    const Model model(kT, d, held);
    for (int s = 0; s < kSamples; ++s) {
      const Point<Model> p = random_point<Model>(rng);
      typename Model::NoiseJacobian L;
      model.propagate(p.x, p.u, p.w, nullptr, &L);
      for (int j = 0; j < Model::kNoises; ++j) {
        const double h = 1e-6 * p.w_scale[j];
        typename Model::Noise wp = p.w, wm = p.w;
        wp[j] += h;
        wm[j] -= h;
        const typename Model::State col =
            (model.propagate(p.x, p.u, wp) - model.propagate(p.x, p.u, wm)) / (2.0 * h);
        for (int i = 0; i < Model::kStates; ++i) {
          const double e = std::abs(L(i, j) - col[i]) * p.w_scale[j] / p.scale[i];
          EXPECT_LT(e, kTolerance) << "J_f_w(" << i << ", " << j << "), discretization "
                                   << static_cast<int>(d) << ", sample " << s;
        }
      }
    }
  }
}

TYPED_TEST(ModelJacobians, StructuredProcessNoiseEqualsLQLt) {
  // add_process_noise uses L's sparsity; reference: the dense product L diag(q) L^T.
  using Model = TypeParam;
  std::mt19937_64 rng(13);
  const ModalParameters held{0.03134, 22.21, 9.840e5};
  for (Discretization d : {Discretization::kForwardEuler, Discretization::kSymplecticEuler}) {
    const Model model(kT, d, held);
    for (int s = 0; s < 20; ++s) {
      const Point<Model> p = random_point<Model>(rng);
      typename Model::Noise q;
      for (int i = 0; i < Model::kNoises; ++i) q[i] = uniform(rng, 0.0, 1e3);
      typename Model::NoiseJacobian L;
      model.propagate(p.x, p.u, Model::Noise::Zero(), nullptr, &L);
      const typename Model::StateMatrix dense = L * q.asDiagonal() * L.transpose();
      typename Model::StateMatrix P = Model::StateMatrix::Zero();
      model.add_process_noise(p.x, q, &P);
      EXPECT_LE((P - dense).cwiseAbs().maxCoeff(), 1e-14 * dense.cwiseAbs().maxCoeff());
    }
  }
}

TEST(ModelLayout, StateSizesAndIndicesFollow000) {
  // 000 secs 4.3-4.4 and 6.1: 5, 7, 6, 6, 6 states; parameters after the deflection states.
  EXPECT_EQ(ModalXModel::kStates, 5);
  EXPECT_EQ(ModalXyModel::kStates, 7);
  EXPECT_EQ(ModalXyMkModel::kStates, 6);
  EXPECT_EQ(ModalXyMcModel::kStates, 6);
  EXPECT_EQ(CoeffXyModel::kStates, 6);
  EXPECT_EQ(ModalXModel::kMass, 2);
  EXPECT_EQ(ModalXModel::kStiffness, 4);
  EXPECT_EQ(ModalXyModel::kMass, 4);
  EXPECT_EQ(ModalXyModel::kDamping, 5);
  EXPECT_EQ(ModalXyModel::kStiffness, 6);
  EXPECT_EQ(ModalXyMkModel::kDamping, -1);
  EXPECT_EQ(ModalXyMkModel::kStiffness, 5);
  EXPECT_EQ(ModalXyMcModel::kDamping, 5);
  EXPECT_EQ(ModalXyMcModel::kStiffness, -1);
  EXPECT_EQ(CoeffXyModel::kKt, 4);
  EXPECT_EQ(CoeffXyModel::kKr, 5);
  EXPECT_EQ(ModalXModel::kNoises, 4);   // 000 eq. 6.1: Q is 4 x 4
  EXPECT_EQ(ModalXyModel::kNoises, 5);  // 000 eq. 6.4: 5 x 5
  EXPECT_EQ(CoeffXyModel::kNoises, 4);  // 000 sec. 4.4: 4 x 4
}

TEST(ModelEquations, ForwardEulerIs000Eq4_3) {
  // One step of 000 eq. 4.3 written out by hand.
  const ModalXModel model(kT, Discretization::kForwardEuler, {});
  ModalXModel::State x;
  x << 2e-5, -0.1, 0.031, 22.0, 9.9e5;
  ForceInput u;
  u.known_N = Eigen::Vector2d(-40.0, 0.0);
  const ModalXModel::State f = model.propagate(x, u, ModalXModel::Noise::Zero());
  EXPECT_DOUBLE_EQ(f[0], x[1] * kT + x[0]);
  EXPECT_DOUBLE_EQ(f[1], kT / x[2] * (-x[1] * x[3] - x[0] * x[4] + u.known_N.x()) + x[1]);
  EXPECT_EQ(f.tail<3>(), x.tail<3>());
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
