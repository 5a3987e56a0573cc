// Options of the bifurcation criterion on once-per-revolution samples (docs/bifurcation.md).
#pragma once

namespace chatterlab {
namespace dynamics {

struct BifurcationOptions {
  // W: revolutions in the sliding window of the spread statistic s_n (local_spread.h), odd.
  // On white noise s_n has a relative std of 0.914 / sqrt(W) (0.117 at 61, measured 0.117).
  // 61 revolutions are 0.047 mm at the 000 sec. 5.2 ramp (1 mm per 1,290 revolutions) and
  // 0.24 s at 15,000 rpm; chatter whose rotation number nu lies within ~1.5 / W of an integer
  // looks like drift to the local trend (docs/bifurcation.md sec. 2).
  int window_revolutions = 61;

  // Standard deviation of the measurement noise on x_n (m). > 0: the noise floor is this value
  // (e.g. white_noise_sigma of the raw deflection, noise_level.h, or a sensor's rating).
  // 0: estimated from the quietest part of the run (noise_block_revolutions and
  // noise_quantile). Only a stated level can tell a run that chatters throughout from a noisy
  // stable one; the estimate assumes at least noise_quantile of the run is chatter-free.
  double measurement_noise_m = 0.0;
  // Estimated floor: the run is cut into blocks of this many revolutions, each gives the robust
  // std of its central residuals (relative std 1.166 / sqrt(200) = 8 %), and the floor is the
  // noise_quantile quantile of the block values (so a run that is 90 % chatter still has its
  // floor from its stable tenth), corrected for the order statistic's low bias on noise.
  int noise_block_revolutions = 200;
  double noise_quantile = 0.1;
  // The floor never goes below this (m): noise-free simulations would otherwise put the
  // thresholds at rounding level. 1 nm is 500 times below the 5e-7 m sensor noise of 000
  // sec. 6.1 and 1,000 times below the smallest chatter amplitude of interest (1e-6 m).
  double min_noise_floor_m = 1e-9;

  // Chatter is confirmed where s_n > enter_factor * floor on min_chatter_revolutions
  // consecutive revolutions. Noise alone gives s_n ~ floor with a 0.117 relative std at W = 61;
  // its largest value over 50 runs of 10,000 revolutions was 1.51 floor, 0.7 floor below 2.2
  // (a margin for a floor estimated 3 stds low, 8 %, and for noise heavier-tailed than
  // Gaussian). Quasi-periodic chatter of amplitude A on noise sigma has a median s_n at it from
  // A ~ 2.5 sigma, period-two clusters from A ~ 2 sigma; steady quasi-periodic chatter was
  // confirmed in 100 of 100 runs at A = 3 sigma (1.5e-6 m on 000's 5e-7 m), 31 at 2.5 sigma
  // and none at 2 sigma. Growing chatter is dated by the exit level below, not by this one.
  double enter_factor = 2.2;
  // A chatter episode spans the revolutions with s_n > exit_factor * floor around its
  // confirmation: onsets are dated back and ends forward to this lower level (hysteresis),
  // which removes most of the lag of waiting for the entry level on a growing amplitude. The
  // noise-only maximum, 1.51 floor, is about the lowest level that does not date onsets into noise.
  double exit_factor = 1.5;
  // Revolutions in a row above the entry level that confirm chatter. A burst of large
  // amplitude lasting L revolutions keeps s_n above it for about L + W/2 revolutions (s_n sees
  // chatter once a quarter of its window holds it), so 91 = W + W/2 counts chatter that lasts
  // about one window (0.24 s at 15,000 rpm) and drops shorter transients.
  int min_chatter_revolutions = 91;
  // Chatter ends at a quiet stretch (s_n <= exit level) of this many revolutions, or at one
  // that reaches the end of the run whatever its length; shorter ones are bridged.
  int min_stable_revolutions = 61;
  // The run ended because the motion grew without bound (a simulation that diverged, e.g. the
  // linear angle-only switching past its stability limit): a final stretch above the entry
  // level that reaches the run's end is chatter whatever its length, since what followed it
  // was unbounded. Off for measured data.
  bool ends_unbounded = false;

  // The run is constant-depth when |depth_last - depth_first| <= this (m); otherwise an
  // incline (depth rising) or a decline (falling). 1 um is 1e-3 of a millimetre-scale run.
  double constant_depth_tolerance_m = 1e-6;
};

// Throws InputError naming the first field that breaks its rule
// ("bifurcation.window_revolutions = 40: must be odd and >= 5").
void validate(const BifurcationOptions& options);

}  // namespace dynamics
}  // namespace chatterlab
