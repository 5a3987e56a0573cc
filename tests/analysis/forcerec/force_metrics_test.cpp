// The format's force figures (analysis/forcerec/force_metrics.h, EXPERIMENT_FORMAT section 4):
// windows by their closed forms, harmonic amplitudes of a known sum of cosines, the lag of a
// shifted copy, NRMSE and fit of a known error.
#include "analysis/forcerec/force_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "analysis/common/constants.h"

namespace chatterlab::forcerec {
namespace {

constexpr double kFs = 10240.0;
constexpr double kFtp = 511.5;  // 15345 rpm, 2 teeth

TEST(ForceMetrics, EvaluationWindowSkipsTheStartAndTheEnd) {
  // N = 30720 (3 s): k from ceil(0.05 fs) = 512 to N - 0.01 fs = 30617.6 -> 30618 excluded.
  const IndexWindow w = evaluation_window(30720, kFs);
  EXPECT_EQ(w.begin, 512);
  EXPECT_EQ(w.end, 30618);
  // Shorter than 0.06 s: empty.
  EXPECT_EQ(evaluation_window(600, kFs).size(), 0);
}

TEST(ForceMetrics, HarmonicCountAndWindowFollowTheFormat) {
  EXPECT_EQ(harmonic_count(kFs, kFtp), 8);    // floor(0.4 x 10240 / 511.5) = 8
  EXPECT_EQ(harmonic_count(kFs, 200.0), 12);  // capped at 12
  EXPECT_EQ(harmonic_count(kFs, 0.0), 0);
  // Cut window [0.6, 2.95] s of a 3 s record: k0 = 6144, k1 = floor(min(2.95, 2.99) fs) = 30208,
  // P = floor(24064 x 511.5 / 10240) = 1202 periods, n = round(1202 x 10240 / 511.5) = 24063.
  const IndexWindow w = harmonic_window(30720, kFs, kFtp, 0.6, 2.95);
  EXPECT_EQ(w.begin, 6144);
  EXPECT_EQ(w.size(), 24063);
  EXPECT_EQ(harmonic_window(30720, kFs, kFtp, 0.6, 0.6001).size(), 0);  // no whole period
}

TEST(ForceMetrics, HarmonicsOfASumOfCosinesAreItsAmplitudes) {
  // x = 3 + 2 cos(w t + 0.3) + 0.5 cos(3 w t - 1), sampled over whole periods at an exact
  // 20 samples per period: the DFT sums are exact to rounding.
  const double ftp = kFs / 20.0;
  Eigen::VectorXd x(20000);
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    const double t = static_cast<double>(k) / kFs;
    x(k) = 3.0 + 2.0 * std::cos(kTwoPi * ftp * t + 0.3) + 0.5 * std::cos(3 * kTwoPi * ftp * t - 1);
  }
  const IndexWindow w = harmonic_window(x.size(), kFs, ftp, 0.0, 100.0);
  const Harmonics h = tooth_harmonics(x, w, kFs, ftp, 4);
  EXPECT_NEAR(h.mean_N, 3.0, 1e-10);
  ASSERT_EQ(h.amplitudes_N.size(), 4u);
  EXPECT_NEAR(h.amplitudes_N[0], 2.0, 1e-9);
  EXPECT_NEAR(h.amplitudes_N[1], 0.0, 1e-9);
  EXPECT_NEAR(h.amplitudes_N[2], 0.5, 1e-9);
  EXPECT_NEAR(h.amplitudes_N[3], 0.0, 1e-9);
  EXPECT_THROW(tooth_harmonics(x, IndexWindow{}, kFs, ftp, 4), std::invalid_argument);
}

TEST(ForceMetrics, LagNrmseAndFitOfAShiftedScaledCopy) {
  Eigen::VectorXd F(5000), late(5000);
  for (Eigen::Index k = 0; k < F.size(); ++k) {
    F(k) = 10.0 + std::sin(0.05 * static_cast<double>(k)) + 0.3 * std::sin(0.31 * k + 1.0);
  }
  // The estimate is F delayed by 3 samples: Fhat(k) = F(k - 3).
  for (Eigen::Index k = 0; k < F.size(); ++k) late(k) = F(std::max<Eigen::Index>(0, k - 3));
  const IndexWindow w = evaluation_window(F.size(), kFs);
  EXPECT_EQ(reference_error(late, F, w).lag_samples, 3);
  // 1.1 F: NRMSE = 10 % of rms(F); fit = 100 (1 - 0.1 ||F|| / ||F - mean F||).
  const Eigen::VectorXd scaled = 1.1 * F;
  const ReferenceError e = reference_error(scaled, F, w);
  const auto seg = F.segment(w.begin, w.size());
  EXPECT_NEAR(e.nrmse_pct, 10.0, 1e-10);
  EXPECT_NEAR(e.fit_pct,
              100.0 * (1.0 - 0.1 * seg.norm() / (seg.array() - seg.mean()).matrix().norm()), 1e-9);
  EXPECT_EQ(e.lag_samples, 0);
  EXPECT_THROW(reference_error(scaled.head(100), F, w), std::invalid_argument);
}

}  // namespace
}  // namespace chatterlab::forcerec
