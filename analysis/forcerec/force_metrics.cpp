// See force_metrics.h (EXPERIMENT_FORMAT.md section 4, kind force-record, "Figures").
#include "analysis/forcerec/force_metrics.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace forcerec {

namespace {
constexpr double kSkipStartS = 0.05;  // the AKF's start-up from x0 = 0
constexpr double kSkipEndS = 0.01;    // the repeated last sample and a margin
constexpr int kMaxHarmonics = 12;
constexpr double kHarmonicBand = 0.4;  // of fs
constexpr int kMaxLag = 10;

void check_window(const IndexWindow& w, Eigen::Index size, const char* what) {
  if (w.size() == 0 || w.begin < 0 || w.end > size) {
    throw std::invalid_argument(std::string(what) + ": the window is empty or outside the record");
  }
}
}  // namespace

IndexWindow evaluation_window(Eigen::Index samples, double sample_rate_hz) {
  IndexWindow w;
  // k / fs >= 0.05  <=>  k >= ceil(0.05 fs);  k / fs < T - 0.01  <=>  k < N - 0.01 fs.
  w.begin = static_cast<Eigen::Index>(std::ceil(kSkipStartS * sample_rate_hz - 1e-9));
  const double last = static_cast<double>(samples) - kSkipEndS * sample_rate_hz;
  w.end = std::max<Eigen::Index>(0, static_cast<Eigen::Index>(std::ceil(last - 1e-9)));
  w.end = std::min(w.end, samples);
  if (w.end < w.begin) w.end = w.begin;
  return w;
}

int harmonic_count(double sample_rate_hz, double tooth_freq_hz) {
  if (!(tooth_freq_hz > 0) || !(sample_rate_hz > 0)) return 0;
  const double k = std::floor(kHarmonicBand * sample_rate_hz / tooth_freq_hz);
  return static_cast<int>(std::min<double>(kMaxHarmonics, std::max(0.0, k)));
}

IndexWindow harmonic_window(Eigen::Index samples, double sample_rate_hz, double tooth_freq_hz,
                            double cut_begin_s, double cut_end_s) {
  IndexWindow w;
  if (!(tooth_freq_hz > 0) || !(sample_rate_hz > 0)) return w;
  const double T = static_cast<double>(samples) / sample_rate_hz;
  const double k0 = std::ceil(std::max(cut_begin_s, kSkipStartS) * sample_rate_hz - 1e-9);
  const double k1 = std::floor(std::min(cut_end_s, T - kSkipEndS) * sample_rate_hz + 1e-9);
  if (!(k1 > k0)) return w;
  const double periods = std::floor((k1 - k0) * tooth_freq_hz / sample_rate_hz);
  if (periods < 1) return w;
  const double n = std::round(periods * sample_rate_hz / tooth_freq_hz);
  w.begin = static_cast<Eigen::Index>(k0);
  w.end = std::min<Eigen::Index>(samples, w.begin + static_cast<Eigen::Index>(n));
  return w;
}

Harmonics tooth_harmonics(const Eigen::Ref<const Eigen::VectorXd>& x, const IndexWindow& w,
                          double sample_rate_hz, double tooth_freq_hz, int count) {
  check_window(w, x.size(), "tooth_harmonics");
  Harmonics h;
  const auto seg = x.segment(w.begin, w.size());
  const double n = static_cast<double>(w.size());
  h.mean_N = seg.mean();
  h.amplitudes_N.reserve(static_cast<std::size_t>(std::max(0, count)));
  for (int k = 1; k <= count; ++k) {
    // A rotating phasor: one complex multiply per sample, renormalised every 4096 samples.
    const double dphi = -kTwoPi * k * tooth_freq_hz / sample_rate_hz;
    const std::complex<double> step(std::cos(dphi), std::sin(dphi));
    std::complex<double> ph(1.0, 0.0), acc(0.0, 0.0);
    for (Eigen::Index j = 0; j < seg.size(); ++j) {
      acc += seg(j) * ph;
      ph *= step;
      if ((j & 4095) == 4095) {
        const double a = dphi * static_cast<double>(j + 1);
        ph = std::complex<double>(std::cos(a), std::sin(a));
      }
    }
    h.amplitudes_N.push_back(2.0 / n * std::abs(acc));
  }
  return h;
}

double nrmse_pct(const Eigen::Ref<const Eigen::VectorXd>& estimate,
                 const Eigen::Ref<const Eigen::VectorXd>& reference, const IndexWindow& w) {
  if (estimate.size() != reference.size()) {
    throw std::invalid_argument("nrmse_pct: estimate and reference differ in length");
  }
  check_window(w, reference.size(), "nrmse_pct");
  const auto e = estimate.segment(w.begin, w.size()) - reference.segment(w.begin, w.size());
  return 100.0 * e.norm() / reference.segment(w.begin, w.size()).norm();
}

ReferenceError reference_error(const Eigen::Ref<const Eigen::VectorXd>& estimate,
                               const Eigen::Ref<const Eigen::VectorXd>& reference,
                               const IndexWindow& w) {
  ReferenceError r;
  r.nrmse_pct = nrmse_pct(estimate, reference, w);
  const auto F = reference.segment(w.begin, w.size());
  const auto Fh = estimate.segment(w.begin, w.size());
  const double Fm = F.mean();
  r.fit_pct = 100.0 * (1.0 - (Fh - F).norm() / (F.array() - Fm).matrix().norm());
  // Lag: the shift l of the estimate that best correlates with the reference. The sum runs over
  // the k of the window with k + l inside the record.
  const double Em = Fh.mean();
  double best = -std::numeric_limits<double>::infinity();
  for (int l = -kMaxLag; l <= kMaxLag; ++l) {
    const Eigen::Index lo = std::max<Eigen::Index>(w.begin, -l);
    const Eigen::Index hi = std::min<Eigen::Index>(w.end, estimate.size() - l);
    if (hi <= lo) continue;
    const double s = ((estimate.segment(lo + l, hi - lo).array() - Em) *
                      (reference.segment(lo, hi - lo).array() - Fm))
                         .sum();
    if (s > best) {
      best = s;
      r.lag_samples = l;
    }
  }
  return r;
}

}  // namespace forcerec
}  // namespace chatterlab
