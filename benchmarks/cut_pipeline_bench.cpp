// Speed of one whole cut test (`make bench`; figures in docs/identification.md): the demo
// campaign's constant-depth cut (experiments/demo.synth.yaml, written once to a temporary
// folder) through the pipeline on one thread: tachometer, runout, offset angle, the
// identification passes, the six estimator variants with observability and 10 repeatability
// runs each. Arg(0): repeatability off (estimation.repeat_runs: 0).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>

#include "app/core/campaign.h"
#include "app/kinds/cut/cut_step.h"
#include "app/pipeline/pipeline.h"
#include "app/synth/synth.h"

namespace {

using namespace chatterlab;

const std::filesystem::path& demo_campaign() {
  static const std::filesystem::path dir = [] {
    const auto d = std::filesystem::temp_directory_path() / "chatterlab-bench-cut";
    std::filesystem::remove_all(d);
    app::synthesize_campaign(
        std::filesystem::path(CHATTERLAB_SOURCE_DIR) / "experiments/demo.synth.yaml", d);
    return d;
  }();
  return dir;
}

void BM_CutTestPipeline(benchmark::State& state) {
  app::CampaignSpec spec = app::load_campaign(demo_campaign());
  if (state.range(0) == 0) {
    auto block =
        std::make_shared<app::EstimationBlock>(*spec.block<app::EstimationBlock>("estimation"));
    block->options.repeat.runs = 0;
    spec.blocks["estimation"] = block;
  }
  // Only the tap tests, the dyno group and the constant cut.
  std::vector<app::TestSpec> keep;
  for (auto& t : spec.tests) {
    if (t.kind != "cut" || t.id == "cuts/constant-1mm") keep.push_back(t);
  }
  spec.tests = keep;
  app::PipelineOptions o;
  o.jobs = 1;
  double identification_s = 0.0;
  for (auto _ : state) {
    const app::CampaignResults r = app::run_campaign(spec, o);
    for (const auto& t : r.tests) {
      if (const auto* c = t.status.ok() ? t.result_as<app::CutOutcome>() : nullptr) {
        identification_s = c->estimation.runtime_s;
      }
    }
    benchmark::DoNotOptimize(r.runtime_s);
  }
  state.counters["cut_estimation_s"] = identification_s;
}
BENCHMARK(BM_CutTestPipeline)->Arg(0)->Arg(10)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
