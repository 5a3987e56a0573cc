// Speed of the milling simulator (`make bench`; not part of the tests). Figures in
// docs/simulator.md. The incline is 000 sec. 5.2: 0 to 6 mm at 1,290 revolutions per mm,
// 800 steps per tooth, two teeth: 7,740 revolutions, 12,384,000 steps. Targets on one core of
// the project's 2-core machine: traditional model <= 0.2 s, numerical model <= 5 s.
#include <benchmark/benchmark.h>

#include "analysis/milling/simulation.h"

namespace {

using namespace chatterlab::milling;

// Table 5.2, incline trial 1 (bifurcates near 2.3 mm: most of the run chatters).
SimulationOptions incline_trial1() {
  SimulationOptions o;
  o.modal_x = {0.03134, 22.21, 9.840e5};
  o.coefficients = {cutting_coefficients(0.2483e9, 0.2196e9),
                    cutting_coefficients(6.641e9, 4.154e9)};
  return o;
}

void run(benchmark::State& state, const SimulationOptions& o) {
  std::int64_t steps = 0;
  for (auto _ : state) {
    const SimulationResult r = simulate(o);
    if (!r.summary.ok()) state.SkipWithError(r.summary.message.c_str());
    steps += r.steps;
    benchmark::DoNotOptimize(r.samples.x_m.data());
  }
  state.SetItemsProcessed(steps);  // items/s = steps/s
}

void BM_InclineTraditional(benchmark::State& state) { run(state, incline_trial1()); }
BENCHMARK(BM_InclineTraditional)->Unit(benchmark::kMillisecond);

void BM_InclineTraditionalPositionFirst(benchmark::State& state) {
  SimulationOptions o = incline_trial1();
  o.euler_order = EulerOrder::kPositionFirst;
  run(state, o);
}
BENCHMARK(BM_InclineTraditionalPositionFirst)->Unit(benchmark::kMillisecond);

// Inertial forces act at every step: no force-free fast path. 12,384,000 steps at a constant
// 0.4 mm (000 figs 7.3-7.9; trial 1 with inertial forces diverges above ~1.1 mm).
void BM_ConstantDepthTraditionalInertial(benchmark::State& state) {
  SimulationOptions o = incline_trial1();
  o.depth = DepthProfile::constant(0.4e-3, 7740);
  o.inertial.enabled = true;
  o.inertial.eccentricity_m = 1e-5;
  o.inertial.eccentricity_angle_rad = 5.17;
  o.initial_deflection_m = {1e-8, 1e-8};
  run(state, o);
}
BENCHMARK(BM_ConstantDepthTraditionalInertial)->Unit(benchmark::kMillisecond);

void BM_InclineNumerical(benchmark::State& state) {
  SimulationOptions o = incline_trial1();
  o.chip_model = ChipModel::kNumerical;
  run(state, o);
}
BENCHMARK(BM_InclineNumerical)->Unit(benchmark::kMillisecond)->Iterations(2);

// Plain against fast search on the same chattering run (constant 3 mm, 200 revolutions, long
// window throughout): the same trajectory, bit for bit.
void BM_Chatter3mmNumerical(benchmark::State& state) {
  SimulationOptions o = incline_trial1();
  o.chip_model = ChipModel::kNumerical;
  o.numerical.fast_search = state.range(0) != 0;
  o.depth = DepthProfile::constant(3.0e-3, 200);
  run(state, o);
}
BENCHMARK(BM_Chatter3mmNumerical)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
