#include "analysis/frf/modal_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <optional>
#include <string>

#include "analysis/common/ceres_lm.h"
#include "analysis/common/constants.h"
#include "analysis/common/number_text.h"
#include "analysis/frf/fit_band.h"
#include "analysis/frf/modal_model.h"
#include "analysis/frf/peaks.h"
#include "analysis/frf/windows.h"
#include "analysis/metrics/metrics.h"

namespace chatterlab {
namespace frf {
namespace {

constexpr double kZetaMin = 1e-6;  // bounds of the fitted damping ratio
constexpr double kZetaMax = 0.5;   // a mode damped more than this shows no peak to fit
constexpr double kAtBound = 1e-3;  // relative distance that counts as "at a bound"

// Complex receptance residuals (model - measured) / scale, real and imaginary parts.
class ReceptanceCost : public ceres::CostFunction {
 public:
  ReceptanceCost(const ModalModel& model, const Eigen::VectorXd& w, const Eigen::VectorXcd& h,
                 double scale)
      : model_(model), w_(w), h_(h), scale_(scale) {
    set_num_residuals(static_cast<int>(2 * w_.size()));
    mutable_parameter_block_sizes()->push_back(model_.parameters());
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* theta = parameters[0];
    const int np = model_.parameters();
    const bool want_j = jacobians != nullptr && jacobians[0] != nullptr;
    std::vector<std::complex<double>> J_h_theta(static_cast<size_t>(np));
    for (Eigen::Index k = 0; k < w_.size(); ++k) {
      const std::complex<double> r =
          (model_.evaluate(theta, w_[k], want_j ? J_h_theta.data() : nullptr) - h_[k]) / scale_;
      residuals[2 * k] = r.real();
      residuals[2 * k + 1] = r.imag();
      if (!want_j) continue;
      double* row_re = jacobians[0] + (2 * k) * np;
      double* row_im = row_re + np;
      for (int p = 0; p < np; ++p) {
        row_re[p] = J_h_theta[static_cast<size_t>(p)].real() / scale_;
        row_im[p] = J_h_theta[static_cast<size_t>(p)].imag() / scale_;
      }
    }
    return true;
  }

 private:
  const ModalModel& model_;
  const Eigen::VectorXd& w_;
  const Eigen::VectorXcd& h_;
  double scale_;
};

struct BandData {
  std::vector<Eigen::Index> bins;
  Eigen::VectorXd w;   // rad/s
  Eigen::VectorXcd h;  // measured receptance
  double scale = 0.0;  // max |h|
  double w_lo = 0.0;
  double w_hi = 0.0;
};

struct Solved {
  bool converged = false;
  std::string message;
  ModalModel model;
  std::vector<double> theta;
  int iterations = 0;
  std::vector<size_t> at_bounds;  // modes whose wn or zeta ended on a bound
};

// Levenberg-Marquardt from peak picking (modal_model.h gives the parameters). With `warm`
// (a converged fit of the same peaks less peaks[added]), every other mode and the residual
// terms start where that fit ended; only peaks[added] starts from peak picking.
Solved solve(const std::vector<FrfPeak>& peaks, const BandData& band, double df,
             const ModalFitOptions& o, const Solved* warm = nullptr, int added = -1) {
  Solved s;
  const int n = static_cast<int>(peaks.size());
  s.model.wn0.resize(n);
  s.model.zeta0.resize(n);
  s.model.a0.resize(n);
  for (int i = 0; i < n; ++i) {
    const FrfPeak& p = peaks[static_cast<size_t>(i)];
    // Half-power bandwidth, floored at half a bin: a narrower peak is not resolved.
    const double bw = std::max(p.half_power_bw_hz, 0.5 * df);
    const double wn = kTwoPi * p.f_hz;
    const double zeta = std::clamp(bw / (2.0 * p.f_hz), 2.0 * kZetaMin, 0.5 * kZetaMax);
    // |H(wn)| = |A| / (2 zeta wn^2) with phase -90 deg for A > 0 (003 eq. 4-27).
    const double sign = p.value.imag() <= 0.0 ? 1.0 : -1.0;
    s.model.wn0[i] = wn;
    s.model.zeta0[i] = zeta;
    s.model.a0[i] = sign * p.magnitude * 2.0 * zeta * wn * wn;
    if (warm != nullptr && i != added) {
      const int j = i < added ? i : i - 1;
      s.model.wn0[i] = warm->model.wn(warm->theta.data(), j);
      s.model.zeta0[i] = warm->model.zeta(warm->theta.data(), j);
      s.model.a0[i] = warm->model.a(warm->theta.data(), j);
    }
  }
  s.model.residual_scale = o.residual_terms ? band.scale : 0.0;
  s.model.w_ref = band.w_lo;
  s.theta.assign(static_cast<size_t>(s.model.parameters()), 0.0);
  for (int i = 0; i < n; ++i) s.theta[static_cast<size_t>(3 * i + 2)] = 1.0;
  if (warm != nullptr && o.residual_terms) {
    s.theta[static_cast<size_t>(3 * n)] = warm->theta[static_cast<size_t>(3 * (n - 1))];
    s.theta[static_cast<size_t>(3 * n + 1)] = warm->theta[static_cast<size_t>(3 * (n - 1) + 1)];
  }

  ceres::Problem problem;
  problem.AddResidualBlock(new ReceptanceCost(s.model, band.w, band.h, band.scale), nullptr,
                           s.theta.data());
  for (int i = 0; i < n; ++i) {
    problem.SetParameterLowerBound(s.theta.data(), 3 * i, std::log(band.w_lo / s.model.wn0[i]));
    problem.SetParameterUpperBound(s.theta.data(), 3 * i, std::log(band.w_hi / s.model.wn0[i]));
    problem.SetParameterLowerBound(s.theta.data(), 3 * i + 1,
                                   std::log(kZetaMin / s.model.zeta0[i]));
    problem.SetParameterUpperBound(s.theta.data(), 3 * i + 1,
                                   std::log(kZetaMax / s.model.zeta0[i]));
  }
  const ceres::Solver::Options options = dense_lm_options(o.max_iterations, 1e-12, 1e-12, 1e-14);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  s.iterations = lm_iterations(summary);
  s.converged = summary.termination_type == ceres::CONVERGENCE;
  s.message = summary.message;
  for (int i = 0; i < n; ++i) {
    const double wn = s.model.wn(s.theta.data(), i);
    const double zeta = s.model.zeta(s.theta.data(), i);
    if (wn <= band.w_lo * (1.0 + kAtBound) || wn >= band.w_hi * (1.0 - kAtBound) ||
        zeta <= kZetaMin * (1.0 + kAtBound) || zeta >= kZetaMax * (1.0 - kAtBound)) {
      s.at_bounds.push_back(static_cast<size_t>(i));
    }
  }
  return s;
}

// NRMSE fit (004 eq. 3.2) of a solved model over the band.
double band_fit_pct(const Solved& s, const BandData& band) {
  Eigen::VectorXcd model(band.w.size());
  for (Eigen::Index k = 0; k < band.w.size(); ++k) {
    model[k] = s.model.evaluate(s.theta.data(), band.w[k]);
  }
  return metrics::nrmse_fit_pct(band.h, model);
}

// The largest local maximum of |H - H_fit| in the band that could be a mode hidden in a
// shoulder of a larger one: coherence >= min_coherence on its bin and two bins either side
// (as for a peak of |H|), height >= floor, and more than 1.5 bins from every frequency in
// `tried`. As an FrfPeak: parabolic frequency and height of |residual|, value = residual
// (its imaginary part gives the sign of the modal constant), half-power bandwidth of
// |residual| (the start value of zeta, floored at half a bin by solve). Empty when none.
std::optional<FrfPeak> residual_peak(const Solved& s, const BandData& band, const Frf& frf,
                                     double min_coherence, double floor,
                                     const std::vector<double>& tried) {
  const Eigen::Index n = band.w.size();
  Eigen::VectorXcd r(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    r[k] = band.h[k] - s.model.evaluate(s.theta.data(), band.w[k]);
  }
  const Eigen::VectorXd mag = r.cwiseAbs();
  const Eigen::Index nb = frf.coherence.size();
  Eigen::Index best = -1;
  for (Eigen::Index k = 1; k + 1 < n; ++k) {
    if (!(mag[k] > mag[k - 1] && mag[k] >= mag[k + 1]) || mag[k] < floor) continue;
    if (best >= 0 && mag[k] <= mag[best]) continue;
    const Eigen::Index bin = band.bins[static_cast<size_t>(k)];
    const Eigen::Index c_from = std::max<Eigen::Index>(0, bin - 2);
    const Eigen::Index c_to = std::min<Eigen::Index>(nb - 1, bin + 2);
    if (frf.coherence.segment(c_from, c_to - c_from + 1).minCoeff() < min_coherence) continue;
    const double f = frf.f_hz[bin];
    if (std::any_of(tried.begin(), tried.end(),
                    [&](double t) { return std::abs(t - f) < 1.5 * frf.df_hz; })) {
      continue;
    }
    best = k;
  }
  if (best < 0) return std::nullopt;
  const double ym = mag[best - 1];
  const double y0 = mag[best];
  const double yp = mag[best + 1];
  const double curvature = ym - 2.0 * y0 + yp;
  const double delta = curvature < 0.0 ? 0.5 * (ym - yp) / curvature : 0.0;
  FrfPeak p;
  p.bin = band.bins[static_cast<size_t>(best)];
  p.f_hz = frf.f_hz[p.bin] + delta * frf.df_hz;
  p.magnitude = y0 - 0.25 * (ym - yp) * delta;
  p.value = r[best];
  // Half-power bandwidth of the residual peak (linear interpolation; one side doubled when
  // the other rises again first), as find_frf_peaks does for |H|.
  const double level = p.magnitude / std::sqrt(2.0);
  auto crossing = [&](int step) {
    for (Eigen::Index i = best;;) {
      const Eigen::Index j = i + step;
      if (j < 0 || j >= n || mag[j] > mag[i]) return -1.0;
      if (mag[j] <= level) {
        const double past = static_cast<double>(i - best) +
                            step * (mag[i] - level) / (mag[i] - mag[j]);  // bins from `best`
        return std::abs(past - delta);  // bins from the parabolic peak
      }
      i = j;
    }
  };
  const double lo = crossing(-1);
  const double hi = crossing(+1);
  const double bins = lo > 0.0 && hi > 0.0 ? lo + hi : 2.0 * std::max(lo, hi);
  p.half_power_bw_hz = std::max(0.0, bins) * frf.df_hz;
  return p;
}

void check_options(const ModalFitOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw InputError("modal_fit." + what);
  };
  require(o.n_modes >= 0, "n_modes = " + std::to_string(o.n_modes) + ": must be >= 0 (0 = auto)");
  require(o.max_modes >= 1, "max_modes = " + std::to_string(o.max_modes) + ": must be >= 1");
  require(o.min_frequency_hz >= 0.0,
          "min_frequency_hz = " + std::to_string(o.min_frequency_hz) + ": must be >= 0");
  require(o.min_coherence >= 0.0 && o.min_coherence <= 1.0,
          "min_coherence = " + std::to_string(o.min_coherence) + ": must be in [0, 1]");
  require(o.min_prominence_db >= 0.0,
          "min_prominence_db = " + std::to_string(o.min_prominence_db) + ": must be >= 0");
  require(o.band_dominance_db >= 0.0,
          "band_dominance_db = " + std::to_string(o.band_dominance_db) + ": must be >= 0");
  require(o.mode_floor_db >= 0.0,
          "mode_floor_db = " + std::to_string(o.mode_floor_db) + ": must be >= 0");
  require(
      o.resolution_warning_bins >= 0.0,
      "resolution_warning_bins = " + std::to_string(o.resolution_warning_bins) + ": must be >= 0");
  require(o.min_mode_gain_pct >= 0.0,
          "min_mode_gain_pct = " + std::to_string(o.min_mode_gain_pct) + ": must be >= 0");
  require(o.min_mode_spacing_bins >= 0.0,
          "min_mode_spacing_bins = " + std::to_string(o.min_mode_spacing_bins) + ": must be >= 0");
  require(o.max_rejected_residual_peaks >= 1,
          "max_rejected_residual_peaks = " + std::to_string(o.max_rejected_residual_peaks) +
              ": must be >= 1");
  require(o.max_iterations >= 1,
          "max_iterations = " + std::to_string(o.max_iterations) + ": must be >= 1");
}

}  // namespace

ModalFit fit_modes(const Frf& frf, const ModalFitOptions& o) {
  check_options(o);
  ModalFit fit;
  if (!frf.summary.ok()) {
    fit.summary.fail("no modal fit: the FRF failed (" + frf.summary.message + ")");
    return fit;
  }
  const Eigen::Index nb = frf.f_hz.size();
  if (nb < 8 || frf.coherence.size() != nb || frf.h1.size() != nb || frf.h2.size() != nb) {
    fit.summary.fail("no modal fit: the FRF has " + std::to_string(nb) +
                     " bins (or inconsistent sizes): needs at least 8");
    return fit;
  }
  const Eigen::VectorXcd& h = o.estimator == FrfEstimator::kH1 ? frf.h1 : frf.h2;
  const double f_last = frf.f_hz[nb - 1];

  PeakOptions peak_options;
  peak_options.min_prominence_db = o.min_prominence_db;
  peak_options.min_coherence = o.min_coherence;
  peak_options.f_min_hz = o.min_frequency_hz;
  const std::vector<FrfPeak> peaks = find_frf_peaks(frf.f_hz, h, frf.coherence, peak_options);
  const std::string peak_rule =
      printf_text("coherence >= %g and prominence >= %g dB above %g Hz", o.min_coherence,
                  o.min_prominence_db, o.min_frequency_hz);

  std::array<double, 2> band_hz{};
  if (o.band_hz) {
    band_hz = *o.band_hz;
    if (!(band_hz[0] > 0.0 && band_hz[1] > band_hz[0] && band_hz[0] < f_last)) {
      throw InputError(
          printf_text("modal_fit.band_hz = [%g, %g]: must satisfy 0 < lo < hi and lo < %g Hz "
                      "(the last FRF bin)",
                      band_hz[0], band_hz[1], f_last));
    }
    band_hz[1] = std::min(band_hz[1], f_last);
  } else if (peaks.empty()) {
    fit.summary.fail("no resonance peak with " + peak_rule + ": cannot choose a fit band");
    return fit;
  } else {
    band_hz = auto_fit_band(frf.f_hz, h.cwiseAbs(), frf.coherence, peaks, o.band_dominance_db,
                            o.min_frequency_hz, o.min_coherence);
  }
  fit.band_lo_hz = band_hz[0];
  fit.band_hi_hz = band_hz[1];

  std::vector<FrfPeak> chosen =
      peaks_to_fit(peaks, band_hz, o.n_modes, o.mode_floor_db, o.max_modes, &fit.summary.warnings);
  const std::string in_band = printf_text(" in the band [%.6g, %.6g] Hz", band_hz[0], band_hz[1]);
  if (o.n_modes > 0 && static_cast<int>(chosen.size()) < o.n_modes) {
    fit.summary.fail("modal_fit.n_modes = " + std::to_string(o.n_modes) + " but only " +
                     std::to_string(chosen.size()) + " peaks with " + peak_rule + " lie" + in_band);
    return fit;
  }
  if (chosen.empty()) {
    fit.summary.fail("no resonance peak with " + peak_rule + in_band);
    return fit;
  }

  BandData band;
  for (Eigen::Index k = 0; k < nb; ++k) {
    if (frf.f_hz[k] >= band_hz[0] && frf.f_hz[k] <= band_hz[1]) band.bins.push_back(k);
  }
  const auto n_band = static_cast<Eigen::Index>(band.bins.size());
  band.w.resize(n_band);
  band.h.resize(n_band);
  for (Eigen::Index k = 0; k < n_band; ++k) {
    band.w[k] = kTwoPi * frf.f_hz[band.bins[static_cast<size_t>(k)]];
    band.h[k] = h[band.bins[static_cast<size_t>(k)]];
    band.scale = std::max(band.scale, std::abs(band.h[k]));
  }
  band.w_lo = kTwoPi * band_hz[0];
  band.w_hi = kTwoPi * band_hz[1];
  const int n_params = 3 * static_cast<int>(chosen.size()) + (o.residual_terms ? 2 : 0);
  if (n_band < n_params || !(band.scale > 0.0)) {
    fit.summary.fail(printf_text("the band holds %g bins: too few for %g parameters",
                                 static_cast<double>(n_band), static_cast<double>(n_params)) +
                     in_band);
    return fit;
  }

  // Automatic count: a candidate the fit pushes onto a bound of wn or zeta is not a
  // resonance the data support; drop it and fit again.
  Solved s = solve(chosen, band, frf.df_hz, o);
  while (o.n_modes == 0 && s.converged && !s.at_bounds.empty() &&
         s.at_bounds.size() < chosen.size()) {
    for (auto it = s.at_bounds.rbegin(); it != s.at_bounds.rend(); ++it) {
      fit.summary.warnings.push_back(printf_text(
          "peak at %.6g Hz dropped: the fit moved it onto a bound of its frequency or damping",
          chosen[*it].f_hz));
      chosen.erase(chosen.begin() + static_cast<long>(*it));
    }
    s = solve(chosen, band, frf.df_hz, o);
  }
  // Residual modes: a mode closely spaced to a larger one is a shoulder of |H|, not a peak;
  // it shows as a peak of the residual. Added one at a time while each raises the fit.
  std::vector<bool> from_residual(chosen.size(), false);
  if (o.n_modes == 0 && o.residual_modes && s.converged && s.at_bounds.empty()) {
    double largest = 0.0;
    for (const FrfPeak& p : chosen) largest = std::max(largest, p.magnitude);
    const double floor = largest * std::pow(10.0, -o.mode_floor_db / 20.0);
    double fit_pct = band_fit_pct(s, band);
    std::vector<double> tried;
    std::string added;
    for (int rejected = 0; rejected < o.max_rejected_residual_peaks &&
                           static_cast<int>(chosen.size()) < o.max_modes &&
                           100.0 - fit_pct >= o.min_mode_gain_pct &&
                           n_band >= 3 * static_cast<Eigen::Index>(chosen.size() + 1) + 2;) {
      const std::optional<FrfPeak> p = residual_peak(s, band, frf, o.min_coherence, floor, tried);
      if (!p) break;
      tried.push_back(frf.f_hz[p->bin]);
      const auto at = std::upper_bound(chosen.begin(), chosen.end(), p->f_hz,
                                       [](double f, const FrfPeak& q) { return f < q.f_hz; });
      const auto pos = at - chosen.begin();
      std::vector<FrfPeak> trial = chosen;
      trial.insert(trial.begin() + pos, *p);
      Solved t = solve(trial, band, frf.df_hz, o, &s, static_cast<int>(pos));
      // Two modes closer than min_mode_spacing_bins are not resolved by the bins.
      bool resolved = true;
      for (int i = 0; i + 1 < t.model.modes(); ++i) {
        for (int j = i + 1; j < t.model.modes(); ++j) {
          resolved =
              resolved && std::abs(t.model.wn(t.theta.data(), i) - t.model.wn(t.theta.data(), j)) >=
                              kTwoPi * o.min_mode_spacing_bins * frf.df_hz;
        }
      }
      const double trial_pct =
          t.converged && t.at_bounds.empty() && resolved ? band_fit_pct(t, band) : -1e300;
      if (trial_pct - fit_pct < o.min_mode_gain_pct) {
        ++rejected;
        continue;
      }
      added += (added.empty() ? "" : ", ") + printf_text("%.6g", p->f_hz);
      chosen = std::move(trial);
      from_residual.insert(from_residual.begin() + pos, true);
      s = std::move(t);
      fit_pct = trial_pct;
      rejected = 0;
    }
    if (!added.empty()) {
      fit.summary.warnings.push_back(
          "modes added from the fit's residual (shoulders of closely spaced modes, not peaks "
          "of |H|) near " +
          added +
          printf_text(" Hz: each raised the fit by at least %g points", o.min_mode_gain_pct));
    }
  }

  fit.iterations = s.iterations;
  const int n_modes = s.model.modes();
  if (!s.converged) {
    fit.summary.fail(
        printf_text("modal fit of %g modes", n_modes) + in_band +
        printf_text(" did not converge within modal_fit.max_iterations = %g: ", o.max_iterations) +
        s.message);
    return fit;
  }

  // Model on every bin, and the fit over the band (004 eq. 3.2).
  fit.fitted.resize(nb);
  for (Eigen::Index k = 0; k < nb; ++k) {
    fit.fitted[k] = s.model.evaluate(s.theta.data(), kTwoPi * frf.f_hz[k]);
  }
  Eigen::VectorXcd fitted_band(n_band);
  for (Eigen::Index k = 0; k < n_band; ++k) {
    fitted_band[k] = fit.fitted[band.bins[static_cast<size_t>(k)]];
  }
  fit.fit_nrmse_pct = metrics::nrmse_fit_pct(band.h, fitted_band);
  if (o.residual_terms) {
    const double r_upper = s.theta[static_cast<size_t>(3 * n_modes)];
    const double r_lower = s.theta[static_cast<size_t>(3 * n_modes + 1)];
    fit.upper_residual_m_n = band.scale * r_upper;
    fit.lower_residual_per_kg = band.scale * r_lower * band.w_lo * band.w_lo;
  }

  // Physical modes, exponential window removed (windows.h), m = 1/A (003 eq. 4-27).
  std::vector<std::pair<Mode, ModeQuality>> found;
  for (int i = 0; i < n_modes; ++i) {
    const double fn_fit = s.model.wn(s.theta.data(), i) / kTwoPi;
    const double zeta_fit = s.model.zeta(s.theta.data(), i);
    const double a = s.model.a(s.theta.data(), i);
    const PoleShift pole = undo_exponential_window(fn_fit, zeta_fit, frf.exp_window_tau_s);
    if (!(pole.zeta > 0.0)) {
      fit.summary.fail(
          printf_text("mode at %.6g Hz: damping ratio %.4g after removing the exponential "
                      "window (fitted %.4g, window 1/(tau wn) = %.4g) is not positive: the "
                      "window is too strong for this mode",
                      fn_fit, pole.zeta, zeta_fit, 1.0 / (frf.exp_window_tau_s * kTwoPi * fn_fit)));
      return fit;
    }
    ModeQuality q;
    q.at_bound = std::find(s.at_bounds.begin(), s.at_bounds.end(), static_cast<size_t>(i)) !=
                 s.at_bounds.end();
    if (q.at_bound) {
      fit.summary.warnings.push_back(printf_text(
          "mode at %.6g Hz (zeta %.4g) ended on a bound of its frequency (the band) or damping "
          "[%g, %g]: treat it with suspicion",
          fn_fit, zeta_fit, kZetaMin, kZetaMax));
    }
    q.from_residual = from_residual[static_cast<size_t>(i)];
    q.negative_constant = a < 0.0;
    const Mode m = mode_from_modal(pole.fn_hz, pole.zeta, 1.0 / std::abs(a));
    q.half_power_bins = 2.0 * m.zeta * m.fn_hz / frf.df_hz;
    q.resolution_limited = q.half_power_bins < o.resolution_warning_bins;
    found.emplace_back(m, q);
  }
  std::sort(found.begin(), found.end(),
            [](const auto& x, const auto& y) { return x.first.fn_hz < y.first.fn_hz; });
  // One warning per kind, listing the modes it concerns (the report flags each mode).
  std::string negative, limited;
  int n_limited = 0;
  double bins_lo = 1e300, bins_hi = 0.0;
  for (const auto& [m, q] : found) {
    fit.modes.push_back(m);
    fit.quality.push_back(q);
    if (q.negative_constant)
      negative += (negative.empty() ? "" : ", ") + printf_text("%.6g", m.fn_hz);
    if (q.resolution_limited) {
      limited += (limited.empty() ? "" : ", ") + printf_text("%.6g", m.fn_hz);
      ++n_limited;
      bins_lo = std::min(bins_lo, q.half_power_bins);
      bins_hi = std::max(bins_hi, q.half_power_bins);
    }
  }
  if (!negative.empty()) {
    fit.summary.warnings.push_back(
        "negative modal constant (phase +90 deg at resonance) at " + negative +
        " Hz: not a driving-point FRF or a channel sign is inverted; m, c, k use |A|");
  }
  if (n_limited > 0) {
    fit.summary.warnings.push_back(
        printf_text("damping is resolution-limited for %g of ", static_cast<double>(n_limited)) +
        printf_text("%g modes (", static_cast<double>(n_modes)) + limited +
        printf_text(" Hz): half-power bandwidth 2 zeta fn is below %g df = ",
                    o.resolution_warning_bins) +
        printf_text("%.3g Hz, so zeta and c are estimates from ",
                    o.resolution_warning_bins * frf.df_hz) +
        printf_text("%.2g to ", bins_lo) +
        printf_text("%.2g bins; longer records (finer df) would resolve them", bins_hi));
  }
  if (fit.fit_nrmse_pct < 80.0) {
    fit.summary.warnings.push_back(
        printf_text("poor fit: NRMSE fit %.1f %% over the band (below 80 %%)", fit.fit_nrmse_pct));
  }
  fit.summary.succeed();
  return fit;
}

}  // namespace frf
}  // namespace chatterlab
