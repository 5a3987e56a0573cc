// The tap-test chain on real measured data: five impact-hammer hits on a lightly damped
// structure (pyFRF showcase, shared/data/real-pyfrf-impact/README.md beside the project), 25.6 kHz,
// response in m/s^2. No modal parameters are published for it, so the checks are what a
// modal analyst would check: every hit accepted, a clean FRF, a fit that follows it, and
// fitted frequencies at the FRF's own peaks found by an independent method.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "analysis/frf/frf.h"
#include "analysis/frf/hits.h"
#include "analysis/frf/modal_fit.h"

namespace chatterlab {
namespace frf {
namespace {

constexpr double kFs = 25600.0;

struct TwoColumns {
  Eigen::VectorXd force;
  Eigen::VectorXd response;
};

// header "force,response", then one "f,x" row per sample.
TwoColumns read_csv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line) || line != "force,response") {
    throw std::runtime_error(path + ": missing or without the header force,response");
  }
  std::vector<double> f, x;
  while (std::getline(in, line)) {
    const auto comma = line.find(',');
    f.push_back(std::stod(line.substr(0, comma)));
    x.push_back(std::stod(line.substr(comma + 1)));
  }
  TwoColumns out;
  out.force = Eigen::Map<Eigen::VectorXd>(f.data(), static_cast<Eigen::Index>(f.size()));
  out.response = Eigen::Map<Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
  return out;
}

// Independent peak picking: local maxima of |H1| in [f_lo, f_hi], refined by a parabola
// through the log-magnitudes of the three bins (the library uses a parabola on the linear
// magnitude); the `count` largest, in increasing frequency.
std::vector<double> largest_peaks_hz(const Frf& frf, double f_lo, double f_hi, size_t count) {
  std::vector<std::pair<double, double>> peaks;  // (|H|, f)
  const Eigen::VectorXd db = 20.0 * frf.h1.cwiseAbs().array().log10();
  for (Eigen::Index k = 1; k + 1 < frf.f_hz.size(); ++k) {
    if (frf.f_hz[k] < f_lo || frf.f_hz[k] > f_hi) continue;
    if (!(db[k] > db[k - 1] && db[k] >= db[k + 1])) continue;
    const double delta = 0.5 * (db[k - 1] - db[k + 1]) / (db[k - 1] - 2.0 * db[k] + db[k + 1]);
    peaks.emplace_back(std::abs(frf.h1[k]), frf.f_hz[k] + delta * frf.df_hz);
  }
  std::sort(peaks.rbegin(), peaks.rend());
  std::vector<double> out;
  for (size_t i = 0; i < std::min(count, peaks.size()); ++i) out.push_back(peaks[i].second);
  std::sort(out.begin(), out.end());
  return out;
}

class RealTap : public ::testing::Test {
 protected:
  // A missing data file fails the test (data_ stays null), it never skips it.
  static void SetUpTestSuite() {
    try {
      data_ = new TwoColumns(
          read_csv(std::string(CHATTERLAB_SHARED_DATA) + "/real-pyfrf-impact/tap/x/hits.csv"));
    } catch (const std::exception& e) {
      load_error_ = e.what();
    }
  }
  static void TearDownTestSuite() {
    delete data_;
    data_ = nullptr;
  }
  static TwoColumns* data_;
  static std::string load_error_;
};
TwoColumns* RealTap::data_ = nullptr;
std::string RealTap::load_error_;

TEST_F(RealTap, FiveHitsOneFrfAndAFitThatFollowsIt) {
  ASSERT_NE(data_, nullptr) << load_error_;
  const TwoColumns& d = *data_;
  ASSERT_EQ(d.force.size(), 128000);  // five 1 s records at 25.6 kHz

  // Hits: one per 1 s record, 0.8 ms into it (the source's own pre-trigger); all accepted.
  const HitSet hits = detect_hits(d.force, d.response, kFs);
  ASSERT_TRUE(hits.summary.ok()) << hits.summary.message;
  ASSERT_EQ(hits.hits.size(), 5u);
  EXPECT_EQ(hits.accepted_count(), 5);
  for (size_t i = 0; i < 5; ++i) {
    const Hit& h = hits.hits[i];
    std::printf("hit %zu: t = %.5f s, peak %.1f N, record [%ld, %ld)\n", i + 1, h.time_s,
                h.peak_force_n, static_cast<long>(h.start), static_cast<long>(h.end));
    EXPECT_NEAR(h.time_s, static_cast<double>(i) + 0.0008, 0.0002);
    EXPECT_GT(h.peak_force_n, 60.0);
    EXPECT_LT(h.peak_force_n, 95.0);
  }

  // FRF: 1 Hz bins (records of ~1 s); the response decayed to ~0.5 % of its early RMS by
  // the record end, under the 1 % rule, so no exponential window.
  const Frf frf = compute_frf(d.force, d.response, hits, ResponseKind::kAcceleration);
  ASSERT_TRUE(frf.summary.ok()) << frf.summary.message;
  EXPECT_EQ(frf.hits_used, 5);
  EXPECT_NEAR(frf.df_hz, 1.0, 0.001);
  EXPECT_EQ(frf.exp_window_tau_s, 0.0);

  // The four largest receptance peaks between 100 Hz and 5 kHz, found independently.
  const std::vector<double> main_hz = largest_peaks_hz(frf, 100.0, 5000.0, 4);
  ASSERT_EQ(main_hz.size(), 4u);

  const ModalFit fit = fit_modes(frf);
  ASSERT_TRUE(fit.summary.ok()) << fit.summary.message;
  std::printf("band [%.1f, %.1f] Hz, %zu modes, NRMSE fit %.2f %%, %d iterations\n", fit.band_lo_hz,
              fit.band_hi_hz, fit.modes.size(), fit.fit_nrmse_pct, fit.iterations);
  std::printf("   fn (Hz)     zeta     m (kg)     c (kg/s)     k (N/m)   coherence\n");
  for (const Mode& m : fit.modes) {
    const auto bin = static_cast<Eigen::Index>(std::lround(m.fn_hz / frf.df_hz)) - 1;
    std::printf("%9.2f  %8.5f  %9.4g  %10.4g  %10.4g   %.4f\n", m.fn_hz, m.zeta, m.m_kg, m.c_kg_s,
                m.k_N_m, frf.coherence[bin]);
  }
  for (const std::string& w : fit.summary.warnings) std::printf("warning: %s\n", w.c_str());

  // Peak picking alone finds 9 modes and fits 89.1 % (004 eq. 3.2): closely spaced modes
  // that are shoulders of larger peaks, not peaks of |H|, were missing. With the modes found
  // in the fit's residual (906, 3665, 4091, 4167 Hz) the fit is 94.5 %, the same as an
  // independent least-squares fit of the same 13-mode model (94.53 %); 93 % leaves room for
  // numerical detail and fails with the 9 peak-picked modes.
  EXPECT_GT(fit.fit_nrmse_pct, 93.0);
  for (double shoulder_hz : {906.1, 3664.9}) {
    const auto it = std::find_if(fit.modes.begin(), fit.modes.end(), [&](const Mode& m) {
      return std::abs(m.fn_hz - shoulder_hz) < frf.df_hz;
    });
    ASSERT_NE(it, fit.modes.end()) << "no fitted mode within a bin of " << shoulder_hz << " Hz";
    EXPECT_TRUE(fit.quality[static_cast<size_t>(it - fit.modes.begin())].from_residual);
  }
  // No two fitted modes closer than 2 bins (what the bins can tell apart).
  for (size_t i = 0; i + 1 < fit.modes.size(); ++i) {
    EXPECT_GE(fit.modes[i + 1].fn_hz - fit.modes[i].fn_hz, 2.0 * frf.df_hz);
  }
  for (double f : main_hz) {
    EXPECT_GT(f, fit.band_lo_hz);
    EXPECT_LT(f, fit.band_hi_hz);
    const auto nearest =
        std::min_element(fit.modes.begin(), fit.modes.end(), [f](const Mode& a, const Mode& b) {
          return std::abs(a.fn_hz - f) < std::abs(b.fn_hz - f);
        });
    std::printf("peak %.2f Hz (coherence %.4f) -> fitted %.2f Hz, 2 zeta fn = %.2f Hz\n", f,
                frf.coherence[static_cast<Eigen::Index>(std::lround(f / frf.df_hz)) - 1],
                nearest->fn_hz, 2.0 * nearest->zeta * nearest->fn_hz);
    // Half a bin: the peak of a resolved resonance lies within it (|H| peaks at
    // fn sqrt(1 - 2 zeta^2), 0.003 Hz below fn here).
    EXPECT_NEAR(nearest->fn_hz, f, 0.5 * frf.df_hz);
    // Resolution-limited: the fitted half-power band spans fewer than 4 bins.
    EXPECT_LT(2.0 * nearest->zeta * nearest->fn_hz, 4.0 * frf.df_hz);
    EXPECT_GT(frf.coherence[static_cast<Eigen::Index>(std::lround(f / frf.df_hz)) - 1], 0.99);
  }
  const auto limited = std::count_if(fit.quality.begin(), fit.quality.end(),
                                     [](const ModeQuality& q) { return q.resolution_limited; });
  EXPECT_GE(limited, 4);
  const auto resolution_warnings = std::count_if(
      fit.summary.warnings.begin(), fit.summary.warnings.end(),
      [](const std::string& w) { return w.find("resolution-limited") != std::string::npos; });
  EXPECT_EQ(resolution_warnings, 1);  // one line for all of them
}

}  // namespace
}  // namespace frf
}  // namespace chatterlab
