// Peak picking on analytic receptances with known resonances.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/frf/mode.h"
#include "analysis/frf/peaks.h"

namespace chatterlab {
namespace frf {
namespace {

struct Analytic {
  Eigen::VectorXd f_hz;
  Eigen::VectorXcd h;
  Eigen::VectorXd coherence;
};

Analytic sampled(const std::vector<Mode>& modes, double df, double f_max) {
  Analytic a;
  const auto n = static_cast<Eigen::Index>(f_max / df);
  a.f_hz = Eigen::VectorXd::LinSpaced(n, df, df * static_cast<double>(n));
  a.h = receptance(modes, a.f_hz);
  a.coherence = Eigen::VectorXd::Ones(n);
  return a;
}

TEST(FrfPeaks, FindsEachResonanceWithItsBandwidth) {
  // Two modes; 0.5 Hz bins resolve both half-power bands (112.7 and 100 Hz) finely, so the
  // interpolated peak is within 0.01 % of the maximum of |H| (found on a 0.01 Hz grid; the
  // neighbour's tail moves it from fn sqrt(1 - 2 zeta^2)) and the bandwidth within 2 % of
  // 2 zeta fn (its small-damping value).
  const Mode a = mode_from_mck(0.03134, 22.21, 9.840e5);
  const Mode b = mode_from_modal(2500.0, 0.02, 0.05);
  const Analytic s = sampled({a, b}, 0.5, 6000.0);
  const std::vector<FrfPeak> peaks = find_frf_peaks(s.f_hz, s.h, s.coherence);
  ASSERT_EQ(peaks.size(), 2u);
  const Analytic fine = sampled({a, b}, 0.01, 6000.0);
  int i = 0;
  for (const Mode& m : {a, b}) {
    const FrfPeak& p = peaks[static_cast<size_t>(i++)];
    Eigen::Index best = 0;
    const auto lo = static_cast<Eigen::Index>(0.9 * m.fn_hz / 0.01);
    const auto hi = static_cast<Eigen::Index>(1.1 * m.fn_hz / 0.01);
    fine.h.segment(lo, hi - lo).cwiseAbs().maxCoeff(&best);
    EXPECT_NEAR(p.f_hz / fine.f_hz[lo + best], 1.0, 1e-4);
    EXPECT_NEAR(p.half_power_bw_hz / (2.0 * m.zeta * m.fn_hz), 1.0, 0.02);
    EXPECT_GT(p.prominence_db, 10.0);
  }
  EXPECT_LT(peaks[0].value.imag(), 0.0);  // positive modal constant: phase near -90 deg
}

TEST(FrfPeaks, ParabolaRefinesAPeakBetweenBins) {
  // A lightly damped mode half-way between 1 Hz bins: the parabola moves the estimate from
  // the bin towards the true maximum by more than half the gap.
  const Mode m = mode_from_modal(900.5, 0.002, 1.0);
  const Analytic s = sampled({m}, 1.0, 2000.0);
  const std::vector<FrfPeak> peaks = find_frf_peaks(s.f_hz, s.h, s.coherence);
  ASSERT_EQ(peaks.size(), 1u);
  EXPECT_LT(std::abs(peaks[0].f_hz - 900.5), 0.25);
}

TEST(FrfPeaks, RulesOnCoherenceFrequencyAndProminence) {
  const Mode m = mode_from_mck(0.03134, 22.21, 9.840e5);
  Analytic s = sampled({m}, 1.0, 3000.0);
  PeakOptions o;
  // Poor coherence two bins away from the peak disqualifies it.
  Eigen::VectorXd poor = s.coherence;
  poor[888] = 0.5;
  EXPECT_TRUE(find_frf_peaks(s.f_hz, s.h, poor, o).empty());
  // Outside [f_min, f_max].
  o.f_min_hz = 1000.0;
  EXPECT_TRUE(find_frf_peaks(s.f_hz, s.h, s.coherence, o).empty());
  o.f_min_hz = 0.0;
  // Prominence: the peak over the higher of its two bases. The left base is |H| at the first
  // bin (about the static compliance 1/k), the right one |H| at 3 kHz (about 1/(9 k)),
  // so the left one sets it: 20 log10(|H|peak / |H(1 Hz)|), about 18 dB.
  const std::vector<FrfPeak> peaks = find_frf_peaks(s.f_hz, s.h, s.coherence, o);
  ASSERT_EQ(peaks.size(), 1u);
  EXPECT_NEAR(peaks[0].prominence_db, 20.0 * std::log10(peaks[0].magnitude / std::abs(s.h[0])),
              0.05);
  o.min_prominence_db = 30.0;
  EXPECT_TRUE(find_frf_peaks(s.f_hz, s.h, s.coherence, o).empty());
}

}  // namespace
}  // namespace frf
}  // namespace chatterlab
