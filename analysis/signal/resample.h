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
  double cutoff_fraction = 0.9;    // of the lower Nyquist frequency (pass band edge ~ this)
  double kaiser_beta = 8.0;        // stop-band attenuation ~ 80 dB
  int half_length_per_phase = 12;  // taps each side = this * max(up, down)
  int max_factor = 10000;          // largest up or down accepted (rates that reduce badly)
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
