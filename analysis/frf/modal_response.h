// Synthetic tap-test records: hammer pulses and the exact response of a sum of modes.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "analysis/common/summary.h"  // InputError
#include "analysis/frf/mode.h"
#include "analysis/frf/response_kind.h"

namespace chatterlab {
namespace frf {

// One hammer hit: f(t) = peak_n sin(pi (t - time_s) / width_s) for time_s <= t <= time_s +
// width_s, zero elsewhere.
struct HammerPulse {
  double time_s = 0.0;    // start of the pulse
  double peak_n = 0.0;    // peak force, > 0
  double width_s = 2e-4;  // pulse duration; 0.2 ms is a typical steel-tip hit on a tool
};

// Samples t = i / fs_hz, i = 0 .. n-1, of the sum of the pulses.
// @throws InputError if fs_hz <= 0, n < 0, or a pulse has peak_n or width_s <= 0
Eigen::VectorXd half_sine_pulses(const std::vector<HammerPulse>& pulses, double fs_hz,
                                 Eigen::Index n);

// Response of sum_i modes[i] (each m x'' + c x' + k x = F, 000 eq. 2.5, from rest) to the
// force that is linear between the given samples (first-order hold). Each mode is
// discretised exactly for that input: with z = [x, x', u, u'], z' = M z and
// exp(M h) (h = 1/fs) maps one sample to the next, so the result is exact to rounding for
// a piecewise-linear force. Acceleration is (F - c x' - k x) / m at each sample.
// Seen as a sampled system, the hold multiplies the FRF by sinc^2(f/fs) (a magnitude bias
// of about (pi f/fs)^2 / 3: 0.4 % at f = fs/29): use synthesize_tap_record for records
// whose FRF must match the modes.
// @param force_n  force samples (N); the force before sample 0 is zero
// @return         displacement (m), velocity (m/s) or acceleration (m/s^2), same length
// @throws InputError if fs_hz <= 0 or modes is empty
Eigen::VectorXd modal_response(const std::vector<Mode>& modes,
                               const Eigen::Ref<const Eigen::VectorXd>& force_n, double fs_hz,
                               ResponseKind kind);

struct TapSynthesisOptions {
  // The record is simulated at oversample * fs (first-order hold, exact) and both channels
  // pass through the same linear-phase anti-alias FIR before decimation, as a DAQ with
  // matched channels does; the FRF of the record then equals the modes' receptance up to
  // the fine-rate hold bias (pi f / (oversample fs))^2 / 3 (6e-5 at f = fs/29 with 8).
  int oversample = 8;
  // Anti-alias FIR: Blackman-windowed sinc with 2 * half_taps_per_factor * oversample + 1
  // taps, cutoff antialias_cutoff * fs. 16 taps per factor put the stopband (< -74 dB)
  // above about 0.56 fs, so nothing aliases below 0.44 fs.
  int half_taps_per_factor = 16;
  double antialias_cutoff = 0.45;
  // Gaussian noise added after decimation (white, like ADC noise). Force: std =
  // force_noise_fraction * the largest pulse peak. Response: std =
  // response_noise_fraction * RMS of the noiseless response over the whole record.
  double force_noise_fraction = 0.0;
  double response_noise_fraction = 0.0;
  std::uint64_t seed = 1;  // local std::mt19937_64 seed
};

struct TapRecord {
  Eigen::VectorXd force_n;   // N
  Eigen::VectorXd response;  // unit of the ResponseKind
};

// n samples at fs_hz of the hammer pulses and the modes' response to them.
// @throws InputError on fs_hz <= 0, n < 1, empty modes or invalid options
TapRecord synthesize_tap_record(const std::vector<Mode>& modes,
                                const std::vector<HammerPulse>& pulses, double fs_hz,
                                Eigen::Index n, ResponseKind kind,
                                const TapSynthesisOptions& options = {});

}  // namespace frf
}  // namespace chatterlab
