#include "analysis/frf/frf.h"

#include <cmath>
#include <complex>
#include <cstdio>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/frf/windows.h"
#include "analysis/signal/fft.h"

namespace chatterlab {
namespace frf {
namespace {

// Factor that turns the response's FRF into receptance at angular frequency w. With the
// exponential window on both channels the measured FRF is the response's transfer function
// at s = 1/tau + j w (windows.h), so the derivatives are undone there: acceleration / s^2,
// velocity / s (with no window s = j w: / (-w^2) and / (j w)).
std::complex<double> to_receptance(ResponseKind kind, double w, double tau_s) {
  const std::complex<double> s(tau_s > 0.0 ? 1.0 / tau_s : 0.0, w);
  switch (kind) {
    case ResponseKind::kAcceleration:
      return 1.0 / (s * s);
    case ResponseKind::kVelocity:
      return 1.0 / s;
    case ResponseKind::kDisplacement:
      break;
  }
  return {1.0, 0.0};
}

}  // namespace

Frf compute_frf(const Eigen::Ref<const Eigen::VectorXd>& force,
                const Eigen::Ref<const Eigen::VectorXd>& response, const HitSet& hits,
                ResponseKind kind, const FrfOptions& options) {
  Frf frf;
  if (force.size() != response.size()) {
    throw InputError("frf: force has " + std::to_string(force.size()) + " samples, response " +
                     std::to_string(response.size()) + ": must be equal");
  }
  if (!options.exp_window_auto && !(options.exp_window_tau_s >= 0.0)) {
    throw InputError("frf.exp_window_tau_s = " + std::to_string(options.exp_window_tau_s) +
                     ": must be >= 0 (0 = no window)");
  }
  if (hits.accepted_count() == 0) {
    frf.summary.fail("no FRF: no accepted hit (" + hits.summary.message + ")");
    return frf;
  }
  const Eigen::Index length = hits.record_samples;
  if (length < 4) {
    frf.summary.fail("no FRF: the record is " + std::to_string(length) +
                     " samples long: needs at least 4");
    return frf;
  }
  for (const Hit& hit : hits.hits) {
    if (hit.accepted &&
        (hit.start < 0 || hit.end > force.size() || hit.end - hit.start != length)) {
      throw InputError("frf: hit record [" + std::to_string(hit.start) + ", " +
                       std::to_string(hit.end) + ") does not fit " + std::to_string(force.size()) +
                       " samples with length " + std::to_string(length));
    }
  }

  frf.exp_window_tau_s =
      options.exp_window_auto
          ? auto_exponential_tau_s(response, hits, options.exp_window_end_fraction,
                                   options.decay_segment_fraction)
          : options.exp_window_tau_s;
  const double fs = hits.fs_hz;
  signal::RealFft fft(length);
  const Eigen::Index bins = length / 2;  // k = 1 .. L/2
  Eigen::VectorXd s_ff = Eigen::VectorXd::Zero(bins);
  Eigen::VectorXd s_xx = Eigen::VectorXd::Zero(bins);
  Eigen::VectorXcd s_fx = Eigen::VectorXcd::Zero(bins);
  Eigen::VectorXd f_rec(length);
  Eigen::VectorXd x_rec(length);
  Eigen::VectorXcd f_spec(fft.bins());
  Eigen::VectorXcd x_spec(fft.bins());
  for (const Hit& hit : hits.hits) {
    if (!hit.accepted) continue;
    const Eigen::Index trigger = hit.trigger - hit.start;
    const Eigen::VectorXd expw = exponential_window(length, trigger, frf.exp_window_tau_s, fs);
    const Eigen::VectorXd fw =
        force_window(length, trigger, hit.pulse_end - hit.start, options.force_window_margin);
    f_rec = (force.segment(hit.start, length).array() - hits.force_baseline_n) * fw.array() *
            expw.array();
    x_rec = (response.segment(hit.start, length).array() - hits.response_baseline) * expw.array();
    fft.forward(f_rec, &f_spec);
    fft.forward(x_rec, &x_spec);
    for (Eigen::Index k = 0; k < bins; ++k) {
      const std::complex<double> f = f_spec[k + 1];
      const std::complex<double> x = x_spec[k + 1];
      s_ff[k] += std::norm(f);
      s_xx[k] += std::norm(x);
      s_fx[k] += std::conj(f) * x;
    }
    ++frf.hits_used;
  }

  frf.df_hz = fs / static_cast<double>(length);
  frf.f_hz.resize(bins);
  frf.h1.resize(bins);
  frf.h2.resize(bins);
  frf.coherence.resize(bins);
  for (Eigen::Index k = 0; k < bins; ++k) {
    const double f_hz = static_cast<double>(k + 1) * frf.df_hz;
    const std::complex<double> conv = to_receptance(kind, kTwoPi * f_hz, frf.exp_window_tau_s);
    frf.f_hz[k] = f_hz;
    frf.h1[k] = s_fx[k] / s_ff[k] * conv;
    frf.h2[k] = s_xx[k] / std::conj(s_fx[k]) * conv;
    const double denom = s_ff[k] * s_xx[k];
    frf.coherence[k] = denom > 0.0 ? std::norm(s_fx[k]) / denom : 0.0;
  }
  if (frf.hits_used == 1) {
    frf.summary.warnings.push_back("one hit only: coherence is 1 by construction and says nothing");
  }
  if (frf.exp_window_tau_s > 0.0) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "exponential window tau = %.4g s applied (adds %.4g 1/s to every pole's decay "
                  "rate; removed from the fitted damping)",
                  frf.exp_window_tau_s, 1.0 / frf.exp_window_tau_s);
    frf.summary.warnings.push_back(buf);
  }
  frf.summary.succeed();
  return frf;
}

}  // namespace frf
}  // namespace chatterlab
