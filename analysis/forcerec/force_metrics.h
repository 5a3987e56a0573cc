// The figures of a reconstructed force that EXPERIMENT_FORMAT.md section 4 defines
// (kind force-record, "Figures, per axis"), shared by the kind and the synthetic-campaign writer
// so that truth.yaml and results.json mean the same thing.
//
// Evaluation window: samples k with 0.05 s <= k / fs < T - 0.01 s (T = N / fs): the AKF's
// start-up (x0 = 0) and the repeated last sample are outside it.
// With a reference force F (interval means):
//   nrmse_pct   = 100 rms(Fhat - F) / rms(F) over the window,
//   fit_pct     = 004 eq. 3.2 with F as y: 100 (1 - ||Fhat - F|| / ||F - mean F||),
//   lag_samples = the l in -10..10 maximising sum_k (Fhat(k + l) - mean)(F(k) - mean) over
//                 the window (positive: the estimate is late).
// Harmonics of the tooth-passing frequency f_tp over whole tooth periods of the cut window
// [c0, c1] (s): k0 = ceil(max(c0, 0.05) fs), k1 = floor(min(c1, T - 0.01) fs),
// P = floor((k1 - k0) f_tp / fs), n = round(P fs / f_tp); mean = mean of x(k0 .. k0 + n - 1),
// A_h = (2 / n) |sum_j x(k0 + j) exp(-2 pi i h f_tp j / fs)|, h = 1..K,
// K = min(12, floor(0.4 fs / f_tp)).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace chatterlab {
namespace forcerec {

// Samples [begin, end).
struct IndexWindow {
  Eigen::Index begin = 0;
  Eigen::Index end = 0;
  Eigen::Index size() const { return end > begin ? end - begin : 0; }
};

// The evaluation window of a record of `samples` samples at fs (empty when too short).
IndexWindow evaluation_window(Eigen::Index samples, double sample_rate_hz);

// K of the format: min(12, floor(0.4 fs / f_tp)); 0 when f_tp is not > 0.
int harmonic_count(double sample_rate_hz, double tooth_freq_hz);

// The harmonic window: k0 and k0 + n (n whole tooth periods); empty when the cut window holds
// no whole tooth period. @param cut_begin_s, cut_end_s the cut window (the whole record: 0, T).
IndexWindow harmonic_window(Eigen::Index samples, double sample_rate_hz, double tooth_freq_hz,
                            double cut_begin_s, double cut_end_s);

struct Harmonics {
  double mean_N = 0.0;
  std::vector<double> amplitudes_N;  // A_1 .. A_K
};

// Mean and A_1..A_K of x over window w (harmonic_window). @throws std::invalid_argument when w
// is empty or outside x.
Harmonics tooth_harmonics(const Eigen::Ref<const Eigen::VectorXd>& x, const IndexWindow& w,
                          double sample_rate_hz, double tooth_freq_hz, int count);

struct ReferenceError {
  double nrmse_pct = 0.0;
  double fit_pct = 0.0;
  int lag_samples = 0;
};

// The three figures against a reference over window w (evaluation_window). @throws
// std::invalid_argument when the sizes differ or w is empty or outside them.
ReferenceError reference_error(const Eigen::Ref<const Eigen::VectorXd>& estimate,
                               const Eigen::Ref<const Eigen::VectorXd>& reference,
                               const IndexWindow& w);

// 100 rms(estimate - reference) / rms(reference) over w alone (the oracle bounds of synth).
double nrmse_pct(const Eigen::Ref<const Eigen::VectorXd>& estimate,
                 const Eigen::Ref<const Eigen::VectorXd>& reference, const IndexWindow& w);

}  // namespace forcerec
}  // namespace chatterlab
