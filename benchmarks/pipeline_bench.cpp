// Speed of the foundation steps (`make bench`; not part of the tests). Figures in
// docs/performance.md.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "analysis/cutting/dyno_slot.h"
#include "analysis/cutting/slot_synth.h"
#include "analysis/frf/frf.h"
#include "analysis/frf/hits.h"
#include "analysis/frf/modal_fit.h"
#include "analysis/frf/modal_response.h"
#include "app/core/signals.h"

namespace {

using namespace chatterlab;

const std::filesystem::path kDir = std::filesystem::temp_directory_path() / "chatterlab-bench";

cutting::SlotRecord slot_record() {
  cutting::SlotRecordSpec s;
  s.spindle_rpm = 600;
  s.feed_per_tooth_m = 0.1e-3;
  s.coefficients = {5.89e8, 3.19e8, 9080, 11300};
  s.theta_dyn_rad = 0.65;
  s.noise_std_N = 2;
  s.fs_hz = 20000;
  s.duration_s = 2.0;
  return cutting::generate_slot_record(s);
}

frf::TapRecord tap_record() {
  const std::vector<frf::Mode> modes = {frf::mode_from_mck(0.03134, 22.21, 9.84e5),
                                        frf::mode_from_mck(0.06, 52.0, 1.8e7)};
  std::vector<frf::HammerPulse> pulses;
  for (int i = 0; i < 5; ++i) pulses.push_back({0.2 + i * 1.0, 150.0, 3e-4});
  frf::TapSynthesisOptions o;
  o.response_noise_fraction = 0.01;
  o.force_noise_fraction = 0.001;
  return frf::synthesize_tap_record(modes, pulses, 25600, 5 * 25600 + 5120,
                                    frf::ResponseKind::kAcceleration, o);
}

// One dyno slot record of 40k samples: edges, offsets, theta_dyn search, mean forces.
void BM_DynoSlotRecord(benchmark::State& state) {
  const auto rec = slot_record();
  for (auto _ : state) {
    auto r = cutting::analyse_slot_record(rec.Fx_N, rec.Fy_N, rec.zero_V, rec.fs_hz, 600);
    benchmark::DoNotOptimize(r.theta_dyn_rad);
  }
  state.SetItemsProcessed(state.iterations() * rec.Fx_N.size());
}
BENCHMARK(BM_DynoSlotRecord)->Unit(benchmark::kMillisecond);

// Tap test of 5 hits at 25.6 kHz: hits, H1/H2, coherence, two-mode fit.
void BM_TapHitsFrfFit(benchmark::State& state) {
  const auto rec = tap_record();
  for (auto _ : state) {
    const auto hits = frf::detect_hits(rec.force_n, rec.response, 25600);
    const auto f =
        frf::compute_frf(rec.force_n, rec.response, hits, frf::ResponseKind::kAcceleration);
    const auto fit = frf::fit_modes(f);
    benchmark::DoNotOptimize(fit.fit_nrmse_pct);
  }
}
BENCHMARK(BM_TapHitsFrfFit)->Unit(benchmark::kMillisecond);

// CSV parse of 3 columns x rows, then one calibrated channel.
void BM_CsvLoad(benchmark::State& state) {
  const auto rows = static_cast<Eigen::Index>(state.range(0));
  std::filesystem::create_directories(kDir);
  const auto file = kDir / "bench.csv";
  Eigen::VectorXd a = Eigen::VectorXd::Random(rows), b = Eigen::VectorXd::Random(rows),
                  c = Eigen::VectorXd::Random(rows);
  app::write_signals(file, {"Fx", "Fy", "zero"}, {&a, &b, &c});
  app::DataSpec d;
  d.file = file;
  d.relative_file = "bench.csv";
  for (auto _ : state) {
    const auto t = app::SignalTable::open(d, "bench.csv");
    benchmark::DoNotOptimize(t.channel("Fy")[0]);
  }
  state.SetItemsProcessed(state.iterations() * rows * 3);
  state.SetBytesProcessed(state.iterations() *
                          static_cast<int64_t>(std::filesystem::file_size(file)));
}
BENCHMARK(BM_CsvLoad)->Arg(1 << 20)->Unit(benchmark::kMillisecond);

// Raw .f32 of 3 channels x rows: map, NaN scan, one calibrated channel.
void BM_RawF32Load(benchmark::State& state) {
  const auto rows = static_cast<Eigen::Index>(state.range(0));
  std::filesystem::create_directories(kDir);
  const auto file = kDir / "bench.f32";
  Eigen::VectorXd a = Eigen::VectorXd::Random(rows);
  app::write_signals(file, {"x", "y", "tach"}, {&a, &a, &a});
  app::DataSpec d;
  d.file = file;
  d.relative_file = "bench.f32";
  d.channels = {"x", "y", "tach"};
  app::ChannelSpec cal;
  cal.scale = 3.9e-5;
  for (auto _ : state) {
    const auto t = app::SignalTable::open(d, "bench.f32");
    benchmark::DoNotOptimize(t.channel("y", cal)[0]);
  }
  state.SetItemsProcessed(state.iterations() * rows * 3);
  state.SetBytesProcessed(state.iterations() * rows * 12);
}
BENCHMARK(BM_RawF32Load)->Arg(1 << 24)->Unit(benchmark::kMillisecond);

}  // namespace
