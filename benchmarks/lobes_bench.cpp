// Speed of the stability-lobe analysis (`make bench`; not part of the tests). Figures in
// docs/lobes.md. A 200-speed diagram of the semi-discretization: the single-degree-of-freedom
// benchmark of Insperger & Stepan 2004 made flexible on x and y (one mode each, so the state
// has 4 entries and the delay map 4 + 2 m), down-milling a/D = 0.05, 5,000-25,000 rpm, depths
// up to 10 mm by a 16-point scan and bisection to 0.1 %, m = 30 intervals per tooth period.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "analysis/common/constants.h"
#include "analysis/lobes/lobes.h"

namespace {

using namespace chatterlab;
using namespace chatterlab::lobes;

LobesInput diagram() {
  LobesInput in;
  in.teeth = 2;
  in.radius_m = 10e-3;
  in.Kt_N_m2 = {6e8, 6e8};
  in.Kr_N_m2 = {2e8, 2e8};
  in.operation = milling::Operation::kDownMilling;
  in.radial_immersion_m = 0.05 * 2.0 * in.radius_m;
  const double m = 0.03993, wn = kTwoPi * 922.0, zeta = 0.011;
  in.x_modes = {{m, 2.0 * zeta * m * wn, m * wn * wn}};
  in.y_modes = in.x_modes;
  for (int i = 0; i < 200; ++i) in.spindle_rpm.push_back(5000.0 + 20000.0 * i / 199.0);
  in.max_depth_m = 10e-3;
  return in;
}

void BM_LobesSemiDiscretization200Speeds(benchmark::State& state) {
  const LobesInput in = diagram();
  SemiDiscretizationOptions o;
  o.threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const LobesResult r = semi_discretization(in, o);
    benchmark::DoNotOptimize(r.speeds.data());
  }
  state.SetItemsProcessed(state.iterations() * 200);  // items/s = speeds/s
}
BENCHMARK(BM_LobesSemiDiscretization200Speeds)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The worst case for the eigenvalue problem: slotting, every delayed block read (64 x 64).
void BM_LobesSemiDiscretization200SpeedsSlot(benchmark::State& state) {
  LobesInput in = diagram();
  in.radial_immersion_m = 2.0 * in.radius_m;
  for (auto _ : state) {
    const LobesResult r = semi_discretization(in);
    benchmark::DoNotOptimize(r.speeds.data());
  }
  state.SetItemsProcessed(state.iterations() * 200);
}
BENCHMARK(BM_LobesSemiDiscretization200SpeedsSlot)->Unit(benchmark::kMillisecond);

// The 200 speeds of `in` by semi-discretization at its automatic m, on state.range(0) threads.
void run_automatic_m(benchmark::State& state, const LobesInput& in) {
  SemiDiscretizationOptions o;
  o.steps_per_tooth = automatic_steps_per_tooth(in);
  o.threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const LobesResult r = semi_discretization(in, o);
    benchmark::DoNotOptimize(r.speeds.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(in.spindle_rpm.size()));
}

// The same diagram at the automatic m (a/D = 0.05: 81 intervals per tooth period).
void BM_LobesAutomaticM200Speeds(benchmark::State& state) { run_automatic_m(state, diagram()); }
BENCHMARK(BM_LobesAutomaticM200Speeds)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The brute-force stability chart: |mu| on a 200 x 200 grid of speed x depth (40,000 Floquet
// evaluations), m = 30 and the automatic m.
void BM_LobesGrid200x200(benchmark::State& state) {
  const LobesInput in = diagram();
  SemiDiscretizationOptions o;
  o.steps_per_tooth = state.range(1) > 0 ? automatic_steps_per_tooth(in) : 30;
  o.threads = static_cast<int>(state.range(0));
  std::vector<double> depths;
  for (int j = 1; j <= 200; ++j) depths.push_back(10e-3 * j / 200.0);
  for (auto _ : state) {
    const Eigen::MatrixXd g = sd_spectral_radius_grid(in, o, depths);
    benchmark::DoNotOptimize(g.data());
  }
  state.SetItemsProcessed(state.iterations() * 40000);
}
BENCHMARK(BM_LobesGrid200x200)
    ->Args({1, 0})
    ->Args({2, 0})
    ->Args({2, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The demo campaign's hammer/dyno diagram: two modes per axis (state 8), Ktc, Krc of the dyno
// group, up-milling at 0.382 mm of a 12.7 mm tool (automatic m = 109), 7,500-22,500 rpm.
LobesInput demo_hammer_modes() {
  LobesInput in;
  in.teeth = 2;
  in.radius_m = 6.35e-3;
  in.Kt_N_m2 = {5.89e8, 5.89e8};
  in.Kr_N_m2 = {3.19e8, 3.19e8};
  in.operation = milling::Operation::kUpMilling;
  in.radial_immersion_m = 0.382e-3;
  in.x_modes = {{0.03211, 13.39, 1.023e6}, {0.06, 30.0, 1.8e7}};
  in.y_modes = {{0.03211, 13.39, 1.023e6}, {0.07, 35.0, 2.4e7}};
  for (int i = 0; i < 200; ++i) in.spindle_rpm.push_back(7500.0 + 15000.0 * i / 199.0);
  in.max_depth_m = 10e-3;
  return in;
}
void BM_LobesDemoHammerModes200Speeds(benchmark::State& state) {
  run_automatic_m(state, demo_hammer_modes());
}
BENCHMARK(BM_LobesDemoHammerModes200Speeds)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_LobesZeroOrder200Speeds(benchmark::State& state) {
  const LobesInput in = diagram();
  for (auto _ : state) {
    const ZeroOrderResult r = zero_order(in);
    benchmark::DoNotOptimize(r.lobes.speeds.data());
  }
}
BENCHMARK(BM_LobesZeroOrder200Speeds)->Unit(benchmark::kMillisecond);

}  // namespace
