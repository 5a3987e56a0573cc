// Speed of the AKF force reconstruction (analysis/forcerec/akf.h, 004 eqs 2.6-2.11) on a 6th
// order dynamometer axis (004's X axis poles and zeros, 7 augmented states) over a 60 s record
// at 10240 Hz (614,400 samples; items/s = record samples/s): the filter pass with a given gain in
// its modal and dense forms, the whole `akf` of the format (101-value S sweep over 1.05 s of the
// cut window, then the pass), and one design (DARE and modal form). The issue asks for
// 20 M samples/s per axis, tuning included (numpy: 6-9 M/s with the steady-state gain).
#include <benchmark/benchmark.h>

#include <complex>
#include <random>
#include <vector>

#include "analysis/forcerec/akf.h"
#include "analysis/forcerec/model.h"

namespace {

using namespace chatterlab;
using namespace chatterlab::forcerec;

constexpr double kAkfBenchFs = 10240.0;
constexpr Eigen::Index kAkfBenchSamples = 614400;

// Sum of second-order sections in real modal form with the given poles (fn Hz, zeta) and zeros
// (relative degree one), unit DC gain: 004's X axis (notes/004.md sec. 2).
ContinuousModel akf_bench_model() {
  using cd = std::complex<double>;
  auto root = [](double fn, double zeta) {
    const double w = 2.0 * M_PI * fn;
    return cd(-zeta * w, w * std::sqrt(1.0 - zeta * zeta));
  };
  const std::vector<cd> p0 = {root(1411.8, 0.0214), root(1458.8, 0.163), root(1518.6, 0.0221)};
  std::vector<cd> p, z = {root(1421.0, 0.041), root(1570.9, 0.050)};
  for (const cd& r : p0) {
    p.push_back(r);
    p.push_back(std::conj(r));
  }
  z.push_back(std::conj(z[0]));
  z.push_back(std::conj(z[1]));
  z.emplace_back(-21734.0, 0.0);
  cd h0 = 1.0;
  for (const cd& zi : z) h0 *= -zi;
  for (const cd& pi : p) h0 /= -pi;
  ContinuousModel m;
  m.A = Eigen::MatrixXd::Zero(6, 6);
  m.B = Eigen::VectorXd::Zero(6);
  m.C = Eigen::RowVectorXd::Zero(6);
  for (int i = 0; i < 6; i += 2) {
    cd r = 1.0 / h0.real();
    for (const cd& zi : z) r *= p[i] - zi;
    for (int l = 0; l < 6; ++l) {
      if (l != i) r /= p[i] - p[l];
    }
    m.A.block<2, 2>(i, i) << p[i].real(), -p[i].imag(), p[i].imag(), p[i].real();
    m.B[i] = 1.0;
    m.C[i] = 2.0 * r.real();
    m.C[i + 1] = -2.0 * r.imag();
  }
  return m;
}

struct AkfBenchRecord {
  DiscreteModel model;
  Eigen::VectorXd y;
};

// Mean 30 N and five tooth harmonics at 511.5 Hz through the model, noise 0.007 N^2.
const AkfBenchRecord& akf_bench_record() {
  static const AkfBenchRecord r = [] {
    AkfBenchRecord out;
    out.model = zoh(akf_bench_model(), kAkfBenchFs);
    Eigen::VectorXd F(kAkfBenchSamples);
    const double amp[5] = {20.0, 8.0, 5.0, 3.0, 2.0};
    for (Eigen::Index k = 0; k < F.size(); ++k) {
      const double t = (static_cast<double>(k) + 0.5) / kAkfBenchFs;
      double v = 30.0;
      for (int h = 0; h < 5; ++h) v += amp[h] * std::cos(2.0 * M_PI * (h + 1) * 511.5 * t + h);
      F[k] = v;
    }
    out.y = simulate(out.model, F);
    std::mt19937_64 rng(3);
    std::normal_distribution<double> nd(0.0, std::sqrt(0.007));
    for (Eigen::Index k = 0; k < out.y.size(); ++k) out.y[k] += nd(rng);
    return out;
  }();
  return r;
}

// range(0): 1 modal form, 0 dense (the same filter, S = 6.3 N^2: the knee of this record).
void BM_AkfPass6thOrder(benchmark::State& state) {
  const AkfBenchRecord& r = akf_bench_record();
  AkfFilter f = design_akf(r.model, 6.30957, 0.007);
  if (state.range(0) == 0) {
    f.modal = false;
    f.b = f.L;
    f.g = f.G_a;
    f.h = -f.K[6] * f.G_a;
    f.h[6] += 1.0;
  }
  Eigen::VectorXd force(r.y.size());
  for (auto _ : state) {
    run_akf(f, r.y, &force);
    benchmark::DoNotOptimize(force.data());
  }
  state.SetItemsProcessed(state.iterations() * r.y.size());
  state.SetLabel(f.modal ? "modal" : "dense");
}
BENCHMARK(BM_AkfPass6thOrder)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// One value of the sweep: E(S) over the tuning window (0.05 s skipped + 1 s summed).
void BM_AkfErrorNorm6thOrder(benchmark::State& state) {
  const AkfBenchRecord& r = akf_bench_record();
  const AkfFilter f = design_akf(r.model, 6.30957, 0.007);
  const SampleWindow w = akf_tuning_window(r.y.size(), kAkfBenchFs, 0.6, 59.9);
  for (auto _ : state) {
    double E = akf_error_norm(f, r.y, w.begin, w.end, 512);
    benchmark::DoNotOptimize(E);
  }
  state.SetItemsProcessed(state.iterations() * (w.end - w.begin));
}
BENCHMARK(BM_AkfErrorNorm6thOrder)->Unit(benchmark::kMicrosecond);

// The format's `akf` with S by the knee: tuning over [0.6 s, 0.6 s + 1.05 s), then the pass.
void BM_AkfWithTuning6thOrder(benchmark::State& state) {
  const AkfBenchRecord& r = akf_bench_record();
  const SampleWindow w = akf_tuning_window(r.y.size(), kAkfBenchFs, 0.6, 59.9);
  double S = 0.0;
  for (auto _ : state) {
    const AkfResult a = reconstruct_force_akf(r.model, r.y, 0.007, w);
    S = a.S_N2;
    benchmark::DoNotOptimize(a.force.data());
  }
  state.SetItemsProcessed(state.iterations() * r.y.size());
  state.SetLabel("S = " + std::to_string(S));
}
BENCHMARK(BM_AkfWithTuning6thOrder)->Unit(benchmark::kMillisecond);

// One design: DARE by doubling on the 7-state augmented model, then the modal form.
void BM_AkfDesign6thOrder(benchmark::State& state) {
  const AkfBenchRecord& r = akf_bench_record();
  for (auto _ : state) {
    AkfFilter f = design_akf(r.model, 6.30957, 0.007);
    benchmark::DoNotOptimize(f.K.data());
  }
}
BENCHMARK(BM_AkfDesign6thOrder)->Unit(benchmark::kMicrosecond);

}  // namespace
