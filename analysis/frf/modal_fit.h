// Modal parameters from a receptance FRF: peak picking, then a least-squares fit.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/frf/frf.h"
#include "analysis/frf/mode.h"

namespace chatterlab {
namespace frf {

enum class FrfEstimator { kH1, kH2 };

// Rules (docs/tap-tests.md gives the reasons):
//  Candidates: peaks of |H| above min_frequency_hz with coherence >= min_coherence on the
//    peak bin and two bins either side, and prominence >= min_prominence_db
//    (find_frf_peaks).
//  Automatic band: the dominant candidates are those within band_dominance_db of the
//    largest; the band runs from the lowest to the highest dominant peak, each edge moved
//    out to the deepest |H| valley (bins with good coherence) before the next candidate
//    peak, at most a factor 2 in frequency away.
//  Automatic mode count: the candidates inside the band within mode_floor_db of the
//    largest peak in the band (at most max_modes, the largest kept); a candidate the fit
//    pushes onto a bound of its frequency (the band edges) or damping ratio ([1e-6, 0.5])
//    is dropped with a warning and the fit repeated. n_modes > 0 takes the n largest
//    candidates in the band, and nothing is dropped.
//  Residual modes (automatic count, residual_modes): a mode closely spaced to a larger one
//    shows as a shoulder, not as a local maximum of |H|, so peak picking cannot see it.
//    After the fit, the largest local maximum of |H - H_fit| (coherence as for candidates,
//    within mode_floor_db of the band's largest peak) becomes a candidate; it is kept if the
//    refit (other modes starting where the last fit ended) converges with no mode on a
//    bound, no two modes closer than min_mode_spacing_bins * df, and raises the fit by at least
//    min_mode_gain_pct points. Repeated until max_modes, or max_rejected_residual_peaks
//    candidates in a row are rejected.
//  Fit: Ceres Levenberg-Marquardt on the complex receptance over the band, model and
//    parameters in modal_model.h, started from peak picking (parabolic peak frequency,
//    half-power bandwidth with a floor of half a bin, modal constant from the peak height).
//  Exponential window: each fitted pole is moved back by 1/tau (undo_exponential_window).
//  Warning: damping resolution-limited when 2 zeta fn < resolution_warning_bins * df.
struct ModalFitOptions {
  std::optional<std::array<double, 2>> band_hz;  // [lo, hi] in Hz; empty: automatic
  int n_modes = 0;                               // 0 = automatic
  FrfEstimator estimator = FrfEstimator::kH1;    // H1: best with noise on the response
  bool residual_terms = true;                    // upper (constant) and lower (mass-line) residuals
  double min_frequency_hz = 50.0;        // below: rigid-body motion and 1/w^2-amplified noise
  double min_coherence = 0.9;            // around a candidate peak, and at the band edges
  double min_prominence_db = 6.0;        // a candidate stands out of its surroundings by 2x
  double band_dominance_db = 20.0;       // dominant peaks: within 10x of the largest
  double mode_floor_db = 40.0;           // fitted peaks: within 100x of the largest in band
  int max_modes = 20;                    // automatic count: at most this many modes in one fit
  bool residual_modes = true;            // automatic count: add modes found in the fit's residual
  double min_mode_gain_pct = 0.5;        // a residual mode must raise the fit by this many points
  int max_rejected_residual_peaks = 3;   // stop after this many rejected residual peaks in a row
  double min_mode_spacing_bins = 2.0;    // a residual mode's fit keeps all modes this far apart
  double resolution_warning_bins = 4.0;  // 4 bins across the half-power band
  int max_iterations = 200;              // Levenberg-Marquardt iterations
};

// What a reader should know about one fitted mode (shown beside it in the report).
struct ModeQuality {
  // 2 zeta fn < resolution_warning_bins * df: zeta and c are estimates from few bins.
  bool resolution_limited = false;
  double half_power_bins = 0.0;    // 2 zeta fn / df
  bool negative_constant = false;  // A < 0: not a driving-point FRF (m, c, k use |A|)
  bool at_bound = false;           // the fit ended on a bound of wn or zeta
  bool from_residual = false;      // found in the residual of a fit (a shoulder), not as a peak
};

struct ModalFit {
  StepSummary summary;
  std::vector<Mode> modes;           // sorted by frequency, exponential window removed
  std::vector<ModeQuality> quality;  // one per mode, same order
  double fit_nrmse_pct = 0.0;        // 004 eq. 3.2 on the complex receptance over the band
  Eigen::VectorXcd fitted;           // the fitted model (window included) on frf.f_hz
  double band_lo_hz = 0.0;
  double band_hi_hz = 0.0;
  // Residual terms of the fitted model (0 without them):
  //   H_res(w) = upper_residual_m_n - lower_residual_per_kg / w^2.
  double upper_residual_m_n = 0.0;
  double lower_residual_per_kg = 0.0;
  int iterations = 0;
};

// @param frf  an FRF from compute_frf; a failed FRF gives a failed fit
// @throws InputError for an invalid band_hz or option
ModalFit fit_modes(const Frf& frf, const ModalFitOptions& options = {});

}  // namespace frf
}  // namespace chatterlab
