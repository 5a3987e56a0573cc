#include "analysis/frf/windows.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace frf {
namespace {

double rms(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Index from, Eigen::Index count,
           double baseline) {
  return std::sqrt((x.segment(from, count).array() - baseline).square().mean());
}

}  // namespace

Eigen::VectorXd force_window(Eigen::Index n, Eigen::Index trigger, Eigen::Index pulse_end,
                             double margin_factor) {
  if (n < 1) throw InputError("force window length " + std::to_string(n) + ": must be >= 1");
  if (trigger < 0 || pulse_end < trigger || pulse_end > n) {
    throw InputError("force window: trigger " + std::to_string(trigger) + ", pulse end " +
                     std::to_string(pulse_end) +
                     ": must satisfy 0 <= trigger <= end <= " + std::to_string(n));
  }
  if (!(margin_factor >= 0.0)) {
    throw InputError("frf.force_window_margin = " + std::to_string(margin_factor) +
                     ": must be >= 0");
  }
  const Eigen::Index margin = std::max<Eigen::Index>(
      2, std::llround(margin_factor * static_cast<double>(pulse_end - trigger)));
  const Eigen::Index on = trigger - margin;     // first sample at 1
  const Eigen::Index off = pulse_end + margin;  // first sample past the flat top
  Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = std::max<Eigen::Index>(0, on - margin);
       i < std::min<Eigen::Index>(n, off + margin); ++i) {
    if (i < on) {
      const double x = static_cast<double>(on - i) / static_cast<double>(margin + 1);
      w[i] = 0.5 * (1.0 + std::cos(kPi * x));
    } else if (i < off) {
      w[i] = 1.0;
    } else {
      const double x = static_cast<double>(i - off + 1) / static_cast<double>(margin + 1);
      w[i] = 0.5 * (1.0 + std::cos(kPi * x));
    }
  }
  return w;
}

Eigen::VectorXd exponential_window(Eigen::Index n, Eigen::Index origin, double tau_s,
                                   double fs_hz) {
  if (!(tau_s >= 0.0)) {
    throw InputError("frf.exp_window_tau_s = " + std::to_string(tau_s) + ": must be >= 0");
  }
  if (!(fs_hz > 0.0)) throw InputError("fs_hz = " + std::to_string(fs_hz) + ": must be > 0");
  if (tau_s == 0.0) return Eigen::VectorXd::Ones(n);
  Eigen::VectorXd w(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    w[i] = std::exp(-static_cast<double>(i - origin) / (tau_s * fs_hz));
  }
  return w;
}

double auto_exponential_tau_s(const Eigen::Ref<const Eigen::VectorXd>& response, const HitSet& hits,
                              double end_fraction, double segment_fraction) {
  if (!(end_fraction > 0.0 && end_fraction < 1.0)) {
    throw InputError("frf.exp_window_end_fraction = " + std::to_string(end_fraction) +
                     ": must be in (0, 1)");
  }
  if (!(segment_fraction > 0.0 && segment_fraction <= 0.25)) {
    throw InputError("frf.decay_segment_fraction = " + std::to_string(segment_fraction) +
                     ": must be in (0, 0.25]");
  }
  std::vector<double> ratios;
  double span_s = 0.0;
  for (const Hit& hit : hits.hits) {
    if (!hit.accepted) continue;
    const Eigen::Index length = hit.end - hit.start;
    const Eigen::Index seg =
        std::max<Eigen::Index>(16, std::llround(segment_fraction * static_cast<double>(length)));
    const Eigen::Index late = hit.end - seg;
    if (late < hit.trigger + seg) continue;  // too short to tell: no window from this hit
    const double early_rms = rms(response, hit.trigger, seg, hits.response_baseline);
    const double late_rms = rms(response, late, seg, hits.response_baseline);
    if (!(early_rms > 0.0)) continue;
    ratios.push_back(late_rms / early_rms);
    span_s = static_cast<double>(late - hit.trigger) / hits.fs_hz;
  }
  if (ratios.empty()) return 0.0;
  std::nth_element(ratios.begin(), ratios.begin() + static_cast<long>(ratios.size() / 2),
                   ratios.end());
  const double r = ratios[ratios.size() / 2];
  if (r <= end_fraction) return 0.0;
  return span_s / std::log(r / end_fraction);
}

PoleShift undo_exponential_window(double fn_fit_hz, double zeta_fit, double tau_s) {
  PoleShift out{fn_fit_hz, zeta_fit};
  if (tau_s == 0.0) return out;
  const double wn_fit = 2.0 * kPi * fn_fit_hz;
  const double wd = wn_fit * std::sqrt(std::max(0.0, 1.0 - zeta_fit * zeta_fit));
  const double sigma = zeta_fit * wn_fit - 1.0 / tau_s;
  const double wn = std::sqrt(wd * wd + sigma * sigma);
  out.fn_hz = wn / (2.0 * kPi);
  out.zeta = sigma / wn;
  return out;
}

}  // namespace frf
}  // namespace chatterlab
