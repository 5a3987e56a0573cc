// The SIFS plant model (003 ch. 4): tap FRF, fit of 003 eq. 4-27, scaled modal realization,
// discrete observability and the FRF confidence bounds of 003 eqs 6-3/6-4, on the synthetic
// plant of notes/003.md section 7 with synthetic taps whose truth is known.
#include "analysis/sifs/sensor_model.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "analysis/common/constants.h"
#include "analysis/frf/modal_response.h"
#include "analysis/frf/mode.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/record_property.h"

namespace chatterlab {
namespace sifs {
namespace {

using testing::expect_input_error;
using ::testing::HasSubstr;
using testing::record_and_print;
using ::testing::StartsWith;

// notes/003.md section 7: f (Hz), zeta, alpha (the thesis's alpha^-1); G(0) = 1.
const std::vector<SensorMode> kPlant = {
    {420.0, 0.03, 0.55}, {980.0, 0.04, 0.40}, {2400.0, 0.05, 0.05}};

constexpr double kFs = 12800.0;     // format section 6 example and 003 cutting rate
constexpr double kWindowS = 0.2;    // hit windows
constexpr double kPreS = 0.040;     // window start before the impact
constexpr double kSpacingS = 0.25;  // between taps: the slowest mode decays by e^-20 in it

struct Taps {
  Eigen::VectorXd hammer;
  Eigen::VectorXd response;  // noiseless
  std::vector<TapWindow> windows;
  std::vector<Eigen::Index> pulse_start;  // first sample at or after each pulse start
};

// n_hits half-sine pulses, peaks 100..300 N and widths 0.30..0.50 ms in turn (different
// widths put their spectral nulls 3/(2 width) at different frequencies), the exact response
// of the plant (frf/modal_response.h: simulated 8x faster with exact first-order hold, matched
// anti-alias FIR on both channels, decimated). A mode alpha wn^2 / (s^2 + 2 zeta wn s + wn^2)
// is a receptance with m = 1 / (alpha wn^2).
Taps make_taps(int n_hits, const std::vector<double>& spacing_s = {}) {
  std::vector<frf::Mode> modes;
  for (const SensorMode& m : kPlant) {
    const double wn = kTwoPi * m.fn_hz;
    modes.push_back(frf::mode_from_modal(m.fn_hz, m.zeta, 1.0 / (m.alpha * wn * wn)));
  }
  const double peaks[] = {200.0, 120.0, 300.0, 160.0, 250.0, 100.0, 220.0, 280.0};
  const double widths[] = {0.5e-3, 0.4e-3, 0.3e-3, 0.45e-3, 0.35e-3};
  std::vector<frf::HammerPulse> pulses;
  Taps t;
  double at = kPreS;
  for (int i = 0; i < n_hits; ++i) {
    pulses.push_back({at, peaks[i % 8], widths[i % 5]});
    t.pulse_start.push_back(static_cast<Eigen::Index>(std::ceil(at * kFs)));
    const auto begin = static_cast<Eigen::Index>(std::llround((at - kPreS) * kFs));
    t.windows.push_back({begin, begin + static_cast<Eigen::Index>(std::llround(kWindowS * kFs))});
    at += spacing_s.empty() ? kSpacingS : spacing_s[static_cast<size_t>(i) % spacing_s.size()];
  }
  const auto n = static_cast<Eigen::Index>(std::llround((at - kPreS + kSpacingS) * kFs));
  const frf::TapRecord rec =
      frf::synthesize_tap_record(modes, pulses, kFs, n, frf::ResponseKind::kDisplacement);
  t.hammer = rec.force_n;
  t.response = rec.response;
  return t;
}

Eigen::VectorXd white_noise(Eigen::Index n, double std_n, std::mt19937_64* rng) {
  std::normal_distribution<double> normal(0.0, std_n);
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) v[i] = normal(*rng);
  return v;
}

double rel_err(double estimate, double truth) { return std::abs(estimate - truth) / truth; }

// ---------------------------------------------------------------------------------------------
// Model and realization

TEST(SensorResponse, ReproducesTheNotesFigures) {
  // notes/003.md section 7, printed to 3 decimals: G(0) = 1; |G| at the TPF of the 7 test
  // speeds (Z = 4); the first antiresonance near 572 Hz with |G| = 0.107.
  constexpr double kPrinted = 0.0005;
  EXPECT_NEAR(std::abs(sensor_response(kPlant, 0.0) - 1.0), 0.0, 1e-15);
  const double rpm[] = {1000, 4500, 6000, 8400, 9000, 11600, 17600};
  const double g_tpf[] = {1.016, 1.610, 5.509, 0.126, 0.190, 0.877, 0.917};
  for (int i = 0; i < 7; ++i) {
    EXPECT_NEAR(std::abs(sensor_response(kPlant, 4.0 * rpm[i] / 60.0)), g_tpf[i], kPrinted)
        << rpm[i] << " rpm";
  }
  double f_min = 0.0, g_min = 1e300;
  for (double f = 450.0; f < 900.0; f += 0.01) {
    const double g = std::abs(sensor_response(kPlant, f));
    if (g < g_min) g_min = g, f_min = f;
  }
  // The notes' "|G| = 0.107 at about 572 Hz" is |G(572 Hz)|; the minimum lies 1.4 Hz lower.
  EXPECT_NEAR(std::abs(sensor_response(kPlant, 572.0)), 0.107, kPrinted);
  EXPECT_NEAR(f_min, 572.0, 2.0);
  EXPECT_NEAR(g_min, 0.107, 2.0 * kPrinted);
}

TEST(ScaledModal, RealizationEqualsModelFrom1To5000Hz) {
  const ScaledModal r = realize_scaled_modal(kPlant);
  ASSERT_EQ(r.A.rows(), 6);
  double worst = 0.0;
  for (int f = 1; f <= 5000; ++f) {
    const std::complex<double> g = sensor_response(kPlant, f);
    worst = std::max(worst, std::abs(realization_response(r, f) - g) / std::abs(g));
  }
  record_and_print("realization_max_rel_error", worst);
  EXPECT_LT(worst, 1e-9);  // notes/003.md sec. 7 test 1 (measured 3e-15 in the notes)
}

TEST(ScaledModal, ConditionNumberIsTheClosedForm) {
  // Blocks [[0, w], [-w, -2 zeta w]] have row sums w (1 + 2 zeta) and inverses
  // [[-2 zeta / w, -1 / w], [1 / w, 0]] with row sums (1 + 2 zeta) / w, so
  // kappa_inf = 2400 (1.1) x 1.06 / 420 = 6.663 (notes/003.md: "6.7").
  const double closed_form = 2400.0 * 1.1 * 1.06 / 420.0;
  const ScaledModal r = realize_scaled_modal(kPlant);
  record_and_print("cond_A", r.cond_A);
  EXPECT_NEAR(r.cond_A, closed_form, 1e-12 * closed_form);
  EXPECT_NEAR(r.cond_A, 6.7, 0.05);
  EXPECT_GT(1.0 / r.cond_A, 2.220446e-16);  // 003 eq. 4-37
}

TEST(ScaledModal, BadModeIsRejected) {
  expect_input_error([] { realize_scaled_modal({}); }, "sensor model: no modes to realize");
  expect_input_error(
      [] {
        realize_scaled_modal({{420.0, 0.03, 0.55}, {0.0, 0.04, 0.4}});
      },
      "sensor model mode 2 (fn = 0 Hz, zeta = 0.04, alpha = 0.4): needs fn > 0, "
      "zeta >= 0, finite alpha");
}

TEST(DiscreteObservability, FullRankAtTheFilterStep) {
  const ScaledModal r = realize_scaled_modal(kPlant);
  const double rcond = discrete_observability_rcond(r.A, r.C, 1e-4);  // 003: Ts_filt = 1e-4 s
  record_and_print("observability_rcond_T1e-4", rcond);
  EXPECT_GT(rcond, 1e-12);
}

TEST(DiscreteObservability, TwoIdenticalModesAreNotObservable) {
  // Only the sum of the two identical modes' states reaches the output: rank 4 of 6, so
  // sigma_min is rounding noise against sigma_max = O(1).
  std::vector<SensorMode> twin = kPlant;
  twin.push_back(kPlant[1]);
  const ScaledModal r = realize_scaled_modal(twin);
  const double rcond = discrete_observability_rcond(r.A, r.C, 1e-4);
  record_and_print("observability_rcond_twin", rcond);
  EXPECT_LT(rcond, 1e-13);
  expect_input_error([&] { discrete_observability_rcond(r.A, r.C, 0.0); },
                     "observability: T = 0 s: must be > 0");
}

// ---------------------------------------------------------------------------------------------
// Tap FRF and fit

// Response noise: a third of the thesis's R = 0.15 N (the RMS before the impact), so that the
// coherence stays near 1 where 100..300 N pulses of 0.3..0.5 ms put their energy (below 3 kHz).
constexpr double kTapNoiseN = 0.05;
constexpr int kHits = 8;

struct TapFit {
  TapFrf frf;
  SensorModel model;
};

TapFit tap_and_fit(const SensorFitOptions& options, std::uint64_t seed = 7) {
  const Taps t = make_taps(kHits);
  std::mt19937_64 rng(seed);
  const Eigen::VectorXd response = t.response + white_noise(t.response.size(), kTapNoiseN, &rng);
  TapFit f;
  f.frf = tap_frf(t.hammer, response, kFs, t.windows);
  f.model = fit_sensor_model(f.frf, options);
  return f;
}

SensorFitOptions band_options() {
  SensorFitOptions o;
  o.modes = 3;
  o.band_lo_hz = 100.0;
  o.band_hi_hz = 4000.0;  // format section 6 example
  return o;
}

TEST(TapFrf, MatchesThePlantWithUnitCoherenceAndNoiseRms) {
  const TapFit f = tap_and_fit(band_options());
  ASSERT_TRUE(f.frf.summary.ok()) << f.frf.summary.full_report();
  EXPECT_EQ(f.frf.hits, kHits);
  EXPECT_DOUBLE_EQ(f.frf.df_hz, 5.0);  // fs / L = 12800 / 2560
  ASSERT_EQ(f.frf.f_hz.size(), 1280);
  EXPECT_DOUBLE_EQ(f.frf.f_hz[0], 5.0);
  // R_tap against the injected noise: 8 x 499 pooled samples estimate an RMS to ~1 %.
  record_and_print("r_tap_rel_error", rel_err(f.frf.r_tap_n, kTapNoiseN));
  EXPECT_LT(rel_err(f.frf.r_tap_n, kTapNoiseN), 0.10);
  // H1 against G and coherence from 100 Hz to 3 kHz, where the pulses put their energy. At
  // the antiresonances (|G| = 0.046 at 1970 Hz) the noise is about 10 % of a single hit's
  // response spectrum, so there H1 scatters by a few %: its error is judged against the
  // random error of 003 eq. 6-3. The fine-rate hold and the FIR of the synthesis leave < 1e-3
  // (modal_response.h).
  const FrfConfidence c = frf_confidence(f.frf);
  std::vector<double> rel;
  double worst_sigmas = 0.0, coh_min = 1.0, coh_sum = 0.0;
  for (Eigen::Index k = 0; k < f.frf.f_hz.size(); ++k) {
    if (f.frf.f_hz[k] < 100.0 || f.frf.f_hz[k] > 3000.0) continue;
    const std::complex<double> g = sensor_response(kPlant, f.frf.f_hz[k]);
    rel.push_back(std::abs(f.frf.h1[k] - g) / std::abs(g));
    worst_sigmas = std::max(worst_sigmas, std::abs(f.frf.h1[k] - g) / c.magnitude_sigma[k]);
    coh_min = std::min(coh_min, f.frf.coherence[k]);
    coh_sum += f.frf.coherence[k];
  }
  std::nth_element(rel.begin(), rel.begin() + static_cast<long>(rel.size() / 2), rel.end());
  const double rel_median = rel[rel.size() / 2];
  const double rel_max = *std::max_element(rel.begin(), rel.end());
  record_and_print("h1_median_rel_error_100_3000", rel_median);
  record_and_print("h1_max_rel_error_100_3000", rel_max);
  record_and_print("h1_max_error_in_sigmas_100_3000", worst_sigmas);
  record_and_print("coherence_min_100_3000", coh_min);
  record_and_print("coherence_mean_100_3000", coh_sum / static_cast<double>(rel.size()));
  EXPECT_LT(rel_median, 0.01);
  // |H1 - G| is complex with about sigma per component: over 580 bins 5 sigma is exceeded with
  // probability ~2e-3 (Rayleigh tail exp(-25/2) x 580).
  EXPECT_LT(worst_sigmas, 5.0);
  EXPECT_GT(coh_sum / static_cast<double>(rel.size()), 0.99);
  EXPECT_GT(coh_min, 0.95);
  // Impacts: the first sample at or after the pulse start (0.1 of the peak is reached 0.03
  // widths in, under a sample).
  const Taps t = make_taps(kHits);
  for (int i = 0; i < kHits; ++i) {
    EXPECT_NEAR(static_cast<double>(f.frf.impact[static_cast<size_t>(i)]),
                static_cast<double>(t.pulse_start[static_cast<size_t>(i)]), 1.0);
  }
}

// Acceptance of the fit on the plant (brief of this unit): fn 0.5 %, zeta 10 %, alpha 5 %.
constexpr double kFnTol = 0.005;
constexpr double kZetaTol = 0.10;
constexpr double kAlphaTol = 0.05;

void expect_plant(const SensorModel& m) {
  ASSERT_TRUE(m.summary.ok()) << m.summary.full_report();
  ASSERT_EQ(m.modes.size(), kPlant.size());
  for (size_t i = 0; i < kPlant.size(); ++i) {
    const std::string at = std::to_string(static_cast<int>(kPlant[i].fn_hz));
    record_and_print("fn_rel_error_" + at, rel_err(m.modes[i].fn_hz, kPlant[i].fn_hz));
    record_and_print("zeta_rel_error_" + at, rel_err(m.modes[i].zeta, kPlant[i].zeta));
    record_and_print("alpha_rel_error_" + at, rel_err(m.modes[i].alpha, kPlant[i].alpha));
    EXPECT_LT(rel_err(m.modes[i].fn_hz, kPlant[i].fn_hz), kFnTol) << at;
    EXPECT_LT(rel_err(m.modes[i].zeta, kPlant[i].zeta), kZetaTol) << at;
    EXPECT_LT(rel_err(m.modes[i].alpha, kPlant[i].alpha), kAlphaTol) << at;
  }
  record_and_print("fit_nrmse_pct", m.fit_nrmse_pct);
  record_and_print("iterations", m.iterations);
}

TEST(FitSensorModel, RecoversThePlantWithUnitStaticGain) {
  const TapFit f = tap_and_fit(band_options());
  expect_plant(f.model);
  EXPECT_NEAR(f.model.static_gain, 1.0, 1e-14);  // enforced: 1 - the others, rounding only
  // The fit error is the noise and the FRF's own error: H1 is within 5 % of G above.
  EXPECT_LT(f.model.fit_nrmse_pct, 2.0);
  EXPECT_TRUE(f.model.summary.warnings.empty()) << f.model.summary.full_report();
}

TEST(FitSensorModel, FreeStaticGainComesOutNearOne) {
  SensorFitOptions o = band_options();
  o.unit_static_gain = false;
  o.coherence_weights = false;
  const TapFit f = tap_and_fit(o, 11);
  expect_plant(f.model);
  record_and_print("free_static_gain_error", std::abs(f.model.static_gain - 1.0));
  EXPECT_NEAR(f.model.static_gain, 1.0, 0.02);  // sum of three alphas within 5 % each, measured
}

TEST(FitSensorModel, ThesisNoiseLevelOverTenSeeds) {
  // 003's R_tap = 0.15 N (three times kTapNoiseN): the acceptance tolerances hold for every
  // seed (measured worst over 30 seeds: fn 3.5e-4, zeta 7e-3, alpha 3.7e-3 relative).
  const Taps t = make_taps(kHits);
  for (std::uint64_t seed = 100; seed < 110; ++seed) {
    std::mt19937_64 rng(seed);
    const Eigen::VectorXd response = t.response + white_noise(t.response.size(), 0.15, &rng);
    const SensorModel m =
        fit_sensor_model(tap_frf(t.hammer, response, kFs, t.windows), band_options());
    ASSERT_TRUE(m.summary.ok()) << "seed " << seed << ": " << m.summary.full_report();
    for (size_t i = 0; i < kPlant.size(); ++i) {
      EXPECT_LT(rel_err(m.modes[i].fn_hz, kPlant[i].fn_hz), kFnTol) << seed;
      EXPECT_LT(rel_err(m.modes[i].zeta, kPlant[i].zeta), kZetaTol) << seed;
      EXPECT_LT(rel_err(m.modes[i].alpha, kPlant[i].alpha), kAlphaTol) << seed;
    }
  }
}

TEST(FitSensorModel, FailuresSayWhy) {
  SensorFitOptions o = band_options();
  o.modes = 4;
  const TapFit f = tap_and_fit(o);
  EXPECT_TRUE(f.model.summary.failed());
  EXPECT_THAT(f.model.summary.message,
              StartsWith("modes = 4 but only 3 resonance peaks (prominence >= 6 dB, coherence >= "
                         "0.5) lie in the band [100, 4000] Hz (at 4"));
  EXPECT_THAT(f.model.summary.message, HasSubstr(" Hz): no start for mode 4"));
  EXPECT_TRUE(f.model.modes.empty());

  o = band_options();
  o.band_lo_hz = 5000.0;
  o.band_hi_hz = 5010.0;
  const SensorModel narrow = fit_sensor_model(f.frf, o);
  EXPECT_EQ(narrow.summary.message,
            "3 bins lie in the band [5000, 5010] Hz: too few for 8 parameters");

  const SensorModel not_run = fit_sensor_model(TapFrf{}, band_options());
  EXPECT_EQ(not_run.summary.message, "no sensor model: the tap FRF failed (not run)");

  o = band_options();
  o.band_hi_hz = 0.0;
  expect_input_error([&] { fit_sensor_model(f.frf, o); },
                     "sifs-tap band_hz = [100, 0]: must satisfy 0 <= lo < hi");
  o = band_options();
  o.modes = 0;
  expect_input_error([&] { fit_sensor_model(f.frf, o); }, "sifs-tap modes = 0: must be >= 1");
}

// ---------------------------------------------------------------------------------------------
// Confidence bounds (003 eqs 6-3, 6-4 corrected; notes/003.md sec. 7 test 8)

TEST(FrfConfidence, MatchesMonteCarloScatterAtModerateCoherence) {
  // n_d = 10 impacts with response noise 1 N, so the antiresonances and the top of the band
  // have coherence 0.5..0.9; 200 noise realisations on the same impacts.
  constexpr int kRuns = 200;
  constexpr int kNd = 10;
  constexpr double kNoiseN = 1.0;
  const Taps t = make_taps(kNd);
  std::mt19937_64 rng(2024);
  const Eigen::Index nb = static_cast<Eigen::Index>(std::llround(kWindowS * kFs)) / 2;
  Eigen::VectorXd mag_sum = Eigen::VectorXd::Zero(nb), mag_sq = Eigen::VectorXd::Zero(nb);
  Eigen::VectorXd ph_sum = Eigen::VectorXd::Zero(nb), ph_sq = Eigen::VectorXd::Zero(nb);
  Eigen::VectorXd sig_mag = Eigen::VectorXd::Zero(nb), sig_ph = Eigen::VectorXd::Zero(nb);
  Eigen::VectorXd coh = Eigen::VectorXd::Zero(nb);
  Eigen::VectorXd f_hz;
  for (int run = 0; run < kRuns; ++run) {
    const Eigen::VectorXd response = t.response + white_noise(t.response.size(), kNoiseN, &rng);
    const TapFrf frf = tap_frf(t.hammer, response, kFs, t.windows);
    const FrfConfidence c = frf_confidence(frf);
    f_hz = frf.f_hz;
    for (Eigen::Index k = 0; k < nb; ++k) {
      // Phase relative to the true G's, so no wrap at +-pi.
      const double m = std::abs(frf.h1[k]);
      const double p = std::arg(frf.h1[k] / sensor_response(kPlant, f_hz[k]));
      mag_sum[k] += m, mag_sq[k] += m * m, ph_sum[k] += p, ph_sq[k] += p * p;
      sig_mag[k] += c.magnitude_sigma[k], sig_ph[k] += c.phase_sigma_rad[k];
      coh[k] += frf.coherence[k];
    }
  }
  std::vector<double> ratio_mag, ratio_ph;
  for (Eigen::Index k = 0; k < nb; ++k) {
    const double g2 = coh[k] / kRuns;
    if (f_hz[k] < 100.0 || f_hz[k] > 5000.0 || g2 < 0.5 || g2 > 0.9) continue;
    const double sd_mag = std::sqrt((mag_sq[k] - mag_sum[k] * mag_sum[k] / kRuns) / (kRuns - 1));
    const double sd_ph = std::sqrt((ph_sq[k] - ph_sum[k] * ph_sum[k] / kRuns) / (kRuns - 1));
    ratio_mag.push_back(sd_mag / (sig_mag[k] / kRuns));
    ratio_ph.push_back(sd_ph / (sig_ph[k] / kRuns));
  }
  ASSERT_GE(ratio_mag.size(), 20u);
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  const auto [mag_lo, mag_hi] = std::minmax_element(ratio_mag.begin(), ratio_mag.end());
  const auto [ph_lo, ph_hi] = std::minmax_element(ratio_ph.begin(), ratio_ph.end());
  record_and_print("moderate_coherence_bins", static_cast<double>(ratio_mag.size()));
  record_and_print("mag_ratio_median", median(ratio_mag));
  record_and_print("mag_ratio_min", *mag_lo);
  record_and_print("mag_ratio_max", *mag_hi);
  record_and_print("phase_ratio_median", median(ratio_ph));
  record_and_print("phase_ratio_min", *ph_lo);
  record_and_print("phase_ratio_max", *ph_hi);
  // Empirical sigma / eq. 6-3 sigma: the median over the bins within 15 %; every bin within a
  // factor 1.5 (see the measured figures).
  EXPECT_NEAR(median(ratio_mag), 1.0, 0.15);
  EXPECT_NEAR(median(ratio_ph), 1.0, 0.15);
  EXPECT_GT(*mag_lo, 1.0 / 1.5);
  EXPECT_LT(*mag_hi, 1.5);
  EXPECT_GT(*ph_lo, 1.0 / 1.5);
  EXPECT_LT(*ph_hi, 1.5);
}

TEST(FrfConfidence, OneHitGivesZeroBoundsAndAFailedFrfThrows) {
  const Taps t = make_taps(1);
  std::mt19937_64 rng(5);
  const Eigen::VectorXd response = t.response + white_noise(t.response.size(), 0.5, &rng);
  const TapFrf frf = tap_frf(t.hammer, response, kFs, t.windows);
  EXPECT_EQ(frf.summary.warnings.size(), 1u);
  const FrfConfidence c = frf_confidence(frf);
  // Coherence 1 up to rounding: sigma / |H| = sqrt(1 - g2) / (|g| sqrt 2) is the square root of
  // rounding errors (~1e-8 relative).
  EXPECT_LT((c.magnitude_sigma.array() / frf.h1.array().abs()).maxCoeff(), 1e-6);
  EXPECT_LT(c.phase_sigma_rad.maxCoeff(), 1e-6);
  expect_input_error([] { frf_confidence(TapFrf{}); },
                     "frf_confidence: the tap FRF did not succeed (not run)");
}

// ---------------------------------------------------------------------------------------------
// Windows

TEST(AutoTapWindows, FindTheImpactsWithTheShortestSpacing) {
  // Spacings 0.25, 0.22, 0.30 s: windows 0.22 s long, each 30 ms before its impact. A bounce
  // 4 ms after the third hit (half its peak) stays with it.
  const std::vector<double> spacing = {0.25, 0.22, 0.30};
  Taps t = make_taps(4, spacing);
  const auto bounce = static_cast<Eigen::Index>(std::llround(0.004 * kFs));
  const Eigen::Index at = t.pulse_start[2] + bounce;
  for (Eigen::Index i = 0; i < 4; ++i) t.hammer[at + i] += 150.0 * std::sin(kPi * (i + 0.5) / 4.0);
  std::mt19937_64 rng(3);
  t.hammer += white_noise(t.hammer.size(), 0.05, &rng);
  const std::vector<TapWindow> w = auto_tap_windows(t.hammer, kFs);
  ASSERT_EQ(w.size(), 4u);
  const Eigen::Index pre = 384;  // 30 ms at 12.8 kHz
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(static_cast<double>(w[i].begin), static_cast<double>(t.pulse_start[i] - pre), 1.0);
    EXPECT_EQ(w[i].end - w[i].begin, w[0].end - w[0].begin);
  }
  EXPECT_NEAR(static_cast<double>(w[0].end - w[0].begin), 0.22 * kFs, 1.0);
  // The windows pass tap_frf's rules.
  const TapFrf frf = tap_frf(t.hammer, t.response, kFs, w);
  EXPECT_TRUE(frf.summary.ok());
}

TEST(AutoTapWindows, NoHitSaysWhy) {
  expect_input_error([] { auto_tap_windows(Eigen::VectorXd::Zero(1000), kFs); },
                     "hits: auto: the hammer shows no hit: the threshold 0.2 x the largest "
                     "|hammer - median| = 0 N is not above 10 x the hammer noise std 0 N");
  std::mt19937_64 rng(9);
  const Eigen::VectorXd noise = white_noise(5000, 1.0, &rng);
  try {
    auto_tap_windows(noise, kFs);
    ADD_FAILURE() << "no error for a hammer of noise";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), StartsWith("hits: auto: the hammer shows no hit: the threshold 0.2 x"));
  }
  const Taps t = make_taps(2);
  TapOptions o;
  o.auto_pretrigger_s = 0.05;  // the first hit is 40 ms into the record
  expect_input_error(
      [&] { auto_tap_windows(t.hammer, kFs, o); },
      "hits: auto: the hit at t = 0.0400781 s is only 0.0400781 s after the record start: "
      "needs auto_pretrigger_s = 0.05 s before it");
}

TEST(TapFrf, BadWindowsThrowWithTheirIndex) {
  const Taps t = make_taps(3);
  std::vector<TapWindow> w = t.windows;
  w[1].begin += 256;  // starts 20 ms later: 20 ms before the impact, allowed
  w[1].end += 256;
  EXPECT_TRUE(tap_frf(t.hammer, t.response, kFs, w).summary.ok());
  w[1].begin += 13;  // now 19 ms before it
  w[1].end += 13;
  try {
    tap_frf(t.hammer, t.response, kFs, w);
    ADD_FAILURE() << "no error for a window starting 19 ms before its impact";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), StartsWith("hits[1]: the impact at t = 0.290078 s is 19.06 ms after the "
                                     "window start 0.271016 s"));
    EXPECT_THAT(e.what(), HasSubstr("a window must start >= min_pre_impact_s = 20 ms before"));
  }
  w = t.windows;
  w[2].end -= 1;
  expect_input_error([&] { tap_frf(t.hammer, t.response, kFs, w); },
                     "hits[2] has 2559 samples, hits[0] 2560: all windows must have one length");
  w = t.windows;
  w[2].begin = t.hammer.size() - 100;
  w[2].end = w[2].begin + 2560;
  expect_input_error([&] { tap_frf(t.hammer, t.response, kFs, w); },
                     "hits[2] = [0.992188, 1.19219] s: must satisfy 0 <= start < end <= 1 s (the "
                     "record length)");
  // A window of hammer noise only (after the last tap).
  Eigen::VectorXd hammer = t.hammer;
  std::mt19937_64 rng(1);
  hammer += white_noise(hammer.size(), 0.01, &rng);
  w = t.windows;
  w[0] = {hammer.size() - 2560, hammer.size()};
  hammer.tail(2560) = white_noise(2560, 0.01, &rng);
  try {
    tap_frf(hammer, t.response, kFs, w);
    ADD_FAILURE() << "no error for a window without an impact";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), StartsWith("hits[0]: no impact: the largest |hammer - median| "));
    EXPECT_THAT(e.what(), HasSubstr("is not above 10 x the hammer noise std"));
  }
  expect_input_error([&] { tap_frf(t.hammer, t.response, kFs, {}); },
                     "hits: the list of windows is empty");
}

}  // namespace
}  // namespace sifs
}  // namespace chatterlab
