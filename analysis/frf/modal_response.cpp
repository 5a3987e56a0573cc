#include "analysis/frf/modal_response.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace frf {
namespace {

void check_rate(double fs_hz) {
  if (!(std::isfinite(fs_hz) && fs_hz > 0.0)) {
    throw InputError("fs_hz = " + std::to_string(fs_hz) + ": must be > 0");
  }
}

// Exact first-order-hold step of one mode: x1 = Phi x0 + g0 u0 + g1 (u1 - u0) / h.
struct FohStep {
  Eigen::Matrix2d phi;
  Eigen::Vector2d g0;
  Eigen::Vector2d g1;
};

FohStep foh_step(const Mode& mode, double h) {
  // z = [x, x', u, u'], z' = M z with u' constant over the step. M's entries span k/m to 1,
  // so the exponential is taken of the similar matrix D M D^-1 with D = diag(1, 1/wn, 1/k,
  // 1/(k wn)), which is wn [[0,1,0,0],[-1,-2 zeta,1,0],[0,0,0,1],[0,0,0,0]]: all entries
  // O(wn h) and the result accurate to rounding in every block.
  const double wn = std::sqrt(mode.k_N_m / mode.m_kg);
  const double zeta = mode.c_kg_s / (2.0 * std::sqrt(mode.k_N_m * mode.m_kg));
  Eigen::Matrix4d scaled = Eigen::Matrix4d::Zero();
  scaled(0, 1) = 1.0;
  scaled(1, 0) = -1.0;
  scaled(1, 1) = -2.0 * zeta;
  scaled(1, 2) = 1.0;
  scaled(2, 3) = 1.0;
  const Eigen::Matrix4d e_scaled = (scaled * (wn * h)).exp();
  const Eigen::Vector4d d(1.0, 1.0 / wn, 1.0 / mode.k_N_m, 1.0 / (mode.k_N_m * wn));
  // exp(M h) = D^-1 exp(D M D^-1 h) D.
  const Eigen::Matrix4d e = d.cwiseInverse().asDiagonal() * e_scaled * d.asDiagonal();
  FohStep step;
  step.phi = e.topLeftCorner<2, 2>();
  step.g0 = e.block<2, 1>(0, 2);
  step.g1 = e.block<2, 1>(0, 3);
  return step;
}

// Blackman-windowed sinc low-pass, unit DC gain; cutoff as a fraction of the sampling rate.
Eigen::VectorXd blackman_sinc(int half, double cutoff_fraction) {
  const int n = 2 * half + 1;
  Eigen::VectorXd taps(n);
  for (int i = 0; i < n; ++i) {
    const double k = static_cast<double>(i - half);
    const double x = 2.0 * cutoff_fraction * k;
    const double sinc = (k == 0.0) ? 1.0 : std::sin(kPi * x) / (kPi * x);
    const double phase = 2.0 * kPi * static_cast<double>(i) / static_cast<double>(n - 1);
    const double window = 0.42 - 0.5 * std::cos(phase) + 0.08 * std::cos(2.0 * phase);
    taps[i] = sinc * window;
  }
  return taps / taps.sum();
}

}  // namespace

Eigen::VectorXd half_sine_pulses(const std::vector<HammerPulse>& pulses, double fs_hz,
                                 Eigen::Index n) {
  check_rate(fs_hz);
  if (n < 0) throw InputError("pulse samples n = " + std::to_string(n) + ": must be >= 0");
  Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
  for (size_t p = 0; p < pulses.size(); ++p) {
    const HammerPulse& pulse = pulses[p];
    const std::string name = "pulses[" + std::to_string(p) + "]";
    if (!(pulse.peak_n > 0.0)) {
      throw InputError(name + ".peak_n = " + std::to_string(pulse.peak_n) + ": must be > 0");
    }
    if (!(pulse.width_s > 0.0)) {
      throw InputError(name + ".width_s = " + std::to_string(pulse.width_s) + ": must be > 0");
    }
    const auto first = static_cast<Eigen::Index>(std::max(0.0, std::ceil(pulse.time_s * fs_hz)));
    const auto last = std::min<Eigen::Index>(
        n - 1, static_cast<Eigen::Index>(std::floor((pulse.time_s + pulse.width_s) * fs_hz)));
    for (Eigen::Index i = first; i <= last; ++i) {
      const double phase = kPi * (static_cast<double>(i) / fs_hz - pulse.time_s) / pulse.width_s;
      f[i] += pulse.peak_n * std::sin(phase);
    }
  }
  return f;
}

Eigen::VectorXd modal_response(const std::vector<Mode>& modes,
                               const Eigen::Ref<const Eigen::VectorXd>& force_n, double fs_hz,
                               ResponseKind kind) {
  check_rate(fs_hz);
  if (modes.empty()) throw InputError("modal_response: modes is empty: needs at least one mode");
  const double h = 1.0 / fs_hz;
  const Eigen::Index n = force_n.size();
  Eigen::VectorXd out = Eigen::VectorXd::Zero(n);
  for (const Mode& mode : modes) {
    if (!(mode.m_kg > 0.0 && mode.k_N_m > 0.0 && mode.c_kg_s >= 0.0)) {
      throw InputError("modal_response: mode with m = " + std::to_string(mode.m_kg) +
                       ", c = " + std::to_string(mode.c_kg_s) +
                       ", k = " + std::to_string(mode.k_N_m) + ": needs m > 0, c >= 0, k > 0");
    }
    const FohStep step = foh_step(mode, h);
    Eigen::Vector2d x = Eigen::Vector2d::Zero();
    double u_prev = 0.0;  // at rest with zero force before sample 0
    for (Eigen::Index i = 0; i < n; ++i) {
      const double u = force_n[i];
      // The first interval ramps from 0 (at t = -h) to force_n[0].
      x = step.phi * x + step.g0 * u_prev + step.g1 * ((u - u_prev) / h);
      u_prev = u;
      switch (kind) {
        case ResponseKind::kDisplacement:
          out[i] += x[0];
          break;
        case ResponseKind::kVelocity:
          out[i] += x[1];
          break;
        case ResponseKind::kAcceleration:
          out[i] += (u - mode.c_kg_s * x[1] - mode.k_N_m * x[0]) / mode.m_kg;
          break;
      }
    }
  }
  return out;
}

TapRecord synthesize_tap_record(const std::vector<Mode>& modes,
                                const std::vector<HammerPulse>& pulses, double fs_hz,
                                Eigen::Index n, ResponseKind kind,
                                const TapSynthesisOptions& options) {
  check_rate(fs_hz);
  if (n < 1) throw InputError("tap record n = " + std::to_string(n) + ": must be >= 1");
  if (options.oversample < 1) {
    throw InputError("tap_synthesis.oversample = " + std::to_string(options.oversample) +
                     ": must be >= 1");
  }
  if (options.half_taps_per_factor < 1) {
    throw InputError("tap_synthesis.half_taps_per_factor = " +
                     std::to_string(options.half_taps_per_factor) + ": must be >= 1");
  }
  if (!(options.antialias_cutoff > 0.0 && options.antialias_cutoff <= 0.5)) {
    throw InputError("tap_synthesis.antialias_cutoff = " +
                     std::to_string(options.antialias_cutoff) + ": must be in (0, 0.5]");
  }
  if (!(options.force_noise_fraction >= 0.0) || !(options.response_noise_fraction >= 0.0)) {
    throw InputError("tap_synthesis noise fractions must be >= 0");
  }
  const int r = options.oversample;
  const int half = options.half_taps_per_factor * r;
  const double fine_fs = fs_hz * r;
  // Fine samples 0 .. n*r + half: the FIR centred on the last output needs `half` beyond it.
  const Eigen::Index n_fine = (n - 1) * r + half + 1;
  const Eigen::VectorXd force_fine = half_sine_pulses(pulses, fine_fs, n_fine);
  const Eigen::VectorXd resp_fine = modal_response(modes, force_fine, fine_fs, kind);
  const Eigen::VectorXd taps = blackman_sinc(half, options.antialias_cutoff / r);

  TapRecord record;
  record.force_n.resize(n);
  record.response.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    // Linear-phase FIR centred on fine sample i*r: no net delay. Before t = 0 both are zero.
    const Eigen::Index centre = i * r;
    double f = 0.0;
    double x = 0.0;
    for (int j = -half; j <= half; ++j) {
      const Eigen::Index k = centre - j;
      if (k < 0) continue;
      f += taps[j + half] * force_fine[k];
      x += taps[j + half] * resp_fine[k];
    }
    record.force_n[i] = f;
    record.response[i] = x;
  }

  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  double peak = 0.0;
  for (const HammerPulse& p : pulses) peak = std::max(peak, p.peak_n);
  const double force_std = options.force_noise_fraction * peak;
  const double resp_std = options.response_noise_fraction *
                          std::sqrt(record.response.squaredNorm() / static_cast<double>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    record.force_n[i] += force_std * normal(rng);
    record.response[i] += resp_std * normal(rng);
  }
  return record;
}

}  // namespace frf
}  // namespace chatterlab
