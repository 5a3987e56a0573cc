// Measurement-noise level of a densely sampled, smooth signal (a tool deflection), to give the
// bifurcation criterion a stated noise floor (BifurcationOptions::measurement_noise_m).
#pragma once

#include <Eigen/Core>

namespace chatterlab {
namespace dynamics {

// Robust standard deviation of white noise added to a smooth signal, from second differences:
//   d(i) = x(i+1) - 2 x(i) + x(i-1),   var(d) = 6 sigma^2 for white noise,
//   sigma = 1.4826 median|d| / sqrt(6)      (1.4826 = 1 / Phi^-1(3/4): median|N(0,1)| -> 1).
// The signal itself enters d scaled by (2 pi f / fs)^2: a 900 Hz deflection of 1e-4 m at
// fs = 100 kHz contributes 3.2e-7 m to d against sqrt(6) 5e-7 = 1.2e-6 m of noise, and the
// median ignores the few large d at tooth impacts. At low oversampling the estimate is high.
//
// Once-per-revolution samples interpolated between two samples (revolution_sampling.h) carry
// noise of std sigma sqrt((1 - f)^2 + f^2), between 0.71 sigma and sigma: sigma is a
// conservative (slightly high) floor for x_n.
//
// @param signal  at least 3 finite samples
// @throws InputError if fewer than 3 samples or a sample is not finite
double white_noise_sigma(const Eigen::Ref<const Eigen::VectorXd>& signal);

}  // namespace dynamics
}  // namespace chatterlab
