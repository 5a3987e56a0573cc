// Speed of the regularized deconvolution (analysis/forcerec/deconvolution.h, 004 eq. 2.27,
// format `rd`) on 60 s records of one axis: 384,000 samples at 6400 Hz and 614,400 at
// 10240 Hz (issue 9: at least 1.5 M samples/s with the tuning). The model is a sixth-order
// dynamometer axis (three modes at 004 Table 3.1's x-axis poles, 1411.8 Hz / 0.0214 the
// lightest), the force a mean and six harmonics of 511.5 Hz, R = 0.02 N^2.
// BM_RdTuned: the three rules, discrepancy chosen, exact solve and check (items/s = samples/s).
// BM_RdOneSolve: one exact solve at a given alpha with its check.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "analysis/forcerec/deconvolution.h"

namespace {

using namespace chatterlab::forcerec;

ContinuousModel bench_model() {
  struct Mode {
    double fn_hz, zeta, weight;
  };
  const Mode modes[] = {{1411.8, 0.0214, 0.4}, {1458.8, 0.163, 0.2}, {1518.6, 0.0221, 0.4}};
  ContinuousModel m;
  m.A = Eigen::MatrixXd::Zero(6, 6);
  m.B = Eigen::VectorXd::Zero(6);
  m.C = Eigen::RowVectorXd::Zero(6);
  for (int r = 0; r < 3; ++r) {
    const double wn = 2 * M_PI * modes[r].fn_hz, z = modes[r].zeta;
    m.A.block(2 * r, 2 * r, 2, 2) << 0, wn, -wn, -2 * z * wn;
    m.B[2 * r + 1] = 1.0;
    m.C[2 * r] = modes[r].weight * wn;
    m.C[2 * r + 1] = modes[r].weight * 3000.0;
  }
  return m;
}

struct Record {
  DiscreteModel model;
  Eigen::VectorXd y;
};

// range: samples; 384000 -> 6400 Hz, else 10240 Hz (60 s either way).
Record bench_record(Eigen::Index n) {
  const double fs = n == 384000 ? 6400.0 : 10240.0;
  Record r{zoh(bench_model(), fs), Eigen::VectorXd(n)};
  std::mt19937_64 rng(9);
  std::normal_distribution<double> nd(0.0, std::sqrt(0.02));
  Eigen::VectorXd F = Eigen::VectorXd::Constant(n, 30.0);
  const double amp[] = {20, 8, 5, 3, 2, 1};
  for (Eigen::Index k = 0; k < n; ++k) {
    for (int j = 0; j < 6; ++j) F[k] += amp[j] * std::cos(2 * M_PI * (j + 1) * 511.5 * k / fs + j);
  }
  r.y = simulate(r.model, F);
  for (Eigen::Index k = 0; k < n; ++k) r.y[k] += nd(rng);
  return r;
}

void BM_RdTuned(benchmark::State& state) {
  const Record rec = bench_record(state.range(0));
  double alpha = 0.0;
  for (auto _ : state) {
    const DeconvolutionResult res = deconvolve_tikhonov(rec.model, rec.y, 0.02);
    if (!res.summary.ok()) state.SkipWithError(res.summary.message.c_str());
    alpha = res.alpha;
    benchmark::DoNotOptimize(res.force_N.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.counters["alpha"] = alpha;
}
BENCHMARK(BM_RdTuned)->Arg(384000)->Arg(614400)->Arg(768000)->Unit(benchmark::kMillisecond);

void BM_RdOneSolve(benchmark::State& state) {
  const Record rec = bench_record(state.range(0));
  for (auto _ : state) {
    const DeconvolutionResult res = deconvolve_tikhonov_at(rec.model, rec.y, 4e-3);
    if (!res.summary.ok()) state.SkipWithError(res.summary.message.c_str());
    benchmark::DoNotOptimize(res.force_N.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_RdOneSolve)->Arg(384000)->Arg(614400)->Unit(benchmark::kMillisecond);

}  // namespace
