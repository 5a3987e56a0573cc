// Peak picking on an FRF: resonance candidates and their half-power bandwidths.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <vector>

#include "analysis/common/summary.h"  // InputError

namespace chatterlab {
namespace frf {

struct FrfPeak {
  Eigen::Index bin = 0;           // index of the local maximum of |H|
  double f_hz = 0.0;              // parabolic interpolation of |H| over bin-1, bin, bin+1
  double magnitude = 0.0;         // |H| at the interpolated maximum
  std::complex<double> value;     // H at `bin`
  double prominence_db = 0.0;     // 20 log10(|H|peak / higher of the two bases)
  double half_power_bw_hz = 0.0;  // between the |H|peak/sqrt(2) crossings (linear
                                  // interpolation); one side doubled when the other is hidden by
                                  // a neighbour; 0 when neither side crosses before a valley
};

struct PeakOptions {
  double min_prominence_db = 6.0;    // a resonance stands out by at least a factor 2
  double min_coherence = 0.9;        // on every bin within coherence_halfwidth_bins of the peak
  int coherence_halfwidth_bins = 2;  // a noise spike is one good bin among poor ones
  double f_min_hz = 0.0;             // search range
  double f_max_hz = 0.0;             // 0 = up to the last bin
};

// Local maxima of |h| (h[i] > h[i-1], h[i] >= h[i+1]) in [f_min_hz, f_max_hz] with
// coherence >= min_coherence on bins i-w .. i+w (w = coherence_halfwidth_bins) and prominence >=
// min_prominence_db. Prominence as in topographic maps: from the peak go left and right until a
// higher |H| or the end of the data; each side's base is the lowest |H| on the way; the prominence
// compares the peak with the higher base.
// @param f_hz, h, coherence  same length, f_hz evenly spaced
// @return peaks in increasing frequency
std::vector<FrfPeak> find_frf_peaks(const Eigen::Ref<const Eigen::VectorXd>& f_hz,
                                    const Eigen::Ref<const Eigen::VectorXcd>& h,
                                    const Eigen::Ref<const Eigen::VectorXd>& coherence,
                                    const PeakOptions& options = {});

}  // namespace frf
}  // namespace chatterlab
