#include "analysis/frf/fit_band.h"

#include <algorithm>
#include <cmath>

namespace chatterlab {
namespace frf {
namespace {

Eigen::Index bin_at(const Eigen::Ref<const Eigen::VectorXd>& f_hz, double f) {
  const auto it = std::lower_bound(f_hz.data(), f_hz.data() + f_hz.size(), f);
  return std::min<Eigen::Index>(f_hz.size() - 1, it - f_hz.data());
}

// Deepest |H| among bins in [from, to] with good coherence; `fallback` if there is none.
Eigen::Index valley(const Eigen::Ref<const Eigen::VectorXd>& magnitude,
                    const Eigen::Ref<const Eigen::VectorXd>& coherence, Eigen::Index from,
                    Eigen::Index to, double min_coherence, Eigen::Index fallback) {
  Eigen::Index best = -1;
  for (Eigen::Index i = std::max<Eigen::Index>(0, from); i <= to && i < magnitude.size(); ++i) {
    if (coherence[i] < min_coherence) continue;
    if (best < 0 || magnitude[i] < magnitude[best]) best = i;
  }
  return best < 0 ? fallback : best;
}

}  // namespace

std::array<double, 2> auto_fit_band(const Eigen::Ref<const Eigen::VectorXd>& f_hz,
                                    const Eigen::Ref<const Eigen::VectorXd>& magnitude,
                                    const Eigen::Ref<const Eigen::VectorXd>& coherence,
                                    const std::vector<FrfPeak>& peaks, double dominance_db,
                                    double min_frequency_hz, double min_coherence) {
  double largest = 0.0;
  for (const FrfPeak& p : peaks) largest = std::max(largest, p.magnitude);
  const double dominant = largest * std::pow(10.0, -dominance_db / 20.0);
  size_t first = peaks.size();
  size_t last = 0;
  for (size_t i = 0; i < peaks.size(); ++i) {
    if (peaks[i].magnitude < dominant) continue;
    first = std::min(first, i);
    last = std::max(last, i);
  }
  const FrfPeak& p_lo = peaks[first];
  const FrfPeak& p_hi = peaks[last];
  const Eigen::Index n = f_hz.size();
  Eigen::Index from = bin_at(f_hz, std::max(min_frequency_hz, 0.5 * p_lo.f_hz));
  if (first > 0) from = std::max(from, peaks[first - 1].bin + 1);
  Eigen::Index to = bin_at(f_hz, std::min(2.0 * p_hi.f_hz, f_hz[n - 1]));
  if (last + 1 < peaks.size()) to = std::min(to, peaks[last + 1].bin - 1);
  const Eigen::Index lo = valley(magnitude, coherence, from, p_lo.bin - 1, min_coherence, from);
  const Eigen::Index hi = valley(magnitude, coherence, p_hi.bin + 1, to, min_coherence, to);
  return {f_hz[lo], f_hz[hi]};
}

std::vector<FrfPeak> peaks_to_fit(const std::vector<FrfPeak>& peaks,
                                  const std::array<double, 2>& band_hz, int n_modes,
                                  double floor_db, int max_modes,
                                  std::vector<std::string>* warnings) {
  std::vector<FrfPeak> chosen;
  for (const FrfPeak& p : peaks) {
    if (p.f_hz > band_hz[0] && p.f_hz < band_hz[1]) chosen.push_back(p);
  }
  std::sort(chosen.begin(), chosen.end(),
            [](const FrfPeak& a, const FrfPeak& b) { return a.magnitude > b.magnitude; });
  if (n_modes > 0) {
    if (static_cast<int>(chosen.size()) > n_modes) chosen.resize(static_cast<size_t>(n_modes));
  } else if (!chosen.empty()) {
    const double floor = chosen.front().magnitude * std::pow(10.0, -floor_db / 20.0);
    chosen.erase(std::remove_if(chosen.begin(), chosen.end(),
                                [floor](const FrfPeak& p) { return p.magnitude < floor; }),
                 chosen.end());
    if (static_cast<int>(chosen.size()) > max_modes) {
      warnings->push_back(std::to_string(chosen.size()) +
                          " peaks qualify in the band; fitting the " + std::to_string(max_modes) +
                          " largest (modal_fit.max_modes)");
      chosen.resize(static_cast<size_t>(max_modes));
    }
  }
  std::sort(chosen.begin(), chosen.end(),
            [](const FrfPeak& a, const FrfPeak& b) { return a.f_hz < b.f_hz; });
  return chosen;
}

}  // namespace frf
}  // namespace chatterlab
