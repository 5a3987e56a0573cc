// Least-squares fit of a constant plus harmonics of a known fundamental to a uniformly sampled
// signal (003 eq. 3-6 as corrected by notes/003.md: the 2 pi and a phase; the mean of a
// sinusoid is zero, so a plain mean cannot remove unbalance):
//
//   x(t_k) ~ c0 + sum_h Re(c_h e^{j h Omega t_k}),   t_k = k / fs (seconds from sample 0),
//   Omega = 2 pi fundamental_hz,
//
// over the samples [begin, end). Re(c e^{j theta}) = |c| cos(theta + arg c), so a term is
// `amp cos(h Omega t + phase)` with amp = |c_h|, phase = arg c_h. Over a window holding whole
// periods of every harmonic the normal equations are diagonal and c_h equals the DFT bin
// (2/N) sum x_k e^{-j h Omega t_k}; otherwise the full least-squares solve is used (QR of the
// N x (1 + 2H) design matrix, built column by column, no per-sample allocation).
#pragma once

#include <Eigen/Core>
#include <complex>
#include <vector>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace signal {

struct HarmonicFit {
  StepSummary summary;  // fails when the window holds fewer samples than 2 (1 + 2H)
  double fundamental_hz = 0.0;
  std::vector<int> harmonics;  // h, as given
  double c0 = 0.0;
  Eigen::VectorXcd c;         // c_h, one per harmonic, same order
  double residual_rms = 0.0;  // RMS of x - fit over the window
  Eigen::Index samples = 0;   // end - begin
};

// @param x          the signal
// @param fs_hz      its sample rate, > 0
// @param begin,end  the window, 0 <= begin < end <= x.size()
// @param fundamental_hz  > 0
// @param harmonics  distinct positive integers (may be empty: the mean alone)
// @throws InputError for a bad rate, window, fundamental or harmonic list
HarmonicFit fit_harmonics(const Eigen::Ref<const Eigen::VectorXd>& x, double fs_hz,
                          Eigen::Index begin, Eigen::Index end, double fundamental_hz,
                          const std::vector<int>& harmonics);

// x[k] -= c0 + sum_h Re(c_h e^{j h Omega k / fs}) for every k of x (the whole record: the fit is
// extrapolated phase-coherently, which assumes a constant speed).
void subtract_harmonics(const HarmonicFit& fit, double fs_hz, Eigen::Ref<Eigen::VectorXd> x);

}  // namespace signal
}  // namespace chatterlab
