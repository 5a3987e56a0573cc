// Speed of the EKF estimators (`make bench`; figures in docs/estimators.md). Target: one 6-state
// filter step (predict + update, 000 eqs 4.5-4.9) at >= 2 million steps per second on one core.
//
// BM_FilterStep<Model, unscented>: the filter alone (the EKF, or the UKF of
// unscented_kalman_filter.h) on precomputed force inputs and measurements.
// BM_Estimator/<variant>: a whole ekf_* call on 0.2 s of 000 table 5.2's incline-1 cut at 1 mm
// (simulated at the filter step 5e-7 s, 5e-7 m noise): 396,000 steps, chips and history
// included. items/s = steps/s (per-tooth: steps of the pair of filters).
#include <benchmark/benchmark.h>

#include <random>
#include <type_traits>
#include <vector>

#include "analysis/estimate/ekf.h"
#include "analysis/estimate/ekf_variants.h"
#include "analysis/milling/simulation.h"

namespace {

using namespace chatterlab;
using namespace chatterlab::estimate;

const MeasuredCut& bench_cut() {
  static const MeasuredCut cut = [] {
    milling::SimulationOptions o;
    o.modal_x = {0.03134, 22.21, 9.840e5};
    o.coefficients = {milling::cutting_coefficients(2.483e8, 2.196e8),
                      milling::cutting_coefficients(6.641e9, 4.154e9)};
    o.steps_per_tooth = 4000;  // 5e-7 s
    o.depth = milling::DepthProfile::constant(1e-3, 81);
    milling::RecordingRequest rq;
    for (int j = 30; j < 81; ++j) rq.full_revolutions.push_back(j);
    const milling::SimulationResult sim = milling::simulate(o, rq);
    const int S = sim.steps_per_revolution;
    const Eigen::Index n = 400001;
    MeasuredCut c;
    c.time_step_s = sim.time_step_s;
    c.x_m.resize(n);
    c.y_m.resize(n);
    c.theta1_rad.resize(n);
    std::mt19937_64 rng(1);
    std::normal_distribution<double> noise(0.0, 5e-7);
    for (Eigen::Index k = 0; k < n; ++k) {
      const milling::RevolutionRecord& r = sim.records[static_cast<std::size_t>(k / S)];
      c.x_m[k] = r.x_m[k % S] + noise(rng);
      c.y_m[k] = r.y_m[k % S] + noise(rng);
      c.theta1_rad[k] = r.theta1_rad[k % S];
    }
    c.depth_m = Eigen::VectorXd::Constant(1, 1e-3);
    return c;
  }();
  return cut;
}

const std::vector<ToothCoefficients> kCoefficients{{2.483e8, 2.196e8}, {6.641e9, 4.154e9}};
const ModalParameters kModal{0.03134, 22.21, 9.840e5};

// The filter step alone: inputs and measurements of 4,096 samples of the cut, cycled.
template <class Model, bool kUnscented>
void BM_FilterStep(benchmark::State& state) {
  const MeasuredCut& cut = bench_cut();
  const CutChips chips(cut, CutSetup{});
  constexpr int kSamples = 4096;
  std::vector<ForceInput> inputs(kSamples);
  std::vector<typename Model::Measurement> z(kSamples);
  for (int i = 0; i < kSamples; ++i) {
    const StepChips c = chips.chips(chips.first_step() + i);
    if constexpr (Model::kKt >= 0) {
      inputs[static_cast<std::size_t>(i)].regressor_m2 =
          tooth_regressor_m2(c.tooth[0]) + tooth_regressor_m2(c.tooth[1]);
    } else {
      inputs[static_cast<std::size_t>(i)].known_N = cutting_force_N(c, kCoefficients);
    }
    z[static_cast<std::size_t>(i)][0] = cut.x_m[chips.first_step() + i + 1];
    if constexpr (Model::kMeasurements == 2) {
      z[static_cast<std::size_t>(i)][1] = cut.y_m[chips.first_step() + i + 1];
    }
  }
  const Model model(cut.time_step_s, Discretization::kSymplecticEuler, kModal);
  typename Model::State x0 = Model::State::Zero();
  for (int i = Model::kFirstParameter; i < Model::kStates; ++i) x0[i] = 1.0;
  if constexpr (Model::kMass >= 0) x0[Model::kMass] = kModal.m_kg;
  if constexpr (Model::kStiffness >= 0) x0[Model::kStiffness] = kModal.k_N_m;
  if constexpr (Model::kKt >= 0) x0.template tail<2>() << 2e9, 1e9;
  typename Model::StateMatrix P0 = Model::StateMatrix::Identity();
  if constexpr (kUnscented) {
    // Sigma points with positive masses: deflections of 0.1 mm, 1 m/s, parameters 20 %.
    for (int a = 0; a < Model::kAxes; ++a) P0(2 * a, 2 * a) = 1e-8;
    for (int i = Model::kFirstParameter; i < Model::kStates; ++i) {
      P0(i, i) = 0.04 * x0[i] * x0[i];
    }
  }
  using Filter = std::conditional_t<kUnscented, ToolUkf<Model>, ToolEkf<Model>>;
  Filter f = [&]() {
    const auto q = Model::Noise::Constant(0.1);
    const auto r = Model::Measurement::Constant(1e-10);
    if constexpr (kUnscented) {
      return make_tool_ukf(model, x0, P0, q, r, kalman::UnscentedOptions{});
    } else {
      return make_tool_ekf(model, x0, P0, q, r);
    }
  }();
  std::size_t i = 0;
  for (auto _ : state) {
    f.predict(inputs[i]);
    f.update(z[i]);
    i = (i + 1) % kSamples;
    benchmark::DoNotOptimize(f.state().data());
  }
  state.SetItemsProcessed(state.iterations());  // items/s = filter steps/s
}
BENCHMARK_TEMPLATE(BM_FilterStep, ModalXModel, false);
BENCHMARK_TEMPLATE(BM_FilterStep, ModalXyModel, false);
BENCHMARK_TEMPLATE(BM_FilterStep, ModalXyMkModel, false);
BENCHMARK_TEMPLATE(BM_FilterStep, ModalXyMcModel, false);
BENCHMARK_TEMPLATE(BM_FilterStep, CoeffXyModel, false);
BENCHMARK_TEMPLATE(BM_FilterStep, ModalXModel, true);
BENCHMARK_TEMPLATE(BM_FilterStep, ModalXyModel, true);
BENCHMARK_TEMPLATE(BM_FilterStep, ModalXyMkModel, true);
BENCHMARK_TEMPLATE(BM_FilterStep, ModalXyMcModel, true);
BENCHMARK_TEMPLATE(BM_FilterStep, CoeffXyModel, true);

void BM_Estimator(benchmark::State& state) {
  const EstimatorId id = static_cast<EstimatorId>(state.range(0));
  const MeasuredCut& cut = bench_cut();
  std::int64_t steps = 0;
  for (auto _ : state) {
    EkfResult r;
    if (is_modal(id)) {
      r = ekf_modal(id, cut, CutSetup{}, {kCoefficients, {0.02270, 22.21, 1.162e6}});
    } else if (structure_of(id) == EstimatorId::kCoeffXy) {
      r = ekf_coeff(id, cut, CutSetup{}, {kModal, {{2e9, 1e9}}});
    } else {
      r = ekf_coeff(id, cut, CutSetup{}, {kModal, {{1.493e8, 2.315e8}, {4.257e9, 3.106e9}}});
    }
    if (!r.summary.ok()) state.SkipWithError(r.summary.message.c_str());
    steps += r.steps;
    benchmark::DoNotOptimize(r.final_state.data());
  }
  state.SetItemsProcessed(steps);
  state.SetLabel(estimator_name(id));
}
BENCHMARK(BM_Estimator)
    ->DenseRange(0, static_cast<int>(kEstimatorCount) - 1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
