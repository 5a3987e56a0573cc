// Speed of the ERA realization (analysis/sysid/era.h) at the largest Hankel matrix of the
// format (alpha = 1000: 4096 Markov parameters of a 30-state random system with white noise
// at 10 dB SNR), against a full SVD of the same matrix (Eigen BDCSVD, thin U and V): the
// symmetric eigenpair route of era.h against the textbook one (001 eq. 3.15). And the
// validation study of 001 sec. 3.3 (analysis/sysid/era_validation.h), run once and printed to
// stderr: ERA and the frequency-domain subspace method on 50 systems a level at 10 and 0 dB.
#include <benchmark/benchmark.h>

#include <Eigen/SVD>
#include <cmath>
#include <iostream>
#include <random>
#include <string>

#include "analysis/sysid/era.h"
#include "analysis/sysid/era_validation.h"
#include "analysis/sysid/random_system.h"

namespace {

using namespace chatterlab;
using namespace chatterlab::sysid;

constexpr double kFs = 10000.0;

// y_0 = D, y_k = C A^(k-1) B, k < 4096, of a 30-state system, plus white noise at 10 dB.
Eigen::VectorXd bench_markov() {
  RandomSystemOptions o;
  o.order = 30;
  const DiscreteStateSpace s = random_stable_system(o, kFs, 30);
  const int N = 4096;
  Eigen::VectorXd y(N);
  y[0] = s.D;
  Eigen::VectorXd x = s.B;
  for (int k = 1; k < N; ++k) {
    y[k] = s.C.dot(x);
    x = s.A * x;
  }
  const double sigma = std::sqrt(y.squaredNorm() / N / 10.0);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> noise(0.0, sigma);
  for (int k = 0; k < N; ++k) y[k] += noise(rng);
  return y;
}

void BM_EraRealize1000(benchmark::State& state) {
  const Eigen::VectorXd y = bench_markov();
  EraRealization r;
  for (auto _ : state) {
    r = era_realize(y, kFs);
    if (!r.summary.ok()) state.SkipWithError(r.summary.message.c_str());
    benchmark::DoNotOptimize(r.model.A.data());
  }
  state.counters["hankel"] = r.hankel_size;
  state.counters["order"] = static_cast<double>(r.model.order());
  state.counters["svd_s"] = r.svd_s;
}
BENCHMARK(BM_EraRealize1000)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same 1000 x 1000 Hankel matrix H[i][j] = y[i+j+1] (era.h step 3), full SVD.
void BM_HankelBdcSvd1000(benchmark::State& state) {
  const Eigen::VectorXd y = bench_markov();
  const int alpha = 1000;
  Eigen::MatrixXd H(alpha, alpha);
  for (int j = 0; j < alpha; ++j) H.col(j) = y.segment(j + 1, alpha);
  for (auto _ : state) {
    Eigen::BDCSVD<Eigen::MatrixXd> svd(H, Eigen::ComputeThinU | Eigen::ComputeThinV);
    benchmark::DoNotOptimize(svd.singularValues().data());
  }
}
BENCHMARK(BM_HankelBdcSvd1000)->Unit(benchmark::kMillisecond)->UseRealTime();

// range(0): record length N; range(1): 0 for the Gavish-Donoho orders (the defaults), or a
// fixed order for both methods (ERA with a vanishing known noise level and the cap at that
// order), to show what the order rule costs.
void BM_EraValidationTable(benchmark::State& state) {
  EraValidationOptions o;
  o.record_length = static_cast<int>(state.range(0));
  const int fixed = static_cast<int>(state.range(1));
  if (fixed > 0) {
    o.era.markov_noise_std = 1e-200;
    o.era.max_order = fixed;
    o.subspace.order = fixed;
  }
  EraValidationStudy study;
  for (auto _ : state) {
    study = run_era_validation(o);
    benchmark::DoNotOptimize(study.rows.data());
  }
  std::cerr << (fixed > 0 ? "fixed order " + std::to_string(fixed) : "Gavish-Donoho orders") << ", "
            << format_validation_table(study);
  for (const EraValidationLevel& l : study.levels) {
    const std::string db = std::to_string(static_cast<int>(l.snr_db)) + "dB";
    state.counters["era_median_" + db] = l.era.median;
    state.counters["era_p10_" + db] = l.era.p10;
    state.counters["sub_median_" + db] = l.subspace.median;
    state.counters["sub_p10_" + db] = l.subspace.p10;
  }
  state.SetLabel("N = " + std::to_string(o.record_length) +
                 (fixed > 0 ? ", order " + std::to_string(fixed) : ", G-D order"));
}
BENCHMARK(BM_EraValidationTable)
    ->Args({2048, 0})
    ->Args({512, 0})
    ->Args({2048, 30})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
