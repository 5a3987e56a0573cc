// Speed of the SIFS compensator (analysis/sifs/compensator.h) on the notes/003.md section 7
// plant (k = 3: 9 states) at 10 kHz: compensate() on a 1 s cut record (items/s = samples/s)
// with the time-varying gain (its sequence computed until it converges, then held) and the
// steady-state gain (the DARE once per call), and the tap map over a 47-speed grid (1000 ..
// 24000 rpm in 500 rpm steps, q = 2^1 .. 2^30, three 0.2 s hits) on one and on two threads.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "analysis/common/constants.h"
#include "analysis/sifs/compensator.h"

namespace {

using namespace chatterlab;
using namespace chatterlab::sifs;

constexpr double kFs = 10000.0;

std::vector<SensorMode> bench_plant() {
  return {{420.0, 0.03, 0.55}, {980.0, 0.04, 0.40}, {2400.0, 0.05, 0.05}};
}

// Tooth passing at 600 Hz with SF harmonics and noise: the force is irrelevant to the speed.
Eigen::VectorXd bench_record(Eigen::Index samples) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> noise(0.0, 3.0);
  Eigen::VectorXd z(samples);
  for (Eigen::Index i = 0; i < samples; ++i) {
    const double t = static_cast<double>(i) / kFs;
    z[i] = 80.0 + 30.0 * std::cos(kTwoPi * 600.0 * t) + 10.0 * std::cos(kTwoPi * 150.0 * t) +
           noise(rng);
  }
  return z;
}

// range(0): 0 time-varying, 1 steady-state.
void BM_Compensate9States(benchmark::State& state) {
  const GainMode gain = state.range(0) == 0 ? GainMode::kTimeVarying : GainMode::kSteadyState;
  const CompensatorModel m = make_compensator(bench_plant(), 600.0, kFs);
  const Eigen::VectorXd z = bench_record(10000);
  Eigen::VectorXd est(z.size());
  for (auto _ : state) {
    const StepSummary s = compensate(m, std::ldexp(1.0, 15), 10.0, gain, z, &est);
    if (!s.ok()) state.SkipWithError(s.message.c_str());
    benchmark::DoNotOptimize(est.data());
  }
  state.SetItemsProcessed(state.iterations() * z.size());
  state.SetLabel(to_string(gain));
}
BENCHMARK(BM_Compensate9States)->DenseRange(0, 1)->Unit(benchmark::kMicrosecond);

// Synthetic taps as in tests/analysis/sifs/compensator_test.cpp: half-sine hits through the
// zero-order-hold plant, 0.15 N noise.
TapSweepInput bench_taps(const std::vector<SensorMode>* modes) {
  constexpr Eigen::Index kWindow = 2048, kImpact = 300, kHits = 3;
  const Eigen::Index k = static_cast<Eigen::Index>(modes->size());
  Eigen::MatrixXd Aug = Eigen::MatrixXd::Zero(2 * k + 1, 2 * k + 1);
  Eigen::RowVectorXd C = Eigen::RowVectorXd::Zero(2 * k);
  for (Eigen::Index i = 0; i < k; ++i) {
    const SensorMode& mode = (*modes)[static_cast<std::size_t>(i)];
    const double w = kTwoPi * mode.fn_hz;
    Aug.block(2 * i, 2 * i, 2, 2) << 0.0, w, -w, -2.0 * mode.zeta * w;
    Aug(2 * i + 1, 2 * k) = w;
    C(2 * i) = mode.alpha;
  }
  const Eigen::MatrixXd E = (Aug / kFs).exp();
  TapSweepInput in;
  in.modes = modes;
  in.hammer_n = Eigen::VectorXd::Zero(kWindow * kHits);
  for (Eigen::Index w = 0; w < kHits; ++w) {
    for (Eigen::Index i = 0; i < 6; ++i) {
      in.hammer_n[w * kWindow + kImpact + i] = 200.0 * std::sin(kPi * (i + 0.5) / 6.0);
    }
    in.windows.push_back({w * kWindow, (w + 1) * kWindow});
    in.pre_end.push_back(kImpact - 10);
  }
  std::mt19937_64 rng(17);
  std::normal_distribution<double> noise(0.0, 0.15);
  in.response_n.resize(in.hammer_n.size());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * k);
  for (Eigen::Index i = 0; i < in.hammer_n.size(); ++i) {
    in.response_n[i] = C.dot(x) + noise(rng);
    x = E.topLeftCorner(2 * k, 2 * k) * x + E.topRightCorner(2 * k, 1) * in.hammer_n[i];
  }
  in.filter_rate_hz = kFs;
  in.r_tap_n = 0.15;
  in.band_lo_hz = 10.0;
  in.band_hi_hz = 4000.0;
  return in;
}

// range(0): threads.
void BM_TapMap47Speeds(benchmark::State& state) {
  const std::vector<SensorMode> modes = bench_plant();
  const TapSweepInput in = bench_taps(&modes);
  std::vector<double> rpm;
  for (double n = 1000.0; n <= 24000.0; n += 500.0) rpm.push_back(n);
  for (auto _ : state) {
    const TapMap map = tap_map(in, rpm, 4, static_cast<int>(state.range(0)));
    benchmark::DoNotOptimize(map.rmse_n.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(rpm.size()));
  state.SetLabel(std::to_string(rpm.size()) + " speeds x 30 q");
}
BENCHMARK(BM_TapMap47Speeds)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
