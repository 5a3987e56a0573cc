// Tap-test windows: force window on the hammer, exponential window on the response, and
// the damping correction the exponential window calls for.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "analysis/frf/hits.h"

namespace chatterlab {
namespace frf {

// Force window over one record of n samples: 1 on [trigger - margin, pulse_end + margin),
// a half-cosine taper of `margin` samples on each side, 0 elsewhere (positions relative to
// the record start, clipped to it). margin = max(2, round(margin_factor * (pulse_end -
// trigger))) samples. Keeps the whole pulse, including its foot below the threshold, and
// zeroes the noise that would otherwise fill the rest of the force record.
// @throws InputError if n < 1, trigger or pulse_end outside [0, n], or margin_factor < 0
Eigen::VectorXd force_window(Eigen::Index n, Eigen::Index trigger, Eigen::Index pulse_end,
                             double margin_factor);

// w[i] = exp(-(i - origin) / (tau_s fs_hz)), i = 0 .. n-1; all ones when tau_s == 0.
// Applied to both channels it multiplies the FRF's argument: H_w(s) = H(s + 1/tau), so each
// pole moves by -1/tau and the residues are unchanged (see undo_exponential_window).
// @throws InputError if tau_s < 0 or fs_hz <= 0
Eigen::VectorXd exponential_window(Eigen::Index n, Eigen::Index origin, double tau_s, double fs_hz);

// Automatic exponential window: the smallest damping that makes the response decay to
// end_fraction of its early amplitude by the end of the record, or none if it already has.
//   r = median over accepted hits of RMS(last segment) / RMS(first segment after the
//       trigger), both segments segment_fraction of the record long (>= 16 samples);
//   T = time between the segments' centres;
//   tau = T / ln(r / end_fraction) if r > end_fraction, else no window (returns 0).
// Noise in the tail counts as undecayed response, so a noisy tail also gets a window (whose
// damping is then removed exactly by undo_exponential_window).
// @return tau in s, 0 for no window
double auto_exponential_tau_s(const Eigen::Ref<const Eigen::VectorXd>& response, const HitSet& hits,
                              double end_fraction, double segment_fraction);

struct PoleShift {
  double fn_hz = 0.0;
  double zeta = 0.0;  // may come out <= 0 when the window's damping swamps the mode's
};

// Undoes the exponential window on one fitted mode. The fit sees poles
// s' = -zeta' wn' +- j wd with zeta' wn' = zeta wn + 1/tau and the same wd, so
//   sigma = zeta' wn' - 1/tau,  wn = sqrt(wd^2 + sigma^2),  zeta = sigma / wn,
// which to first order is the usual zeta = zeta' - 1/(tau wn). The modal constant 1/m is
// unchanged by the shift. tau_s == 0 (no window) returns the input.
PoleShift undo_exponential_window(double fn_fit_hz, double zeta_fit, double tau_s);

}  // namespace frf
}  // namespace chatterlab
