// The validation of the identification as 001 sec. 3.3 does it (notes/001.md sec. 4), as a
// study over many seeded random systems instead of one draw per case, with a second method
// (frequency_subspace.h) on the same data so that the table says whether ERA is the right
// default. For each system i = 0..systems_per_level-1 (the same systems at every SNR level):
//
// 1. seed_i = seed + i; the order n_i = min_order + splitmix64(seed_i) mod (max_order -
//    min_order + 1), uniform on min_order..max_order (10..30: "10-30 states", 001 sec. 3.3);
//    the system random_stable_system(system options with order n_i, rate, seed_i);
// 2. its impulse response over the record ("impulse"): y_0 = D, y_k = C A^(k-1) B,
//    k = 1..N-1 (001 eq. 3.12);
// 3. white Gaussian noise of standard deviation sigma, SNR = 10 log10(mean(y^2) / sigma^2)
//    over the record (notes/001.md sec. 4 convention; "awgn ... 'measured'"); SNR = +inf: none.
//    The noise generator is std::mt19937_64 seeded with splitmix64(seed_i + 1000003 level);
// 4. the FRF G_m = sum_k y_k exp(-j 2 pi m k / N) (the FFT of the noisy response: "3.3 turns the
//    noisy response into an FRF"; an impulse input has U = 1) on f_m = m rate / N, m = 0..N/2;
// 5. ERA (era_identify, EraOptions) and the subspace method (frequency_subspace_identify,
//    FrequencySubspaceOptions) on all N/2 + 1 points;
// 6. each model scored by frf_fit_pct (era.h step 7) against the noise-free FRF of the true
//    model, frequency_response(truth) at the points 0 < f_m <= rate/2 (the truth's FRF, not
//    the FFT of its truncated response: the two differ by C A^N (zI - A)^-1 B, below 4e-5
//    relative for |z| <= 0.995 and N = 2048).
//
// A failed identification (no state kept, LAPACK failure) has fit NaN in its row and counts
// as -inf in the statistics (the worst fit), so that failures lower the percentiles instead of
// vanishing from them. Percentiles are numpy's default (linear): for the n sorted values
// x_0 <= .. <= x_(n-1), P(p) = x_j + (h - j)(x_(j+1) - x_j), h = (n - 1) p / 100, j = floor h.
// Serial: one RealFft and one system at a time.
//
// Measured (defaults: seeds 1..50, median true order 18.5; GCC 12, Release; fit % median / p10):
//            N = 2048                        N = 512
//            ERA            subspace        ERA            subspace
//   10 dB    82.6 / 77.3    81.2 / 73.9     80.9 / 74.6    76.6 / 68.8
//    0 dB    49.6 / 34.0    45.4 / 27.6     45.5 / 34.4    37.9 / 13.2
// with median orders 8 / 4 (ERA) and 7 / 3 (subspace) at 10 / 0 dB: the Gavish-Donoho rule
// keeps only the modes far above the noise, and the order limits both methods. At a fixed
// order 30 for both (N = 2048): ERA 90.8 / 88.3 and 71.8 / 62.7, subspace 93.2 / 91.9 and
// 78.1 / 74.4 (benchmarks/sysid_bench.cpp, BM_EraValidationTable).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "analysis/sysid/era.h"
#include "analysis/sysid/frequency_subspace.h"
#include "analysis/sysid/random_system.h"

namespace chatterlab {
namespace sysid {

struct EraValidationOptions {
  std::vector<double> snr_db = {10.0, 0.0};  // finite, or +inf for noise-free data
  int systems_per_level = 50;                // >= 1
  int min_order = 10;                        // 1 <= min_order <= max_order
  int max_order = 30;
  int record_length = 2048;  // N: even, >= 16
  double sample_rate_hz = 10000.0;
  std::uint64_t seed = 1;
  RandomSystemOptions system;  // its order is drawn (step 1)
  EraOptions era;
  FrequencySubspaceOptions subspace;
};

// One system at one SNR level.
struct EraValidationRow {
  std::uint64_t seed = 0;
  int true_order = 0;
  double snr_db = 0.0;
  double noise_std = 0.0;  // sigma of step 3
  bool era_ok = false;
  int era_order = 0;  // of the stable model
  double era_fit_pct = std::numeric_limits<double>::quiet_NaN();
  double era_runtime_s = 0.0;
  bool subspace_ok = false;
  int subspace_order = 0;
  double subspace_fit_pct = std::numeric_limits<double>::quiet_NaN();
  double subspace_runtime_s = 0.0;
};

// Fit % statistics of one method at one level (failures as -inf).
struct FitStatistics {
  int count = 0;
  int failures = 0;
  double median = std::numeric_limits<double>::quiet_NaN();
  double p10 = std::numeric_limits<double>::quiet_NaN();
  double min = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
  double median_order = std::numeric_limits<double>::quiet_NaN();  // of the successful runs
  double median_runtime_s = std::numeric_limits<double>::quiet_NaN();
};

struct EraValidationLevel {
  double snr_db = 0.0;
  FitStatistics era;
  FitStatistics subspace;
};

struct EraValidationStudy {
  std::vector<EraValidationRow> rows;  // level by level, systems in seed order
  std::vector<EraValidationLevel> levels;
  double median_true_order = std::numeric_limits<double>::quiet_NaN();
  int record_length = 0;
  double runtime_s = 0.0;
};

// Runs steps 1-6 for every level and system. @throws InputError for options out of range.
EraValidationStudy run_era_validation(const EraValidationOptions& options = {});

// numpy's default (linear) percentile, 0 <= p <= 100, of a non-empty sample (-inf allowed).
// @throws InputError for an empty sample or p out of range.
double percentile_linear(std::vector<double> values, double p);

// The per-level table: SNR, method, median / p10 / min / max fit %, failures, median order,
// median runtime. One line a row, for logs and the benchmark's stderr.
std::string format_validation_table(const EraValidationStudy& study);

}  // namespace sysid
}  // namespace chatterlab
