// Speed of the estimation core (analysis/kalman): one step of the linear Kalman filter with a
// full, a subset (multirate) and a Joseph-form update, the steady-state gain of a 6-state model,
// and the chi-square band of a whole run's mean NIS (items/s = steps/s or solves/s).
#include <benchmark/benchmark.h>

#include <Eigen/Eigenvalues>
#include <random>
#include <vector>

#include "analysis/kalman/chi_square.h"
#include "analysis/kalman/dare.h"
#include "analysis/kalman/kalman_filter.h"

namespace {

using namespace chatterlab::kalman;

constexpr int N = 6, U = 1, M = 2;

LinearModel<N, U, M> bench_model() {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n(0.0, 1.0);
  LinearModel<N, U, M> m;
  for (Eigen::Index i = 0; i < m.A.size(); ++i) m.A.data()[i] = n(rng);
  const Eigen::EigenSolver<Matrix<N, N>> eig(m.A, false);
  m.A *= 0.98 / eig.eigenvalues().cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < m.B.size(); ++i) m.B.data()[i] = n(rng);
  for (Eigen::Index i = 0; i < m.C.size(); ++i) m.C.data()[i] = n(rng);
  m.Q = 0.01 * Matrix<N, N>::Identity();
  m.R = Matrix<M, M>::Identity();
  return m;
}

// mode 0: every row; 1: the second row every fifth step (multirate); 2: Joseph form.
void BM_KalmanStep(benchmark::State& state) {
  const int mode = static_cast<int>(state.range(0));
  FilterOptions o;
  if (mode == 2) o.covariance_update = CovarianceUpdate::kJoseph;
  KalmanFilter<N, U, M> f(bench_model(), Matrix<N, 1>::Zero(), Matrix<N, N>::Identity(), o);
  std::mt19937_64 rng(2);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Matrix<M, 1>> z(1024);
  for (auto& v : z) v << n(rng), n(rng);
  std::size_t i = 0;
  int k = 0;
  for (auto _ : state) {
    f.predict(Matrix<U, 1>::Constant(0.1));
    if (mode == 1) {
      f.update(z[i], MeasurementMask<M>(k % 5 == 0 ? 0b11u : 0b01u));
    } else {
      f.update(z[i]);
    }
    i = (i + 1) % z.size();
    ++k;
    benchmark::DoNotOptimize(f.state().data());
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(mode == 0 ? "full" : mode == 1 ? "multirate" : "joseph");
}
BENCHMARK(BM_KalmanStep)->DenseRange(0, 2);

void BM_SteadyStateGain(benchmark::State& state) {
  const LinearModel<N, U, M> m = bench_model();
  for (auto _ : state) {
    const SteadyStateKalman s = steady_state_gain(m.A, m.C, m.Q, m.R);
    if (!s.summary.ok()) state.SkipWithError(s.summary.message.c_str());
    benchmark::DoNotOptimize(s.K.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SteadyStateGain)->Unit(benchmark::kMicrosecond);

// The band of the mean NIS of 396,000 two-row updates (chi-square(792000) / 396000).
void BM_MeanNisBand(benchmark::State& state) {
  for (auto _ : state) {
    const ChiSquareBand b = mean_chi_square_band(396000, 2);
    benchmark::DoNotOptimize(b.upper);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_MeanNisBand)->Unit(benchmark::kMicrosecond);

}  // namespace
