// Welch-averaged cross-spectra of several channels against one reference (001 sec. 3.1 as the
// format fixes it for kind sweep-frf): segments of `segment` samples with 50 % overlap, each
// segment's mean removed, a periodic Hann window, and
//   S_rx(f_k) = c sum_segments conj(R_k) X_k,   S_rr, S_xx likewise (real),
// at f_k = k fs / segment, k = 0..segment/2. c = 1 / (segments fs sum w^2), doubled for
// 0 < k < segment/2: a one-sided density (scipy.signal.csd's 'density' scaling, whose
// convention conj(first) * second it shares). H1 of channel x against the reference is
// S_rx / S_rr and its coherence |S_rx|^2 / (S_rr S_xx); ratios of two cross-spectra against
// the same reference (S_ry / S_rx) are the H1-type FRF of y against x that the reference
// excites (the loop FRFs of 001 eqs 3.4-3.6, free of the loop's own noise).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "analysis/common/summary.h"  // InputError

namespace chatterlab {
namespace signal {

struct CrossSpectra {
  Eigen::VectorXd f_hz;                // segment/2 + 1 bins
  Eigen::VectorXd S_rr;                // the reference's auto-spectrum
  std::vector<Eigen::VectorXcd> S_rx;  // per channel, conj(R) X
  std::vector<Eigen::VectorXd> S_xx;   // per channel
  int segments = 0;
};

// @param reference  n samples
// @param channels   each n samples
// @param segment    samples per segment, even, >= 8 and <= n
// @param fs_hz      sample rate, > 0
// @throws InputError for sizes or values outside those rules (non-finite samples included)
CrossSpectra welch_cross_spectra(const Eigen::Ref<const Eigen::VectorXd>& reference,
                                 const std::vector<Eigen::VectorXd>& channels, int segment,
                                 double fs_hz);

}  // namespace signal
}  // namespace chatterlab
