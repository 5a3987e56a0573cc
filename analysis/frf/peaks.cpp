#include "analysis/frf/peaks.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace frf {
namespace {

// Frequency where |H| falls to `level` walking from `peak` by `step` (+1 or -1); < 0 when
// a valley (|H| rising again) or the end comes first.
double crossing_hz(const Eigen::VectorXd& mag, const Eigen::Ref<const Eigen::VectorXd>& f_hz,
                   Eigen::Index peak, int step, double level) {
  Eigen::Index i = peak;
  while (true) {
    const Eigen::Index j = i + step;
    if (j < 0 || j >= mag.size() || mag[j] > mag[i]) return -1.0;
    if (mag[j] <= level) {
      const double t = (mag[i] - level) / (mag[i] - mag[j]);
      return f_hz[i] + t * (f_hz[j] - f_hz[i]);
    }
    i = j;
  }
}

}  // namespace

std::vector<FrfPeak> find_frf_peaks(const Eigen::Ref<const Eigen::VectorXd>& f_hz,
                                    const Eigen::Ref<const Eigen::VectorXcd>& h,
                                    const Eigen::Ref<const Eigen::VectorXd>& coherence,
                                    const PeakOptions& options) {
  const Eigen::Index n = h.size();
  if (f_hz.size() != n || coherence.size() != n) {
    throw InputError("find_frf_peaks: f_hz, h and coherence have " + std::to_string(f_hz.size()) +
                     ", " + std::to_string(n) + " and " + std::to_string(coherence.size()) +
                     " values: must be equal");
  }
  std::vector<FrfPeak> peaks;
  if (n < 3) return peaks;
  const Eigen::VectorXd mag = h.cwiseAbs();
  const double f_max = options.f_max_hz > 0.0 ? options.f_max_hz : f_hz[n - 1];
  for (Eigen::Index i = 1; i + 1 < n; ++i) {
    if (!(mag[i] > mag[i - 1] && mag[i] >= mag[i + 1])) continue;
    if (f_hz[i] < options.f_min_hz || f_hz[i] > f_max) continue;
    const Eigen::Index c_from = std::max<Eigen::Index>(0, i - options.coherence_halfwidth_bins);
    const Eigen::Index c_to = std::min<Eigen::Index>(n - 1, i + options.coherence_halfwidth_bins);
    if (coherence.segment(c_from, c_to - c_from + 1).minCoeff() < options.min_coherence) continue;
    double left_base = mag[i];
    for (Eigen::Index j = i - 1; j >= 0 && mag[j] <= mag[i]; --j)
      left_base = std::min(left_base, mag[j]);
    double right_base = mag[i];
    for (Eigen::Index j = i + 1; j < n && mag[j] <= mag[i]; ++j)
      right_base = std::min(right_base, mag[j]);
    const double base = std::max(left_base, right_base);
    const double prominence_db = base > 0.0 ? 20.0 * std::log10(mag[i] / base) : 300.0;
    if (prominence_db < options.min_prominence_db) continue;

    FrfPeak p;
    p.bin = i;
    p.value = h[i];
    p.prominence_db = prominence_db;
    // Parabola through the three bins around the maximum.
    const double ym = mag[i - 1];
    const double y0 = mag[i];
    const double yp = mag[i + 1];
    const double curvature = ym - 2.0 * y0 + yp;
    const double delta = curvature < 0.0 ? 0.5 * (ym - yp) / curvature : 0.0;
    p.f_hz = f_hz[i] + delta * (f_hz[i + 1] - f_hz[i]);
    p.magnitude = y0 - 0.25 * (ym - yp) * delta;
    const double level = p.magnitude / std::sqrt(2.0);
    const double lo = crossing_hz(mag, f_hz, i, -1, level);
    const double hi = crossing_hz(mag, f_hz, i, +1, level);
    if (lo > 0.0 && hi > 0.0) {
      p.half_power_bw_hz = std::max(0.0, hi - lo);
    } else if (lo > 0.0) {
      p.half_power_bw_hz = std::max(0.0, 2.0 * (p.f_hz - lo));
    } else if (hi > 0.0) {
      p.half_power_bw_hz = std::max(0.0, 2.0 * (hi - p.f_hz));
    }
    peaks.push_back(p);
  }
  return peaks;
}

}  // namespace frf
}  // namespace chatterlab
