// Speed of the cut-run signal processing (`make bench`; not part of the tests). Figures in
// docs/cut-processing.md: the offset search of 000 sec. 5.1 (one simulation, then 360
// candidates and two golden-section refinements, each a resampling of the simulated
// revolution), and the tachometer and runout-contour steps on a record of the EXPERIMENT_FORMAT
// example's length (47.4 s at 100 kHz).
#include <benchmark/benchmark.h>

#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/milling/simulation.h"
#include "analysis/sync/cut_synth.h"
#include "analysis/sync/offset_angle.h"
#include "analysis/sync/tip_deflection.h"

namespace {

using namespace chatterlab;

// 000 table 5.2, incline trial 1, 000 sec. 5.2 conditions.
milling::SimulationOptions incline_trial1() {
  milling::SimulationOptions o;
  o.modal_x = {0.03134, 22.21, 9.840e5};
  o.coefficients = {milling::cutting_coefficients(0.2483e9, 0.2196e9),
                    milling::cutting_coefficients(6.641e9, 4.154e9)};
  return o;
}

// A measured mean revolution at 1 mm: the simulator's steady revolution shifted by 147.3 deg,
// on 400 phase points.
sync::RevolutionMean measured_revolution() {
  milling::SimulationOptions o = incline_trial1();
  o.depth = milling::DepthProfile::constant(1e-3, 60);
  milling::RecordingRequest rec;
  rec.full_revolutions = {59};
  const milling::SimulationResult sim = milling::simulate(o, rec);
  sync::RevolutionMean m;
  m.x_m.resize(400);
  m.y_m.resize(400);
  for (int j = 0; j < 400; ++j) {
    const double theta = kTwoPi * j / 400 + 147.3 * kDegToRad;
    m.x_m[j] = sync::periodic_interpolate(sim.records[0].x_m, theta);
    m.y_m[j] = sync::periodic_interpolate(sim.records[0].y_m, theta);
  }
  return m;
}

void BM_OffsetSearchOnly(benchmark::State& state) {
  const sync::RevolutionMean m = measured_revolution();
  milling::SimulationOptions o = incline_trial1();
  o.depth = milling::DepthProfile::constant(1e-3, 60);
  milling::RecordingRequest rec;
  rec.full_revolutions = {59};
  const milling::SimulationResult sim = milling::simulate(o, rec);
  const sync::RevolutionMatcher matcher(m.x_m, m.y_m, sim.records[0].x_m, sim.records[0].y_m);
  for (auto _ : state) {
    const sync::OffsetSearch s = sync::search_offset(matcher, 2);
    benchmark::DoNotOptimize(s.offset_angle_deg);
  }
}
BENCHMARK(BM_OffsetSearchOnly)->Unit(benchmark::kMillisecond);

void BM_FindOffsetAngle(benchmark::State& state) {
  const sync::RevolutionMean m = measured_revolution();
  const milling::SimulationOptions o = incline_trial1();
  for (auto _ : state) {
    const sync::OffsetAngleResult r = sync::find_offset_angle(m, o, 1e-3);
    if (!r.summary.ok()) state.SkipWithError(r.summary.message.c_str());
    benchmark::DoNotOptimize(r.search.offset_angle_deg);
  }
}
BENCHMARK(BM_FindOffsetAngle)->Unit(benchmark::kMillisecond);

// Tachometer angle and tip deflection (contour from 0.9 s of air) on 4.74 M samples: a record of
// the cut-record generator (sync/cut_synth.h), 11,849 revolutions of air with 3 um runout and
// 2e-7 m noise at the sensors, then one revolution of cutting.
void BM_TachAndTipDeflection47s(benchmark::State& state) {
  sync::CutRecordSpec spec;
  spec.cut = incline_trial1();
  spec.cut.depth = milling::DepthProfile::constant(1e-3, 1);
  spec.air_revolutions = 11849;
  spec.tail_revolutions = 0;
  spec.offset_angle_deg = 143.2;
  spec.noise_tip_m = 2e-7 * spec.sensor_to_tip;
  spec.contour.eccentricity_m = 3e-6;
  spec.contour.eccentricity_angle_rad = 0.7;
  spec.seed = 3;
  const sync::CutRecord rec = sync::synthesize_cut_record(spec);
  const Eigen::VectorXd& x = rec.x_sensor_m;
  const Eigen::VectorXd& y = rec.y_sensor_m;
  const Eigen::Index n = x.size();
  for (auto _ : state) {
    const sync::TachAngle t = sync::tach_angle(rec.tach_V, 100000.0, 15000.0);
    const sync::TipDeflection d = sync::tip_deflection(x, y, t, 2.78, 0.0, 0.9);
    if (!d.summary.ok()) state.SkipWithError(d.summary.message.c_str());
    benchmark::DoNotOptimize(d.x_m.data());
  }
  state.SetItemsProcessed(state.iterations() * n);
}
BENCHMARK(BM_TachAndTipDeflection47s)->Unit(benchmark::kMillisecond);

}  // namespace
