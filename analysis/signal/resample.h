// Rational polyphase resampling with an anti-aliasing low-pass (like scipy.signal.resample_poly):
// up-sample by `up`, filter, down-sample by `down`, with up/down the reduced ratio of the two
// rates (12800 Hz -> 10000 Hz: up 25, down 32). The filter is a Kaiser-windowed sinc designed
// at the up-sampled rate with its cut-off at the lower of the two Nyquist frequencies times
// `cutoff_fraction`, gain `up`, and half-length `half_length_per_phase * max(up, down)` taps.
// Only the needed output samples are computed (polyphase), each in O(taps / up).
//
// Alignment: output sample m is the filtered input at time m / to_hz (the filter's delay is
// removed), so t = 0 stays t = 0 and a window [t0, t1] in seconds maps to the same window at
// the new rate. The record is extended by zeros at both ends (the first and last few
// half-lengths carry the edge transient). Output length = ceil(n up / down).
#pragma once

#include <Eigen/Core>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace signal {

struct ResampleOptions {
  // The -6 dB point, as a fraction of the lower Nyquist frequency. With the half-length below the
  // transition band is about +-0.05 of the Nyquist frequency around it: flat (ripple ~1e-4) up
  // to 0.9 of Nyquist, where the sifs harmonics end (format section 6: h SF <= 0.45 x the
  // filter rate), and >= 80 dB down from Nyquist on, so nothing folds back into the band.
  double cutoff_fraction = 0.95;
  double kaiser_beta = 7.86;  // stop-band attenuation ~ 80 dB (0.1102 (80 - 8.7))
  // Taps each side = this * max(up, down): a Kaiser filter of attenuation A dB over a transition
  // of width df (cycles per sample) needs (A - 8) / (14.36 df) taps; df = 0.1 Nyquist =
  // 0.05 / max(up, down) gives 100 max(up, down).
  int half_length_per_phase = 50;
  int max_factor = 10000;  // largest up or down accepted (rates that reduce badly)
};

class RationalResampler {
 public:
  // @param from_hz, to_hz  > 0 rates whose ratio reduces to up/down <= max_factor (both are
  //                        rounded to 1e-6 Hz before the ratio is reduced)
  // @throws InputError otherwise (the message gives the ratio found)
  RationalResampler(double from_hz, double to_hz, const ResampleOptions& options = {});

  int up() const { return up_; }
  int down() const { return down_; }
  bool identity() const { return up_ == down_; }
  double from_hz() const { return from_hz_; }
  double to_hz() const { return to_hz_; }
  Eigen::Index output_size(Eigen::Index n) const;

  // @return the resampled signal (a copy when identity())
  Eigen::VectorXd apply(const Eigen::Ref<const Eigen::VectorXd>& x) const;

 private:
  double from_hz_, to_hz_;
  int up_ = 1, down_ = 1;
  Eigen::VectorXd taps_;   // prototype filter at the up-sampled rate, gain up
  Eigen::Index half_ = 0;  // taps_.size() = 2 half_ + 1
};

}  // namespace signal
}  // namespace chatterlab
