// Speed of the grinding filters (analysis/grinding/multirate_ekf.h, 002 appendix B): each of the
// four estimators over a 40-cycle series of 002 sec. V (n_i = 850, 34,040 fast instants) with
// every fourth inspection arriving two cycles late (replays) and a dressing. items/s = fast
// instants (sum of n_i + 1) per second of a whole run, replays and outputs included; the
// counter `replayed` is the fast rows run again per run. The mark: 2 M steps/s for the
// 4-state filter with replays (a numpy loop reaches 17-27 k steps/s).
#include <benchmark/benchmark.h>

#include "analysis/grinding/grinding_synth.h"
#include "analysis/grinding/multirate_ekf.h"

namespace {

using namespace chatterlab::grinding;

const GrindingSeries& bench_series() {
  static const GrindingSeries s = [] {
    GrindingSeriesSpec spec;
    spec.cycles = 40;
    spec.seed = 11;
    spec.truth.G1 = 14.1;
    for (int c = 4; c <= 36; c += 4) spec.late.push_back({c, c + 2});
    spec.dressings = {{21, 0.04}};
    return synthesize_grinding_series(spec);
  }();
  return s;
}

void BM_GrindingEstimator(benchmark::State& state) {
  const auto id = kGrindingEstimators[static_cast<std::size_t>(state.range(0))].id;
  const GrindingSeries& s = bench_series();
  const GrindingParameters p;
  const GrindingFilterSettings f;
  const std::vector<Dressing> dressings = {{21, 0.04}};
  long steps = 0, replayed = 0;
  for (auto _ : state) {
    GrindingRun r = run_grinding_estimator(id, p, f, s.record, s.inspections, dressings);
    benchmark::DoNotOptimize(r.per_cycle.data());
    steps += r.steps;
    replayed = r.replayed_steps;
  }
  state.SetItemsProcessed(steps);
  state.counters["replayed"] = static_cast<double>(replayed);
  state.SetLabel(kGrindingEstimators[static_cast<std::size_t>(state.range(0))].name);
}
BENCHMARK(BM_GrindingEstimator)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

}  // namespace
