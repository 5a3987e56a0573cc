// Consistency diagnostics (analysis/kalman/consistency.h): NIS of a correctly tuned filter over
// many seeds inside its chi-square band, NEES over the ensemble, window means, and the summary
// arithmetic; a mistuned filter as the negative control.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/kalman/consistency.h"
#include "analysis/kalman/kalman_filter.h"
#include "tests/support/expect_input_error.h"

namespace chatterlab {
namespace kalman {
namespace {

// A lightly damped oscillator sampled at T (forward Euler, stable: spectral radius < 1) driven by
// a force noise, its position measured at every step and its velocity at every fifth (a
// multirate measurement: the velocity row joins the update only when it arrives).
LinearModel<2, 0, 2> oscillator() {
  const double T = 0.05, wn = 2.0, zeta = 0.1;
  LinearModel<2, 0, 2> m;
  m.A << 1.0, T, -T * wn * wn, 1.0 - 2.0 * zeta * wn * T;
  const Eigen::Vector2d G(0.5 * T * T, T);
  m.Q = 4.0 * G * G.transpose() + 1e-6 * Eigen::Matrix2d::Identity();
  m.C.setIdentity();
  m.R << 0.01, 0.0, 0.0, 0.04;
  return m;
}

MeasurementMask<2> rows_at(int k) { return MeasurementMask<2>(k % 5 == 0 ? 0b11u : 0b01u); }

struct FilterRun {
  NisSummary nis;
  std::vector<double> nees;  // per step
  std::vector<double> nis_steps;
};

// One run of `steps` steps: truth drawn from the filter's prior and the model's noises; the
// filter uses `r_scale` times the true R (1: correctly tuned).
FilterRun run(std::uint64_t seed, int steps, double r_scale, bool multirate = true) {
  const LinearModel<2, 0, 2> truth = oscillator();
  LinearModel<2, 0, 2> tuned = truth;
  tuned.R *= r_scale;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  const auto draw = [&](const Eigen::Matrix2d& cov) {
    const Eigen::Matrix2d L = Eigen::LLT<Eigen::Matrix2d>(cov).matrixL();
    return Eigen::Vector2d(L * Eigen::Vector2d(n(rng), n(rng)));
  };
  const Eigen::Vector2d m0(0.1, 0.0);
  const Eigen::Matrix2d P0 = Eigen::Vector2d(0.01, 0.04).asDiagonal();
  Eigen::Vector2d x = m0 + draw(P0);
  KalmanFilter<2, 0, 2> f(tuned, m0, P0);
  NisMonitor<2> monitor;
  FilterRun r;
  for (int k = 1; k <= steps; ++k) {
    x = truth.A * x + draw(truth.Q);
    const Eigen::Vector2d z = truth.C * x + draw(truth.R);
    f.predict(Matrix<0, 1>());
    const Innovation i = f.update(z, multirate ? rows_at(k) : MeasurementMask<2>(0b01u));
    monitor.add(i);
    r.nis_steps.push_back(i.nis);
    r.nees.push_back(nees(x - f.state(), f.covariance()));
  }
  r.nis = monitor.summary();
  return r;
}

constexpr int kSeeds = 200;
constexpr int kSteps = 100;

TEST(Consistency, NisOfATunedFilterIsInsideItsBand) {
  // With the truth drawn from the filter's own model, the innovations are independent Gaussian
  // with covariance S, so the sum of one run's NIS is chi-square(total rows) exactly and its
  // mean lies in the two-sided 95 % band with probability 0.95. Over 200 independent seeds the
  // count inside is Binomial(200, 0.95) (mean 190, sd 3.1); requiring >= 180 fails a consistent
  // filter with probability P(X <= 179) = 0.12 % (exact binomial tail, mpmath). Each update's
  // NIS lies in its chi-square(m_k) band with probability 0.95: over 24,000 updates the
  // fraction has sd 0.0014, and +-0.006 (4 sd) bounds it.
  int inside = 0;
  std::int64_t updates = 0;
  double weighted_inside = 0.0;
  for (int s = 0; s < kSeeds; ++s) {
    const FilterRun r = run(1000 + static_cast<std::uint64_t>(s), kSteps, 1.0);
    ASSERT_EQ(r.nis.updates, kSteps);
    ASSERT_EQ(r.nis.dof, kSteps + kSteps / 5);  // position every step, velocity every fifth
    if (r.nis.mean_inside()) ++inside;
    updates += r.nis.updates;
    weighted_inside += r.nis.fraction_inside * static_cast<double>(r.nis.updates);
  }
  RecordProperty("seeds_inside", inside);
  EXPECT_GE(inside, 180);
  EXPECT_NEAR(weighted_inside / static_cast<double>(updates), 0.95, 0.006);
}

TEST(Consistency, NisFlagsAMistunedFilter) {
  // Negative control: the filter assumes 4 R. Its S is too large, the NIS too small: the mean of
  // a run falls below the band (S_true / S_filter ~ 0.3 to 0.6 here against a band of +-25 %)
  // in nearly every seed, and fewer updates lie in the per-update band than 95 %.
  int inside = 0;
  for (int s = 0; s < kSeeds; ++s) {
    const FilterRun r = run(1000 + static_cast<std::uint64_t>(s), kSteps, 4.0);
    if (r.nis.mean_inside()) ++inside;
    EXPECT_LT(r.nis.mean, r.nis.mean_band.upper);
  }
  RecordProperty("mistuned_seeds_inside", inside);
  EXPECT_LE(inside, 20);
}

TEST(Consistency, EnsembleNeesIsInsideItsBand) {
  // NEES_k = e^T P^-1 e ~ chi-square(2) at every step; its mean over the 200 independent seeds
  // has the band chi-square(400) / 200 at each step. The 100 steps' ensemble means are
  // correlated in time (the same seeds' errors), so their count inside is not binomial: >= 85 of
  // 100 (expected 95) is the requirement; the mistuned filter (4 R: P too large) has almost none.
  std::vector<double> sum(kSteps, 0.0), sum_bad(kSteps, 0.0);
  for (int s = 0; s < kSeeds; ++s) {
    const FilterRun r = run(5000 + static_cast<std::uint64_t>(s), kSteps, 1.0);
    const FilterRun b = run(5000 + static_cast<std::uint64_t>(s), kSteps, 4.0);
    for (int k = 0; k < kSteps; ++k) {
      sum[static_cast<std::size_t>(k)] += r.nees[static_cast<std::size_t>(k)];
      sum_bad[static_cast<std::size_t>(k)] += b.nees[static_cast<std::size_t>(k)];
    }
  }
  const ChiSquareBand band = mean_chi_square_band(kSeeds, 2);
  int inside = 0, inside_bad = 0;
  for (int k = 0; k < kSteps; ++k) {
    if (band.contains(sum[static_cast<std::size_t>(k)] / kSeeds)) ++inside;
    if (band.contains(sum_bad[static_cast<std::size_t>(k)] / kSeeds)) ++inside_bad;
  }
  RecordProperty("nees_steps_inside", inside);
  EXPECT_GE(inside, 85);
  EXPECT_LE(inside_bad, 10);
}

TEST(Consistency, WindowMeansOfALongRun) {
  // 20,000 position-only updates in 200 windows of 100: each window mean lies in
  // chi-square(100) / 100 with probability 0.95 (independent innovations), so the fraction
  // inside is Binomial(200, 0.95) / 200; >= 0.90 fails with probability 0.12 % (as above).
  const FilterRun r = run(42, 20000, 1.0, false);
  const Eigen::Map<const Eigen::VectorXd> nis(r.nis_steps.data(),
                                              static_cast<Eigen::Index>(r.nis_steps.size()));
  const NisWindows w = nis_windows(nis, 1, 100);
  EXPECT_EQ(w.mean.size(), 200);
  EXPECT_NEAR(w.band.lower, 74.222 / 100, 0.5e-5);  // NIST table, dof 100 (chi-square test)
  EXPECT_NEAR(w.band.upper, 129.561 / 100, 0.5e-5);
  EXPECT_GE(w.fraction_inside, 0.90);
  EXPECT_LT(w.fraction_inside, 1.0);
}

TEST(NisMonitor, SummarizesByHand) {
  // Updates: NIS 1 (1 row), 3 (2 rows), none (0 rows, ignored), 10 (1 row). Per-update bands
  // (NIST dof 1: [0.001, 5.024], dof 2: [0.051, 7.378]) contain 1 and 3, not 10; the mean 14 / 3
  // has the band chi-square(4) / 3 = [0.484, 11.143] / 3 (NIST dof 4).
  NisMonitor<2> m;
  m.add({1.0, 1});
  m.add({3.0, 2});
  m.add({std::nan(""), 0});
  m.add({10.0, 1});
  const NisSummary s = m.summary();
  EXPECT_EQ(s.updates, 3);
  EXPECT_EQ(s.dof, 4);
  EXPECT_DOUBLE_EQ(s.mean, 14.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.fraction_inside, 2.0 / 3.0);
  EXPECT_NEAR(s.mean_band.lower, 0.484 / 3, 0.5e-3 / 3);
  EXPECT_NEAR(s.mean_band.upper, 11.143 / 3, 0.5e-3 / 3);
  EXPECT_FALSE(s.mean_inside());
  EXPECT_EQ(s.report(),
            "mean NIS 4.667 outside [0.1615, 3.714] (95 %), 66.7 % of 3 updates inside their band");
  NisMonitor<2> pooled;
  pooled.merge(m);
  pooled.merge(m);
  EXPECT_EQ(pooled.summary().updates, 6);
  EXPECT_DOUBLE_EQ(pooled.summary().mean, 14.0 / 3.0);
}

TEST(NisMonitor, EmptySummaryIsNotConsistent) {
  const NisSummary s = NisMonitor<2>().summary();
  EXPECT_EQ(s.updates, 0);
  EXPECT_TRUE(std::isnan(s.mean));
  EXPECT_FALSE(s.mean_inside());
  EXPECT_EQ(s.report(), "no NIS: no update ran");
}

TEST(Nees, ClosedFormAndBadInput) {
  // Diagonal P: sum of e_i^2 / P_ii = 4 / 4 + 9 / 9.
  const Eigen::Vector2d e(2.0, 3.0);
  const Eigen::Matrix2d P = Eigen::Vector2d(4.0, 9.0).asDiagonal();
  EXPECT_DOUBLE_EQ(nees(e, P), 2.0);
  chatterlab::testing::expect_input_error([&] { nees(e, Eigen::Matrix3d::Identity()); },
                                          "nees: P size = 3 x 3: must be 2 x 2 (the error's size)");
  const Eigen::VectorXd nis = Eigen::VectorXd::Ones(10);
  chatterlab::testing::expect_input_error(
      [&] { nis_windows(nis, 1, 0); },
      "nis_windows: window = 0: must be in [1, 10] (the number of updates)");
  chatterlab::testing::expect_input_error([&] { nis_windows(nis, 0, 5); },
                                          "nis_windows: dimension = 0: must be >= 1");
}

}  // namespace
}  // namespace kalman
}  // namespace chatterlab
