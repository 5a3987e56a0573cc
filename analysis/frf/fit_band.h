// Automatic choices of the modal fit: the frequency band and the peaks to fit in it.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "analysis/frf/peaks.h"

namespace chatterlab {
namespace frf {

// The band [lo, hi] in Hz around the dominant peaks: those within dominance_db of the
// largest candidate. It runs from the lowest to the highest dominant peak, each edge moved
// out to the deepest |H| among bins with coherence >= min_coherence before the next
// candidate peak, and at most a factor 2 away in frequency (never below
// min_frequency_hz). With a single mode this gives about [fn/2, 2 fn].
// @param peaks  candidates in increasing frequency, not empty
std::array<double, 2> auto_fit_band(const Eigen::Ref<const Eigen::VectorXd>& f_hz,
                                    const Eigen::Ref<const Eigen::VectorXd>& magnitude,
                                    const Eigen::Ref<const Eigen::VectorXd>& coherence,
                                    const std::vector<FrfPeak>& peaks, double dominance_db,
                                    double min_frequency_hz, double min_coherence);

// The candidates strictly inside the band to fit, in increasing frequency: the n_modes
// largest if n_modes > 0, else those within floor_db of the largest in the band (at most
// max_modes, the largest kept; a warning says when some were left out).
std::vector<FrfPeak> peaks_to_fit(const std::vector<FrfPeak>& peaks,
                                  const std::array<double, 2>& band_hz, int n_modes,
                                  double floor_db, int max_modes,
                                  std::vector<std::string>* warnings);

}  // namespace frf
}  // namespace chatterlab
