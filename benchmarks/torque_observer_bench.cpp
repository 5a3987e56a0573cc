// Speed of the spindle torque observer (analysis/sysid/torque_observer.h, 001 ch. 4) on a
// 30-state drive model (a random stable system, 31 states with the torque): run_torque_observer
// in its real modal form and the dense recursion of the format's step 4 over a 1 M sample
// record (items/s = samples/s), and the design (DARE, modal form) once.
#include <benchmark/benchmark.h>

#include <random>

#include "analysis/sysid/random_system.h"
#include "analysis/sysid/torque_observer.h"

namespace {

using namespace chatterlab;
using namespace chatterlab::sysid;

TorqueObserver bench_observer() {
  RandomSystemOptions o;
  o.order = 30;
  return design_torque_observer(random_stable_system(o, 10000.0, 1), 0.01, 8.33e-6);
}

Eigen::VectorXd bench_current(Eigen::Index n) {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> nd;
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) y[i] = nd(rng);
  return y;
}

// range(0): 1 modal form, 0 dense.
void BM_TorqueObserver30States(benchmark::State& state) {
  const TorqueObserver obs = bench_observer();
  const Eigen::VectorXd y = bench_current(1'000'000);
  Eigen::VectorXd tau(y.size());
  for (auto _ : state) {
    if (state.range(0) == 1) {
      run_torque_observer(obs, y, &tau);
    } else {
      run_torque_observer_dense(obs, y, &tau);
    }
    benchmark::DoNotOptimize(tau.data());
  }
  state.SetItemsProcessed(state.iterations() * y.size());
  state.SetLabel(state.range(0) == 1 ? (obs.modal ? "modal" : "dense (no modal form)") : "dense");
}
BENCHMARK(BM_TorqueObserver30States)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

void BM_TorqueObserverDesign30States(benchmark::State& state) {
  RandomSystemOptions o;
  o.order = 30;
  const DiscreteStateSpace m = random_stable_system(o, 10000.0, 1);
  for (auto _ : state) {
    TorqueObserver obs = design_torque_observer(m, 0.01, 8.33e-6);
    benchmark::DoNotOptimize(obs.K.data());
  }
}
BENCHMARK(BM_TorqueObserverDesign30States)->Unit(benchmark::kMillisecond);

}  // namespace
