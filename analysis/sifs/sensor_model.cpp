#include "analysis/sifs/sensor_model.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>

#include "analysis/common/ceres_lm.h"
#include "analysis/common/constants.h"
#include "analysis/common/number_text.h"
#include "analysis/common/statistics.h"
#include "analysis/frf/peaks.h"
#include "analysis/signal/fft.h"

namespace chatterlab {
namespace sifs {
namespace {

using cd = std::complex<double>;

constexpr double kMadToStd = 1.4826;  // std of a Gaussian = 1.4826 MAD
// `auto` hits: the threshold must stand this far above the hammer's noise std, or the
// "hits" are noise (the frf/hits.h default noise_multiple).
constexpr double kAutoNoiseMultiple = 10.0;
// tap_frf: a window whose hammer stays within this multiple of its noise std has no impact.
constexpr double kImpactNoiseMultiple = 10.0;
// Fit: bounds of the damping ratio (the upper one is SensorFitOptions::max_zeta), "at a bound"
// within this relative distance, and the iteration cap of Levenberg-Marquardt.
constexpr double kZetaMin = 1e-6;
constexpr double kAtBound = 1e-3;
constexpr int kMaxIterations = 200;
// Peak picking: a resonance stands out of its bases by at least a factor 2 (the frf/peaks.h
// default; a noise wiggle in an antiresonance does not); a peak in noise (coherence below one
// half) is no start.
constexpr double kMinProminenceDb = 6.0;
constexpr double kPeakMinCoherence = 0.5;
// Warnings: G(0) off 1 by more than this (003 sec. 4.2: the sensor is statically calibrated)
// when unit_static_gain is off, and a fit error above this percentage.
constexpr double kStaticGainTolerance = 0.1;
constexpr double kPoorFitPct = 20.0;

Eigen::Index samples(double seconds, double fs_hz) {
  return static_cast<Eigen::Index>(std::llround(seconds * fs_hz));
}

void check_tap_options(const TapOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw InputError("sifs-tap." + what);
  };
  require(o.impact_fraction > 0.0 && o.impact_fraction < 1.0,
          "impact_fraction = " + printf_text("%g", o.impact_fraction) + ": must be in (0, 1)");
  require(o.pre_impact_guard_s >= 0.0,
          "pre_impact_guard_s = " + printf_text("%g", o.pre_impact_guard_s) + ": must be >= 0");
  require(o.min_pre_impact_s > o.pre_impact_guard_s,
          "min_pre_impact_s = " + printf_text("%g", o.min_pre_impact_s) +
              ": must be > pre_impact_guard_s = " + printf_text("%g", o.pre_impact_guard_s));
  require(o.auto_threshold_fraction > 0.0 && o.auto_threshold_fraction < 1.0,
          "auto_threshold_fraction = " + printf_text("%g", o.auto_threshold_fraction) +
              ": must be in (0, 1)");
  require(o.auto_bounce_s >= 0.0,
          "auto_bounce_s = " + printf_text("%g", o.auto_bounce_s) + ": must be >= 0");
  require(o.auto_pretrigger_s >= 0.0,
          "auto_pretrigger_s = " + printf_text("%g", o.auto_pretrigger_s) + ": must be >= 0");
  require(o.auto_max_window_s > 0.0,
          "auto_max_window_s = " + printf_text("%g", o.auto_max_window_s) + ": must be > 0");
}

void check_rate(double fs_hz) {
  if (!(std::isfinite(fs_hz) && fs_hz > 0.0)) {
    throw InputError("sifs-tap sample_rate_hz = " + printf_text("%g", fs_hz) + ": must be > 0");
  }
}

// The impact of one window: the first sample with |hammer - baseline| >= impact_fraction x
// the window's largest |hammer - baseline|.
struct Impact {
  Eigen::Index sample = 0;
  double peak_n = 0.0;
};
Impact find_impact(const Eigen::Ref<const Eigen::VectorXd>& hammer, double baseline,
                   double impact_fraction) {
  Impact im;
  im.peak_n = (hammer.array() - baseline).abs().maxCoeff();
  const double level = impact_fraction * im.peak_n;
  while (im.sample < hammer.size() && std::abs(hammer[im.sample] - baseline) < level) ++im.sample;
  return im;
}

// The modal model of 003 eq. 4-27 on log-parametrised fn and zeta: theta = [p_1, q_1, ...,
// p_k, q_k, free alphas], wn_i = wn0_i e^{p_i}, zeta_i = zeta0_i e^{q_i}. With a unit static
// gain the alpha of mode `eliminated` is 1 - the sum of the others.
struct SensorModelParams {
  std::vector<double> wn0, zeta0;
  int eliminated = -1;  // -1: every alpha free

  int modes() const { return static_cast<int>(wn0.size()); }
  int parameters() const { return 3 * modes() - (eliminated >= 0 ? 1 : 0); }
  double wn(const double* t, int i) const {
    return wn0[static_cast<size_t>(i)] * std::exp(t[2 * i]);
  }
  double zeta(const double* t, int i) const {
    return zeta0[static_cast<size_t>(i)] * std::exp(t[2 * i + 1]);
  }
  // Index in theta of mode i's alpha, or -1 for the eliminated one.
  int alpha_index(int i) const {
    if (i == eliminated) return -1;
    return 2 * modes() + (eliminated >= 0 && i > eliminated ? i - 1 : i);
  }
  double alpha(const double* t, int i) const {
    if (i != eliminated) return t[alpha_index(i)];
    double sum = 0.0;
    for (int j = 0; j < modes(); ++j) {
      if (j != eliminated) sum += t[alpha_index(j)];
    }
    return 1.0 - sum;
  }
  std::vector<SensorMode> to_modes(const double* t) const {
    std::vector<SensorMode> m(static_cast<size_t>(modes()));
    for (int i = 0; i < modes(); ++i) {
      m[static_cast<size_t>(i)] = {wn(t, i) / kTwoPi, zeta(t, i), alpha(t, i)};
    }
    return m;
  }
};

// Weighted complex residuals weight_k (G(j w_k) - H_k) / scale, real and imaginary parts, with
// the analytic Jacobian of T_i = a wn^2 / D, D = wn^2 - w^2 + 2 j zeta wn w:
//   dT/dp = 2 a wn^2 (j zeta wn w - w^2) / D^2,  dT/dq = -2 j a zeta wn^3 w / D^2,
//   dT/da = wn^2 / D (minus the eliminated mode's wn_e^2 / D_e under sum alpha = 1).
class SensorCost : public ceres::CostFunction {
 public:
  SensorCost(const SensorModelParams& model, const Eigen::VectorXd& w, const Eigen::VectorXcd& h,
             const Eigen::VectorXd& weight, double scale)
      : model_(model), w_(w), h_(h), weight_(weight), scale_(scale) {
    set_num_residuals(static_cast<int>(2 * w_.size()));
    mutable_parameter_block_sizes()->push_back(model_.parameters());
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* t = parameters[0];
    const int k = model_.modes();
    const int np = model_.parameters();
    const bool want_j = jacobians != nullptr && jacobians[0] != nullptr;
    std::vector<double> wn(static_cast<size_t>(k)), zeta(static_cast<size_t>(k)),
        alpha(static_cast<size_t>(k));
    for (int i = 0; i < k; ++i) {
      wn[static_cast<size_t>(i)] = model_.wn(t, i);
      zeta[static_cast<size_t>(i)] = model_.zeta(t, i);
      alpha[static_cast<size_t>(i)] = model_.alpha(t, i);
    }
    std::vector<cd> J_g_t(static_cast<size_t>(np));
    for (Eigen::Index b = 0; b < w_.size(); ++b) {
      const double w = w_[b];
      const double c = weight_[b] / scale_;
      cd g = 0.0;
      cd eliminated_da(0.0, 0.0);
      for (int i = 0; i < k; ++i) {
        const auto s = static_cast<size_t>(i);
        const double wn2 = wn[s] * wn[s];
        const cd D(wn2 - w * w, 2.0 * zeta[s] * wn[s] * w);
        g += alpha[s] * wn2 / D;
        if (!want_j) continue;
        const cd D2 = D * D;
        J_g_t[static_cast<size_t>(2 * i)] =
            2.0 * alpha[s] * wn2 * cd(-w * w, zeta[s] * wn[s] * w) / D2;
        J_g_t[static_cast<size_t>(2 * i + 1)] =
            cd(0.0, -2.0 * alpha[s] * zeta[s] * wn2 * wn[s] * w) / D2;
        if (i == model_.eliminated) {
          eliminated_da = wn2 / D;
        } else {
          J_g_t[static_cast<size_t>(model_.alpha_index(i))] = wn2 / D;
        }
      }
      const cd r = c * (g - h_[b]);
      residuals[2 * b] = r.real();
      residuals[2 * b + 1] = r.imag();
      if (!want_j) continue;
      double* row_re = jacobians[0] + (2 * b) * np;
      double* row_im = row_re + np;
      for (int p = 0; p < np; ++p) {
        cd d = J_g_t[static_cast<size_t>(p)];
        if (p >= 2 * k) d -= eliminated_da;
        row_re[p] = c * d.real();
        row_im[p] = c * d.imag();
      }
    }
    return true;
  }

 private:
  const SensorModelParams& model_;
  const Eigen::VectorXd& w_;
  const Eigen::VectorXcd& h_;
  const Eigen::VectorXd& weight_;
  double scale_;
};

// One side of the half-power band: Hz from the peak bin to where |H| first falls to `level`
// walking by `step` (+1 or -1), linearly interpolated; < 0 when |H| climbs above the peak
// (a higher neighbour) or the band ends first. Noise wiggles on the flank do not stop the walk
// (unlike frf::find_frf_peaks' half-power bandwidth, which stops at any local minimum).
double half_power_side(const Eigen::VectorXd& mag, const Eigen::VectorXd& f_hz, Eigen::Index peak,
                       int step, double level) {
  for (Eigen::Index i = peak;;) {
    const Eigen::Index j = i + step;
    if (j < 0 || j >= mag.size() || mag[j] > mag[peak]) return -1.0;
    if (mag[j] <= level) {
      const double t = (mag[i] - level) / (mag[i] - mag[j]);
      return std::abs(f_hz[i] + t * (f_hz[j] - f_hz[i]) - f_hz[peak]);
    }
    i = j;
  }
}

void check_fit_options(const SensorFitOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw InputError("sifs-tap " + what);
  };
  require(o.modes >= 1, "modes = " + std::to_string(o.modes) + ": must be >= 1");
  require(std::isfinite(o.band_lo_hz) && std::isfinite(o.band_hi_hz) && o.band_lo_hz >= 0.0 &&
              o.band_hi_hz > o.band_lo_hz,
          printf_text("band_hz = [%g, %g]: must satisfy 0 <= lo < hi", o.band_lo_hz, o.band_hi_hz));
  require(o.max_zeta > 2.0 * kZetaMin && o.max_zeta < 1.0,
          "max_zeta = " + printf_text("%g", o.max_zeta) + ": must be in (2e-6, 1)");
}

}  // namespace

std::vector<TapWindow> auto_tap_windows(const Eigen::Ref<const Eigen::VectorXd>& hammer_n,
                                        double fs_hz, const TapOptions& o) {
  check_rate(fs_hz);
  check_tap_options(o);
  const Eigen::Index n = hammer_n.size();
  if (n < 16) {
    throw InputError("hits: auto: the hammer record has " + std::to_string(n) +
                     " samples: needs at least 16");
  }
  if (!hammer_n.allFinite())
    throw InputError("hits: auto: the hammer record has non-finite samples");
  const double baseline = median(hammer_n);
  const Eigen::VectorXd d = (hammer_n.array() - baseline).abs();
  const double largest = d.maxCoeff();
  const double noise = kMadToStd * median(d);
  const double threshold = o.auto_threshold_fraction * largest;
  if (!(threshold > kAutoNoiseMultiple * noise) || !(threshold > 0.0)) {
    throw InputError(
        printf_text("hits: auto: the hammer shows no hit: the threshold %g x the largest "
                    "|hammer - median| = %.4g N is not above %g x the hammer noise std %.4g N",
                    o.auto_threshold_fraction, threshold, kAutoNoiseMultiple, noise));
  }
  const Eigen::Index bounce = samples(o.auto_bounce_s, fs_hz);
  const Eigen::Index pre = samples(o.auto_pretrigger_s, fs_hz);
  std::vector<Eigen::Index> impacts;
  Eigen::Index last_crossing = -1;
  for (Eigen::Index i = 0; i < n;) {
    if (d[i] < threshold) {
      ++i;
      continue;
    }
    const Eigen::Index crossing = i;
    double peak = 0.0;
    while (i < n && d[i] >= threshold) peak = std::max(peak, d[i++]);
    if (last_crossing >= 0 && crossing - last_crossing < bounce) continue;  // a bounce
    last_crossing = crossing;
    // The impact as tap_frf defines it: back from the crossing to impact_fraction x peak.
    Eigen::Index impact = crossing;
    while (impact > 0 && d[impact - 1] >= o.impact_fraction * peak) --impact;
    if (impact - pre < 0) {
      throw InputError(
          printf_text("hits: auto: the hit at t = %.6g s is only %.6g s after the record "
                      "start: needs auto_pretrigger_s = %g s before it",
                      static_cast<double>(impact) / fs_hz, static_cast<double>(impact) / fs_hz,
                      o.auto_pretrigger_s));
    }
    impacts.push_back(impact);
  }
  Eigen::Index length = std::min(n, samples(o.auto_max_window_s, fs_hz));
  for (size_t i = 0; i < impacts.size(); ++i) {
    const Eigen::Index next = i + 1 < impacts.size() ? impacts[i + 1] - pre : n;
    length = std::min(length, next - (impacts[i] - pre));
  }
  if (length <= pre) {
    throw InputError(
        printf_text("hits: auto: windows of %.6g s (the shortest spacing of the hits) end "
                    "before their impacts %g s after the window start (auto_pretrigger_s)",
                    static_cast<double>(length) / fs_hz, o.auto_pretrigger_s));
  }
  std::vector<TapWindow> windows;
  for (const Eigen::Index impact : impacts)
    windows.push_back({impact - pre, impact - pre + length});
  return windows;
}

TapFrf tap_frf(const Eigen::Ref<const Eigen::VectorXd>& hammer_n,
               const Eigen::Ref<const Eigen::VectorXd>& response_n, double fs_hz,
               const std::vector<TapWindow>& windows, const TapOptions& o) {
  check_rate(fs_hz);
  check_tap_options(o);
  const Eigen::Index n = hammer_n.size();
  if (response_n.size() != n) {
    throw InputError("sifs-tap: the hammer has " + std::to_string(n) + " samples, the response " +
                     std::to_string(response_n.size()) + ": must be equal");
  }
  if (windows.empty()) throw InputError("hits: the list of windows is empty");
  const Eigen::Index length = windows.front().end - windows.front().begin;
  const Eigen::Index min_pre = samples(o.min_pre_impact_s, fs_hz);
  const Eigen::Index guard = samples(o.pre_impact_guard_s, fs_hz);
  for (size_t i = 0; i < windows.size(); ++i) {
    const TapWindow& w = windows[i];
    const std::string name = "hits[" + std::to_string(i) + "]";
    if (w.begin < 0 || w.end > n || w.end <= w.begin) {
      throw InputError(
          name + printf_text(" = [%.6g, %.6g] s: must satisfy 0 <= start < end <= %.6g s "
                             "(the record length)",
                             static_cast<double>(w.begin) / fs_hz,
                             static_cast<double>(w.end) / fs_hz, static_cast<double>(n) / fs_hz));
    }
    if (w.end - w.begin != length) {
      throw InputError(name + " has " + std::to_string(w.end - w.begin) + " samples, hits[0] " +
                       std::to_string(length) + ": all windows must have one length");
    }
    if (length <= min_pre) {
      throw InputError(name +
                       printf_text(" lasts %.6g s: must be longer than min_pre_impact_s = %g s",
                                   static_cast<double>(length) / fs_hz, o.min_pre_impact_s));
    }
    if (!hammer_n.segment(w.begin, length).allFinite() ||
        !response_n.segment(w.begin, length).allFinite()) {
      throw InputError(name + ": the window holds non-finite samples");
    }
  }

  TapFrf frf;
  signal::RealFft fft(length);
  const Eigen::Index bins = length / 2;  // k = 1 .. L/2
  Eigen::VectorXd s_aa = Eigen::VectorXd::Zero(bins);
  Eigen::VectorXd s_mm = Eigen::VectorXd::Zero(bins);
  Eigen::VectorXcd s_am = Eigen::VectorXcd::Zero(bins);
  Eigen::VectorXd a_rec(length), m_rec(length);
  Eigen::VectorXcd a_spec(fft.bins()), m_spec(fft.bins());
  double pre_sum_sq = 0.0;
  Eigen::Index pre_count = 0;
  for (size_t i = 0; i < windows.size(); ++i) {
    const std::string name = "hits[" + std::to_string(i) + "]";
    const auto hammer = hammer_n.segment(windows[i].begin, length);
    const auto response = response_n.segment(windows[i].begin, length);
    // A window of noise has no impact: its largest excursion from the median must stand out
    // of the median-absolute-deviation noise (blind to the pulse, a tiny part of the window).
    const double hammer_median = median(hammer);
    const double excursion = (hammer.array() - hammer_median).abs().maxCoeff();
    const double hammer_noise = kMadToStd * median((hammer.array() - hammer_median).abs().matrix());
    if (!(excursion > kImpactNoiseMultiple * hammer_noise)) {
      throw InputError(name +
                       printf_text(": no impact: the largest |hammer - median| %.4g N is not "
                                   "above %g x the hammer noise std %.4g N",
                                   excursion, kImpactNoiseMultiple, hammer_noise));
    }
    // The impact against the mean of the part that is pre-impact whenever the window obeys
    // min_pre_impact_s, then again against the mean of the whole pre-impact part.
    double hammer_mean = hammer.head(std::max<Eigen::Index>(1, min_pre - guard)).mean();
    Impact im = find_impact(hammer, hammer_mean, o.impact_fraction);
    for (int pass = 0; pass < 2; ++pass) {
      if (im.sample < min_pre) {
        throw InputError(
            name +
            printf_text(": the impact at t = %.6g s is %.4g ms after the window start %.6g s: a "
                        "window must start >= min_pre_impact_s = %g ms before its impact",
                        static_cast<double>(windows[i].begin + im.sample) / fs_hz,
                        1e3 * static_cast<double>(im.sample) / fs_hz,
                        static_cast<double>(windows[i].begin) / fs_hz, 1e3 * o.min_pre_impact_s));
      }
      hammer_mean = hammer.head(im.sample - guard).mean();
      if (pass == 0) im = find_impact(hammer, hammer_mean, o.impact_fraction);
    }
    const Eigen::Index n_pre = im.sample - guard;
    const double response_mean = response.head(n_pre).mean();
    pre_sum_sq += (response.head(n_pre).array() - response_mean).square().sum();
    pre_count += n_pre;
    frf.impact.push_back(windows[i].begin + im.sample);

    a_rec = hammer.array() - hammer_mean;
    m_rec = response.array() - response_mean;
    fft.forward(a_rec, &a_spec);
    fft.forward(m_rec, &m_spec);
    for (Eigen::Index k = 0; k < bins; ++k) {
      const cd fa = a_spec[k + 1];
      const cd fm = m_spec[k + 1];
      s_aa[k] += std::norm(fa);
      s_mm[k] += std::norm(fm);
      s_am[k] += std::conj(fa) * fm;
    }
  }

  frf.hits = static_cast<int>(windows.size());
  frf.df_hz = fs_hz / static_cast<double>(length);
  frf.r_tap_n = std::sqrt(pre_sum_sq / static_cast<double>(pre_count));
  frf.f_hz.resize(bins);
  frf.h1.resize(bins);
  frf.coherence.resize(bins);
  for (Eigen::Index k = 0; k < bins; ++k) {
    frf.f_hz[k] = static_cast<double>(k + 1) * frf.df_hz;
    frf.h1[k] = s_aa[k] > 0.0 ? s_am[k] / s_aa[k] : cd(0.0, 0.0);
    const double denom = s_aa[k] * s_mm[k];
    frf.coherence[k] = denom > 0.0 ? std::norm(s_am[k]) / denom : 0.0;
  }
  if (frf.hits == 1) {
    frf.summary.warnings.push_back(
        "one hit only: coherence is 1 by construction and the confidence bounds are zero");
  }
  frf.summary.succeed();
  return frf;
}

std::complex<double> sensor_response(const std::vector<SensorMode>& modes, double f_hz) {
  const double w = kTwoPi * f_hz;
  cd g = 0.0;
  for (const SensorMode& m : modes) {
    const double wn = kTwoPi * m.fn_hz;
    g += m.alpha * wn * wn / cd(wn * wn - w * w, 2.0 * m.zeta * wn * w);  // 003 eq. 4-27
  }
  return g;
}

SensorModel fit_sensor_model(const TapFrf& frf, const SensorFitOptions& o) {
  check_fit_options(o);
  SensorModel fit;
  if (!frf.summary.ok()) {
    fit.summary.fail("no sensor model: the tap FRF failed (" + frf.summary.message + ")");
    return fit;
  }
  const Eigen::Index nb = frf.f_hz.size();
  if (frf.h1.size() != nb || frf.coherence.size() != nb) {
    throw InputError("sifs-tap: the FRF has " + std::to_string(nb) + " frequencies, " +
                     std::to_string(frf.h1.size()) + " H1 values and " +
                     std::to_string(frf.coherence.size()) + " coherences: must be equal");
  }
  const std::string in_band =
      printf_text(" in the band [%.6g, %.6g] Hz", o.band_lo_hz, o.band_hi_hz);
  std::vector<Eigen::Index> band_bins;
  for (Eigen::Index k = 0; k < nb; ++k) {
    if (frf.f_hz[k] >= o.band_lo_hz && frf.f_hz[k] <= o.band_hi_hz) band_bins.push_back(k);
  }
  const auto n_band = static_cast<Eigen::Index>(band_bins.size());
  const int n_params = 3 * o.modes - (o.unit_static_gain ? 1 : 0);
  if (n_band < std::max(3, n_params)) {
    fit.summary.fail(printf_text("%g bins lie", static_cast<double>(n_band)) + in_band +
                     printf_text(": too few for %g parameters", n_params));
    return fit;
  }
  Eigen::VectorXd f(n_band), w(n_band), weight(n_band), coh(n_band);
  Eigen::VectorXcd h(n_band);
  for (Eigen::Index b = 0; b < n_band; ++b) {
    const Eigen::Index k = band_bins[static_cast<size_t>(b)];
    f[b] = frf.f_hz[k];
    w[b] = kTwoPi * f[b];
    h[b] = frf.h1[k];
    coh[b] = std::clamp(frf.coherence[k], 0.0, 1.0);
    weight[b] = o.coherence_weights ? std::sqrt(coh[b]) : 1.0;
  }
  const double scale = h.cwiseAbs().maxCoeff();
  if (!(scale > 0.0) || !(weight.maxCoeff() > 0.0)) {
    fit.summary.fail("H1 (or its coherence) is zero throughout" + in_band);
    return fit;
  }

  // Start: the `modes` highest peaks of |H1| in the band, half-power damping, alpha from
  // the peak height |G(wn)| = alpha / (2 zeta), phase -90 deg for alpha > 0 (003 eq. 4-27).
  frf::PeakOptions peak_options;
  peak_options.min_prominence_db = kMinProminenceDb;
  peak_options.min_coherence = kPeakMinCoherence;
  std::vector<frf::FrfPeak> peaks = frf::find_frf_peaks(f, h, coh, peak_options);
  std::sort(peaks.begin(), peaks.end(),
            [](const frf::FrfPeak& a, const frf::FrfPeak& b) { return a.magnitude > b.magnitude; });
  if (static_cast<int>(peaks.size()) < o.modes) {
    std::string found;
    for (const frf::FrfPeak& p : peaks)
      found += (found.empty() ? "" : ", ") + printf_text("%.6g", p.f_hz);
    fit.summary.fail("modes = " + std::to_string(o.modes) + " but only " +
                     std::to_string(peaks.size()) +
                     printf_text(" resonance peaks (prominence >= %g dB, coherence >= %g) lie",
                                 kMinProminenceDb, kPeakMinCoherence) +
                     in_band + (found.empty() ? "" : " (at " + found + " Hz)") +
                     ": no start for mode " + std::to_string(peaks.size() + 1));
    return fit;
  }
  peaks.resize(static_cast<size_t>(o.modes));
  std::sort(peaks.begin(), peaks.end(),
            [](const frf::FrfPeak& a, const frf::FrfPeak& b) { return a.f_hz < b.f_hz; });
  SensorModelParams model;
  std::vector<double> alpha0;
  const Eigen::VectorXd mag = h.cwiseAbs();
  for (const frf::FrfPeak& p : peaks) {
    const double level = p.magnitude / std::sqrt(2.0);
    const double left = half_power_side(mag, f, p.bin, -1, level);
    const double right = half_power_side(mag, f, p.bin, +1, level);
    if (!(left > 0.0 || right > 0.0)) {
      fit.summary.fail(
          printf_text("no start for the mode at %.6g Hz: |H1| reaches its half-power level "
                      "on neither side within the band before rising above the peak, so "
                      "half-power damping is undefined (fit fewer modes or widen the band)",
                      p.f_hz));
      return fit;
    }
    // One side only (a neighbour or the band edge hides the other): twice that side. Floored
    // at half a bin: a narrower peak is not resolved.
    const double bw = std::max(
        left > 0.0 && right > 0.0 ? left + right : 2.0 * std::max(left, right), 0.5 * frf.df_hz);
    const double zeta = std::clamp(bw / (2.0 * p.f_hz), 2.0 * kZetaMin, 0.5 * o.max_zeta);
    model.wn0.push_back(kTwoPi * p.f_hz);
    model.zeta0.push_back(zeta);
    alpha0.push_back((p.value.imag() <= 0.0 ? 1.0 : -1.0) * 2.0 * zeta * p.magnitude);
  }
  // Under sum alpha = 1 the largest start alpha is the one eliminated: 1 - the others keeps it
  // well away from zero.
  if (o.unit_static_gain) {
    model.eliminated =
        static_cast<int>(std::max_element(alpha0.begin(), alpha0.end()) - alpha0.begin());
  }
  std::vector<double> theta(static_cast<size_t>(model.parameters()), 0.0);
  for (int i = 0; i < o.modes; ++i) {
    if (i != model.eliminated)
      theta[static_cast<size_t>(model.alpha_index(i))] = alpha0[static_cast<size_t>(i)];
  }

  ceres::Problem problem;
  problem.AddResidualBlock(new SensorCost(model, w, h, weight, scale), nullptr, theta.data());
  const double w_lo = kTwoPi * f[0];
  const double w_hi = kTwoPi * f[n_band - 1];
  for (int i = 0; i < o.modes; ++i) {
    const auto s = static_cast<size_t>(i);
    problem.SetParameterLowerBound(theta.data(), 2 * i, std::log(w_lo / model.wn0[s]));
    problem.SetParameterUpperBound(theta.data(), 2 * i, std::log(w_hi / model.wn0[s]));
    problem.SetParameterLowerBound(theta.data(), 2 * i + 1, std::log(kZetaMin / model.zeta0[s]));
    problem.SetParameterUpperBound(theta.data(), 2 * i + 1, std::log(o.max_zeta / model.zeta0[s]));
  }
  const ceres::Solver::Options options = dense_lm_options(kMaxIterations, 1e-12, 1e-12, 1e-14);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  fit.iterations = lm_iterations(summary);
  if (summary.termination_type != ceres::CONVERGENCE) {
    fit.summary.fail(printf_text("the fit of %g modes", o.modes) + in_band +
                     printf_text(" did not converge in %g iterations: ", kMaxIterations) +
                     summary.message);
    return fit;
  }

  fit.modes = model.to_modes(theta.data());
  std::sort(fit.modes.begin(), fit.modes.end(),
            [](const SensorMode& a, const SensorMode& b) { return a.fn_hz < b.fn_hz; });
  fit.static_gain = 0.0;
  for (const SensorMode& m : fit.modes) fit.static_gain += m.alpha;
  double err2 = 0.0;
  for (Eigen::Index b = 0; b < n_band; ++b)
    err2 += std::norm(sensor_response(fit.modes, f[b]) - h[b]);
  fit.fit_nrmse_pct = 100.0 * std::sqrt(err2) / h.norm();

  std::string details = printf_text("%g modes fitted", o.modes) + in_band + ":";
  for (const SensorMode& m : fit.modes) {
    details += printf_text("\n  fn = %.6g Hz, zeta = %.4g, alpha = %.4g", m.fn_hz, m.zeta, m.alpha);
    const double wn = kTwoPi * m.fn_hz;
    if (wn <= w_lo * (1.0 + kAtBound) || wn >= w_hi * (1.0 - kAtBound) ||
        m.zeta <= kZetaMin * (1.0 + kAtBound) || m.zeta >= o.max_zeta * (1.0 - kAtBound)) {
      fit.summary.warnings.push_back(
          printf_text("mode at %.6g Hz (zeta %.4g) ended on a bound of its frequency (the band) or "
                      "damping [%g, %g]: treat it with suspicion",
                      m.fn_hz, m.zeta, kZetaMin, o.max_zeta));
    }
    if (m.alpha < 0.0) {
      fit.summary.warnings.push_back(
          printf_text("mode at %.6g Hz has a negative modal gain alpha = %.4g", m.fn_hz, m.alpha));
    }
  }
  if (!o.unit_static_gain && std::abs(fit.static_gain - 1.0) > kStaticGainTolerance) {
    fit.summary.warnings.push_back(
        printf_text("static gain sum alpha = %.4g differs from 1 by more than %g: the sensor is "
                    "statically calibrated, so the calibration or the fit is off (003 sec. 4.2)",
                    fit.static_gain, kStaticGainTolerance));
  }
  if (fit.fit_nrmse_pct > kPoorFitPct) {
    fit.summary.warnings.push_back(
        printf_text("poor fit: ||G - H1|| / ||H1|| = %.1f %% over the band (above %g %%)",
                    fit.fit_nrmse_pct, kPoorFitPct));
  }
  fit.summary.succeed();
  fit.summary.details = details;
  return fit;
}

ScaledModal realize_scaled_modal(const std::vector<SensorMode>& modes) {
  if (modes.empty()) throw InputError("sensor model: no modes to realize");
  const auto n = static_cast<Eigen::Index>(2 * modes.size());
  ScaledModal r;
  r.A = Eigen::MatrixXd::Zero(n, n);
  r.B = Eigen::VectorXd::Zero(n);
  r.C = Eigen::RowVectorXd::Zero(n);
  for (size_t i = 0; i < modes.size(); ++i) {
    const SensorMode& m = modes[i];
    if (!(std::isfinite(m.fn_hz) && m.fn_hz > 0.0 && std::isfinite(m.zeta) && m.zeta >= 0.0 &&
          std::isfinite(m.alpha))) {
      throw InputError(
          "sensor model mode " + std::to_string(i + 1) +
          printf_text(" (fn = %g Hz, zeta = %g, alpha = %g): needs fn > 0, zeta >= 0, finite "
                      "alpha",
                      m.fn_hz, m.zeta, m.alpha));
    }
    // States (q_i, q_i' / w_i) of mode i (notes/003.md sec. 3).
    const double wn = kTwoPi * m.fn_hz;
    const auto j = static_cast<Eigen::Index>(2 * i);
    r.A(j, j + 1) = wn;
    r.A(j + 1, j) = -wn;
    r.A(j + 1, j + 1) = -2.0 * m.zeta * wn;
    r.B[j + 1] = wn;
    r.C[j] = m.alpha;
  }
  // 003 eq. 4-38 (the blocks are invertible for wn > 0).
  const auto inf_norm = [](const Eigen::MatrixXd& M) {
    return M.cwiseAbs().rowwise().sum().maxCoeff();
  };
  r.cond_A = inf_norm(r.A) * inf_norm(r.A.inverse());
  return r;
}

std::complex<double> realization_response(const ScaledModal& r, double f_hz) {
  const Eigen::Index n = r.A.rows();
  const Eigen::MatrixXcd M =
      cd(0.0, kTwoPi * f_hz) * Eigen::MatrixXcd::Identity(n, n) - r.A.cast<cd>();
  const Eigen::VectorXcd x = M.partialPivLu().solve(r.B.cast<cd>());
  return (r.C.cast<cd>() * x)(0);
}

double discrete_observability_rcond(const Eigen::MatrixXd& A, const Eigen::RowVectorXd& C,
                                    double T_s) {
  const Eigen::Index n = A.rows();
  if (n < 1 || A.cols() != n || C.size() != n) {
    throw InputError("observability: A is " + std::to_string(A.rows()) + " x " +
                     std::to_string(A.cols()) + " and C has " + std::to_string(C.size()) +
                     " columns: A must be square with C's width");
  }
  if (!(std::isfinite(T_s) && T_s > 0.0)) {
    throw InputError("observability: T = " + printf_text("%g", T_s) + " s: must be > 0");
  }
  const Eigen::MatrixXd F = (A * T_s).exp();
  Eigen::MatrixXd O(n, n);  // 003 eq. 4-40 on the discrete pair: rows C F^k
  Eigen::RowVectorXd row = C;
  for (Eigen::Index k = 0; k < n; ++k) {
    O.row(k) = row;
    row = row * F;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(O);
  const Eigen::VectorXd& s = svd.singularValues();
  return s[0] > 0.0 ? s[n - 1] / s[0] : 0.0;  // 003 eq. 4-42 in the 2-norm
}

FrfConfidence frf_confidence(const TapFrf& frf) {
  if (!frf.summary.ok() || frf.hits < 1) {
    throw InputError("frf_confidence: the tap FRF did not succeed (" + frf.summary.message + ")");
  }
  const Eigen::Index nb = frf.h1.size();
  FrfConfidence c;
  c.magnitude_sigma.resize(nb);
  c.phase_sigma_rad.resize(nb);
  const double root_2nd = std::sqrt(2.0 * frf.hits);
  for (Eigen::Index k = 0; k < nb; ++k) {
    // 003 eqs 6-3 and 6-4 (the latter without the angle factor, notes/003.md decision 22).
    const double g2 = std::clamp(frf.coherence[k], 0.0, 1.0);
    const double e = g2 > 0.0 ? std::sqrt(1.0 - g2) / (std::sqrt(g2) * root_2nd)
                              : std::numeric_limits<double>::infinity();
    c.magnitude_sigma[k] = e * std::abs(frf.h1[k]);
    c.phase_sigma_rad[k] = e;
  }
  return c;
}

}  // namespace sifs
}  // namespace chatterlab
