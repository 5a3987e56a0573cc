// The linear KalmanFilter and the ExtendedKalmanFilter (analysis/kalman) against a batch
// weighted least-squares solution and the information form, against each other on a linear
// model, and the properties of the shared update: Joseph = standard form for the optimal gain,
// a measurement subset = the update with the reduced H, consider states held, P symmetric PSD,
// no allocation in a step.
#include "analysis/kalman/kalman_filter.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <random>
#include <vector>

#include "analysis/kalman/extended_kalman_filter.h"
#include "tests/support/count_allocations.h"

namespace chatterlab {
namespace kalman {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

template <int R, int C>
Matrix<R, C> gaussian(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Matrix<R, C> m;
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = n(rng);
  return m;
}

// Symmetric positive definite with eigenvalues >= floor.
template <int N>
Matrix<N, N> random_spd(std::mt19937_64& rng, double floor = 0.1) {
  const Matrix<N, N> G = gaussian<N, N>(rng);
  return G * G.transpose() + floor * Matrix<N, N>::Identity();
}

template <int N, int U, int M>
LinearModel<N, U, M> random_model(std::mt19937_64& rng) {
  LinearModel<N, U, M> m;
  m.A = gaussian<N, N>(rng);
  // Dynamic size: GCC takes about 30 s per fixed size to instantiate EigenSolver and RealSchur.
  const Eigen::EigenSolver<MatrixXd> eig(MatrixXd(m.A), false);
  m.A *= 0.95 / eig.eigenvalues().cwiseAbs().maxCoeff();
  m.B = gaussian<N, U>(rng);
  m.C = gaussian<M, N>(rng);
  m.Q = 0.2 * random_spd<N>(rng);
  m.R = random_spd<M>(rng);
  return m;
}

template <int M>
MeasurementMask<M> random_mask(std::mt19937_64& rng) {
  return MeasurementMask<M>(rng() & ((1u << M) - 1u));
}

double relative(const MatrixXd& X, const MatrixXd& ref) { return (X - ref).norm() / ref.norm(); }

// A linear model in the EKF's model interface, f(x, u) = A x + B u, h(x) = C x (written for this
// test from the interface of extended_kalman_filter.h).
template <int N, int U, int M>
class LinearEkfModel {
 public:
  static constexpr int kStates = N;
  static constexpr int kMeasurements = M;
  using State = Matrix<N, 1>;
  using Input = Matrix<U, 1>;
  using Measurement = Matrix<M, 1>;
  explicit LinearEkfModel(const LinearModel<N, U, M>& m) : m_(m) {}
  State propagate(const State& x, const Input& u, Matrix<N, N>* J_f_x) const {
    if (J_f_x) *J_f_x = m_.A;
    return m_.A * x + m_.B * u;
  }
  void add_process_noise(const State&, Matrix<N, N>* P) const { *P += m_.Q; }
  Measurement measure(const State& x, Matrix<M, N>* J_h_x) const {
    if (J_h_x) *J_h_x = m_.C;
    return m_.C * x;
  }
  const Matrix<M, M>& measurement_noise() const { return m_.R; }

 private:
  LinearModel<N, U, M> m_;
};

// The same with C selecting states 2, 0 (the filter takes its selection path).
class SelectingEkfModel : public LinearEkfModel<3, 1, 2> {
 public:
  using LinearEkfModel<3, 1, 2>::LinearEkfModel;
  static constexpr int measured_state(int i) { return i == 0 ? 2 : 0; }
};

TEST(KalmanFilter, FilteredEstimateEqualsBatchWeightedLeastSquares) {
  // x[k+1] = A x[k] + B u[k] + w, z[k] = rows of C x[k] + v (a random subset each step, some
  // empty) with a Gaussian prior on x[0]. The weighted least-squares estimate of the whole
  // trajectory X = (x[0..K]) minimizes
  //   |x0 - m0|^2_P0^-1 + sum |x[k+1] - A x[k] - B u[k]|^2_Q^-1 + sum |z_s[k] - C_s
  //   x[k]|^2_R_ss^-1,
  // i.e. solves the normal equations Lambda X = eta; its last block and the last diagonal block
  // of Lambda^-1 are the filtered x[K] and P[K] (the Kalman filter is the recursive solution of
  // this problem). Tolerance 1e-10 relative: a dense solve of 39 unknowns, condition ~1e3.
  constexpr int N = 3, U = 1, M = 3, K = 12;
  std::mt19937_64 rng(21);
  const LinearModel<N, U, M> m = random_model<N, U, M>(rng);
  const Matrix<N, 1> m0 = gaussian<N, 1>(rng);
  const Matrix<N, N> P0 = random_spd<N>(rng);
  KalmanFilter<N, U, M> f(m, m0, P0);

  const int n = N * (K + 1);
  MatrixXd Lambda = MatrixXd::Zero(n, n);
  VectorXd eta = VectorXd::Zero(n);
  const Matrix<N, N> P0i = P0.inverse(), Qi = m.Q.inverse();
  Lambda.topLeftCorner<N, N>() += P0i;
  eta.head<N>() += P0i * m0;
  for (int k = 0; k < K; ++k) {
    const Matrix<U, 1> u = gaussian<U, 1>(rng);
    const Matrix<M, 1> z = gaussian<M, 1>(rng);
    const MeasurementMask<M> present = random_mask<M>(rng);
    f.predict(u);
    f.update(z, present);
    // Process term: e = D X - B u with D = [-A I] on blocks (k, k + 1).
    MatrixXd D = MatrixXd::Zero(N, n);
    D.block<N, N>(0, N * k) = -m.A;
    D.block<N, N>(0, N * (k + 1)).setIdentity();
    Lambda += D.transpose() * Qi * D;
    eta += D.transpose() * Qi * (m.B * u);
    // Measurement term on block k + 1, present rows only.
    std::vector<int> rows;
    for (int i = 0; i < M; ++i) {
      if (present[static_cast<std::size_t>(i)]) rows.push_back(i);
    }
    if (rows.empty()) continue;
    const int s = static_cast<int>(rows.size());
    MatrixXd Cs(s, N), Rs(s, s);
    VectorXd zs(s);
    for (int a = 0; a < s; ++a) {
      Cs.row(a) = m.C.row(rows[static_cast<std::size_t>(a)]);
      zs[a] = z[rows[static_cast<std::size_t>(a)]];
      for (int b = 0; b < s; ++b) {
        Rs(a, b) = m.R(rows[static_cast<std::size_t>(a)], rows[static_cast<std::size_t>(b)]);
      }
    }
    const MatrixXd Rsi = Rs.inverse();
    Lambda.block<N, N>(N * (k + 1), N * (k + 1)) += Cs.transpose() * Rsi * Cs;
    eta.segment<N>(N * (k + 1)) += Cs.transpose() * Rsi * zs;
  }
  const Eigen::LDLT<MatrixXd> ldlt(Lambda);
  const VectorXd X = ldlt.solve(eta);
  const MatrixXd cov = ldlt.solve(MatrixXd::Identity(n, n));
  EXPECT_LT(relative(f.state(), X.tail<N>()), 1e-10);
  EXPECT_LT(relative(f.covariance(), cov.bottomRightCorner<N, N>()), 1e-10);
}

TEST(KalmanFilter, StaticStateEqualsTheInformationForm) {
  // A constant state (A = I, Q = 0) seen through a random subset of three rows each step: the
  // filtered estimate is the information-form solution
  //   P^-1 = P0^-1 + sum C_s^T R_ss^-1 C_s,  x = P (P0^-1 m0 + sum C_s^T R_ss^-1 z_s)
  // (diagonal R here, so R_ss^-1 is the present rows' 1 / r_i). Tolerance 1e-11 relative.
  constexpr int N = 2, M = 3, K = 40;
  std::mt19937_64 rng(5);
  LinearModel<N, 0, M> m;
  m.C = gaussian<M, N>(rng);
  m.R = Matrix<M, M>::Zero();
  m.R.diagonal() << 0.5, 2.0, 0.1;
  const Matrix<N, 1> m0(1.0, -2.0);
  const Matrix<N, N> P0 = 4.0 * Matrix<N, N>::Identity();
  KalmanFilter<N, 0, M> f(m, m0, P0);
  Matrix<N, N> info = P0.inverse();
  Matrix<N, 1> vec = P0.inverse() * m0;
  for (int k = 0; k < K; ++k) {
    const Matrix<M, 1> z = gaussian<M, 1>(rng);
    const MeasurementMask<M> present = random_mask<M>(rng);
    f.predict(Matrix<0, 1>());
    f.update(z, present);
    for (int i = 0; i < M; ++i) {
      if (!present[static_cast<std::size_t>(i)]) continue;
      info += m.C.row(i).transpose() * m.C.row(i) / m.R(i, i);
      vec += m.C.row(i).transpose() * z[i] / m.R(i, i);
    }
  }
  const Matrix<N, N> P = info.inverse();
  EXPECT_LT(relative(f.state(), P * vec), 1e-11);
  EXPECT_LT(relative(f.covariance(), P), 1e-11);
}

TEST(ExtendedKalmanFilter, EqualsTheKalmanFilterOnALinearModel) {
  // Same model, inputs, measurements, subsets and consider sets: the EKF through the model
  // interface (generic and selection paths) and the KF through its matrices give the same
  // estimates. Tolerance 1e-12 relative over 500 steps (both run the same update on the same
  // numbers; the margin covers a different order of summation).
  for (CovarianceUpdate form : {CovarianceUpdate::kStandard, CovarianceUpdate::kJoseph}) {
    std::mt19937_64 rng(3);
    LinearModel<3, 1, 2> m = random_model<3, 1, 2>(rng);
    FilterOptions o;
    o.covariance_update = form;
    const Matrix<3, 1> x0 = gaussian<3, 1>(rng);
    const Matrix<3, 3> P0 = random_spd<3>(rng);
    KalmanFilter<3, 1, 2> kf(m, x0, P0, o);
    ExtendedKalmanFilter<LinearEkfModel<3, 1, 2>> ekf(LinearEkfModel<3, 1, 2>(m), x0, P0, o);
    LinearModel<3, 1, 2> ms = m;
    ms.C << 0, 0, 1, 1, 0, 0;  // rows select states 2 and 0
    KalmanFilter<3, 1, 2> kf_select(ms, x0, P0, o);
    ExtendedKalmanFilter<SelectingEkfModel> ekf_select(SelectingEkfModel(ms), x0, P0, o);
    for (int k = 0; k < 500; ++k) {
      const Matrix<1, 1> u = gaussian<1, 1>(rng);
      const Matrix<2, 1> z = gaussian<2, 1>(rng);
      const MeasurementMask<2> present = random_mask<2>(rng);
      const StateMask<3> considered(k % 7 == 0 ? 2u : 0u);
      kf.predict(u);
      ekf.predict(u);
      kf_select.predict(u);
      ekf_select.predict(u);
      const Innovation a = kf.update(z, present, considered);
      const Innovation b = ekf.update(z, present, considered);
      const Innovation c = kf_select.update(z, present, considered);
      const Innovation d = present.all() && considered.none()
                               ? ekf_select.update(z)
                               : ekf_select.update(z, present, considered);
      ASSERT_EQ(a.dimension, b.dimension);
      if (a.dimension > 0) {
        ASSERT_NEAR(a.nis, b.nis, 1e-12 * a.nis);
        ASSERT_NEAR(c.nis, d.nis, 1e-12 * c.nis);
      }
    }
    EXPECT_LT(relative(ekf.state(), kf.state()), 1e-12);
    EXPECT_LT(relative(ekf.covariance(), kf.covariance()), 1e-12);
    EXPECT_LT(relative(ekf_select.state(), kf_select.state()), 1e-12);
    EXPECT_LT(relative(ekf_select.covariance(), kf_select.covariance()), 1e-12);
  }
}

TEST(MeasurementUpdate, JosephEqualsStandardForTheOptimalGain) {
  // (I - K H) P (I - K H)^T + K R K^T = P - K H P when K = P H^T S^-1; with consider states the
  // standard form's zeroed block is the exact covariance of the consider gain, i.e. again the
  // Joseph form of that gain. Tolerance 1e-12 relative (5 x 5 products of O(1) entries).
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    LinearModel<5, 0, 3> m = random_model<5, 0, 3>(rng);
    const Matrix<5, 1> x0 = gaussian<5, 1>(rng);
    const Matrix<5, 5> P0 = random_spd<5>(rng);
    const Matrix<3, 1> z = gaussian<3, 1>(rng);
    for (const StateMask<5> considered : {StateMask<5>(0u), StateMask<5>(0b10110u)}) {
      FilterOptions joseph;
      joseph.covariance_update = CovarianceUpdate::kJoseph;
      KalmanFilter<5, 0, 3> a(m, x0, P0), b(m, x0, P0, joseph);
      a.update(z, all_rows<3>(), considered);
      b.update(z, all_rows<3>(), considered);
      EXPECT_EQ(a.state(), b.state());
      EXPECT_LT(relative(a.covariance(), b.covariance()), 1e-12) << "trial " << trial;
    }
  }
}

TEST(MeasurementUpdate, ConsiderStatesKeepTheirEstimateAndCovariance) {
  // The Schmidt update corrects the other states exactly as the full update does (same gain
  // rows) and leaves the consider states' estimates and their covariance block as they were.
  std::mt19937_64 rng(13);
  LinearModel<4, 0, 2> m = random_model<4, 0, 2>(rng);
  const Matrix<4, 1> x0 = gaussian<4, 1>(rng);
  const Matrix<4, 4> P0 = random_spd<4>(rng);
  const Matrix<2, 1> z = gaussian<2, 1>(rng);
  KalmanFilter<4, 0, 2> full(m, x0, P0), held(m, x0, P0);
  full.update(z);
  held.update(z, all_rows<2>(), StateMask<4>(0b1100u));  // states 2 and 3 considered
  EXPECT_TRUE((held.state().head<2>() == full.state().head<2>()));
  EXPECT_TRUE((held.state().tail<2>() == x0.tail<2>()));
  EXPECT_TRUE((held.covariance().topLeftCorner<2, 2>() == full.covariance().topLeftCorner<2, 2>()));
  EXPECT_TRUE((held.covariance().bottomRightCorner<2, 2>() == P0.bottomRightCorner<2, 2>()));
}

TEST(MeasurementUpdate, SubsetEqualsTheUpdateWithTheReducedH) {
  // Rows {0, 2} of a 3-row measurement with correlated R against a 2-row model whose C and R are
  // those rows (R's sub-block): same estimate, covariance and NIS. Tolerance 1e-13 relative
  // (fixed- vs dynamic-size arithmetic may sum in another order).
  std::mt19937_64 rng(17);
  const LinearModel<4, 0, 3> m = random_model<4, 0, 3>(rng);
  LinearModel<4, 0, 2> r;
  r.A = m.A;
  r.Q = m.Q;
  r.C << m.C.row(0), m.C.row(2);
  r.R << m.R(0, 0), m.R(0, 2), m.R(2, 0), m.R(2, 2);
  const Matrix<4, 1> x0 = gaussian<4, 1>(rng);
  const Matrix<4, 4> P0 = random_spd<4>(rng);
  const Matrix<3, 1> z = gaussian<3, 1>(rng);
  KalmanFilter<4, 0, 3> subset(m, x0, P0);
  KalmanFilter<4, 0, 2> reduced(r, x0, P0);
  const Innovation a = subset.update(z, MeasurementMask<3>(0b101u));
  const Innovation b = reduced.update(Matrix<2, 1>(z[0], z[2]));
  EXPECT_EQ(a.dimension, 2);
  EXPECT_NEAR(a.nis, b.nis, 1e-13 * b.nis);
  EXPECT_LT(relative(subset.state(), reduced.state()), 1e-13);
  EXPECT_LT(relative(subset.covariance(), reduced.covariance()), 1e-13);
  // No row present: nothing changes.
  const Innovation none = subset.update(z, MeasurementMask<3>());
  EXPECT_EQ(none.dimension, 0);
  EXPECT_TRUE(std::isnan(none.nis));
  EXPECT_LT(relative(subset.state(), reduced.state()), 1e-13);
}

TEST(MeasurementUpdate, NisIsTheNormalizedInnovationSquared) {
  // nu^T S^-1 nu with S = C P C^T + R inverted explicitly (an independent evaluation).
  // Tolerance 1e-12 relative.
  std::mt19937_64 rng(19);
  const LinearModel<4, 0, 3> m = random_model<4, 0, 3>(rng);
  const Matrix<4, 1> x0 = gaussian<4, 1>(rng);
  const Matrix<4, 4> P0 = random_spd<4>(rng);
  const Matrix<3, 1> z = gaussian<3, 1>(rng);
  KalmanFilter<4, 0, 3> f(m, x0, P0);
  const Innovation i = f.update(z);
  const Matrix<3, 1> nu = z - m.C * x0;
  const Matrix<3, 3> S = m.C * P0 * m.C.transpose() + m.R;
  const double expected = nu.dot(S.inverse() * nu);
  EXPECT_EQ(i.dimension, 3);
  EXPECT_NEAR(i.nis, expected, 1e-12 * expected);
}

TEST(MeasurementUpdate, ANonPositiveInnovationCovarianceLeavesNaN) {
  // S = R = -1 (P = 0): no update is possible; the estimate becomes NaN for the caller's check.
  LinearModel<2, 0, 1> m;
  m.C << 1.0, 0.0;
  m.R << -1.0;
  KalmanFilter<2, 0, 1> f(m, Matrix<2, 1>::Ones(), Matrix<2, 2>::Zero());
  const Innovation i = f.update(Matrix<1, 1>::Constant(3.0));
  EXPECT_TRUE(std::isnan(i.nis));
  EXPECT_FALSE(f.state().allFinite());
}

TEST(MeasurementUpdate, CovarianceStaysSymmetricPositiveSemidefinite) {
  // 20,000 steps of a 6-state model with random subsets and consider sets, both forms, P0 and R
  // spanning 12 orders of magnitude. Checked every 100 steps in correlation coordinates
  // (entries <= 1): exactly symmetric, eigenvalues >= -1e-12 (rounding of a 6 x 6 eigen-solve
  // ~1e-15; 1e-12 still flags a real loss of definiteness).
  for (CovarianceUpdate form : {CovarianceUpdate::kStandard, CovarianceUpdate::kJoseph}) {
    std::mt19937_64 rng(23);
    LinearModel<6, 0, 3> m = random_model<6, 0, 3>(rng);
    m.R.setZero();
    m.R.diagonal() << 1e-6, 1.0, 1e6;
    m.Q *= 1e-4;
    Matrix<6, 6> P0 = Matrix<6, 6>::Zero();
    P0.diagonal() << 1e-6, 1e-3, 1.0, 1e2, 1e4, 1e6;
    FilterOptions o;
    o.covariance_update = form;
    KalmanFilter<6, 0, 3> f(m, Matrix<6, 1>::Zero(), P0, o);
    double smallest = 1.0;
    for (int k = 0; k < 20000; ++k) {
      f.predict(Matrix<0, 1>());
      f.update(gaussian<3, 1>(rng), random_mask<3>(rng), StateMask<6>(k % 5 == 0 ? 0b110000u : 0u));
      if (k % 100 != 0) continue;
      const Matrix<6, 6>& P = f.covariance();
      ASSERT_EQ(P, P.transpose()) << "step " << k;
      const Matrix<6, 1> d = P.diagonal().cwiseSqrt().cwiseInverse();
      const Matrix<6, 6> Cor = d.asDiagonal() * P * d.asDiagonal();
      const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(MatrixXd(Cor), Eigen::EigenvaluesOnly);
      smallest = std::min(smallest, eig.eigenvalues().minCoeff());
      ASSERT_GE(eig.eigenvalues().minCoeff(), -1e-12) << "step " << k;
    }
    RecordProperty(form == CovarianceUpdate::kJoseph ? "smallest_eigenvalue_joseph"
                                                     : "smallest_eigenvalue_standard",
                   std::to_string(smallest));
  }
}

TEST(KalmanFilter, AStepAllocatesNothing) {
  if (!kCountingMalloc) GTEST_SKIP() << "malloc is not counted under AddressSanitizer";
  std::mt19937_64 rng(29);
  const LinearModel<4, 1, 3> m = random_model<4, 1, 3>(rng);
  FilterOptions joseph;
  joseph.covariance_update = CovarianceUpdate::kJoseph;
  KalmanFilter<4, 1, 3> kf(m, Matrix<4, 1>::Zero(), Matrix<4, 4>::Identity(), joseph);
  ExtendedKalmanFilter<LinearEkfModel<4, 1, 3>> ekf(LinearEkfModel<4, 1, 3>(m),
                                                    Matrix<4, 1>::Zero(), Matrix<4, 4>::Identity());
  std::vector<Matrix<3, 1>> z(64);
  for (auto& v : z) v = gaussian<3, 1>(rng);
  chatterlab::testing::g_allocations = 0;
  chatterlab::testing::g_counting = true;
  for (int k = 0; k < 1000; ++k) {
    const Matrix<3, 1>& zk = z[static_cast<std::size_t>(k % 64)];
    const MeasurementMask<3> present(static_cast<unsigned>(k % 8));
    const StateMask<4> considered(static_cast<unsigned>(k % 3));
    kf.predict(Matrix<1, 1>::Constant(0.1));
    kf.update(zk, present, considered);
    ekf.predict(Matrix<1, 1>::Constant(0.1));
    ekf.update(zk);
    ekf.update(zk, present, considered);
    ekf.update_consider(zk, considered);
  }
  chatterlab::testing::g_counting = false;
  EXPECT_EQ(chatterlab::testing::g_allocations, 0);
}

}  // namespace
}  // namespace kalman
}  // namespace chatterlab
