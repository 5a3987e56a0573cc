// Speed of the sliding-mode observer force reconstruction (analysis/forcerec/smo.h, 004 eqs
// 2.15-2.22) on one axis of a 60 s record at 10240 Hz (614,400 samples; items/s = samples/s):
// the whole step (canonical form, ZOH, one-step inverse, exact per-interval observer) and the
// one-step inverse alone. Model: 6th order, the three x-axis modes of
// 004 Table 3.1 in real modal form. Issue 9 asks >= 5 M samples/s (numpy: 1.4-1.7 M/s).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "analysis/forcerec/smo.h"

namespace {

using namespace chatterlab::forcerec;

constexpr double kFs = 10240.0;
constexpr Eigen::Index kSamples = 614400;

ContinuousModel bench_model() {
  const double fn[3] = {1411.8, 1458.8, 1518.6}, zeta[3] = {0.0214, 0.163, 0.0221};
  const double weight[3] = {0.5, 0.3, 0.2};
  ContinuousModel m;
  m.A = Eigen::MatrixXd::Zero(6, 6);
  m.B = Eigen::VectorXd::Zero(6);
  m.C = Eigen::RowVectorXd::Zero(6);
  for (int r = 0; r < 3; ++r) {
    const int i = 2 * r;
    const double wn = 2 * M_PI * fn[r];
    m.A(i, i + 1) = wn;
    m.A(i + 1, i) = -wn;
    m.A(i + 1, i + 1) = -2 * zeta[r] * wn;
    m.B[i + 1] = wn;
    m.C[i] = weight[r];
    m.C[i + 1] = 2 * zeta[r] * weight[r];
  }
  return m;
}

// A milling-like force (mean and 8 tooth harmonics of 511.5 Hz) through the model, plus noise of
// 004's x-axis variance 0.007 N^2.
Eigen::VectorXd bench_output(const ContinuousModel& m) {
  Eigen::VectorXd F(kSamples);
  for (Eigen::Index k = 0; k < kSamples; ++k) {
    double v = 30.0;
    for (int h = 1; h <= 8; ++h) v += 20.0 / h * std::cos(2 * M_PI * h * 511.5 * k / kFs + h);
    F[k] = v;
  }
  Eigen::VectorXd y = simulate(zoh(m, kFs), F);
  std::mt19937_64 rng(4);
  std::normal_distribution<double> nd(0.0, std::sqrt(0.007));
  for (Eigen::Index k = 0; k < kSamples; ++k) y[k] += nd(rng);
  return y;
}

SmoOptions bench_options() {
  SmoOptions o;
  o.tooth_freq_hz = 511.5;
  o.harmonic_count = 8;
  return o;
}

void BM_SmoReconstruct(benchmark::State& state) {
  const ContinuousModel m = bench_model();
  const Eigen::VectorXd y = bench_output(m);
  const SmoOptions o = bench_options();
  for (auto _ : state) {
    SmoResult r = reconstruct_force_smo(m, kFs, y, o);
    if (!r.summary.ok()) state.SkipWithError(r.summary.message.c_str());
    benchmark::DoNotOptimize(r.force.data());
  }
  state.SetItemsProcessed(state.iterations() * kSamples);
}
BENCHMARK(BM_SmoReconstruct)->Unit(benchmark::kMillisecond);

void BM_SmoOneStepInverse(benchmark::State& state) {
  const ContinuousModel m = bench_model();
  const Eigen::VectorXd y = bench_output(m);
  const OneStepInverse inv = one_step_inverse(zoh(m, kFs));
  Eigen::VectorXd F(kSamples);
  for (auto _ : state) {
    run_one_step_inverse(inv, y, F);
    benchmark::DoNotOptimize(F.data());
  }
  state.SetItemsProcessed(state.iterations() * kSamples);
}
BENCHMARK(BM_SmoOneStepInverse)->Unit(benchmark::kMillisecond);

}  // namespace
