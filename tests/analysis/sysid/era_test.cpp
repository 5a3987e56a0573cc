// ERA with the Gavish-Donoho order and the Schur stable split (analysis/sysid/era.h).
#include "analysis/sysid/era.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>

#include "analysis/common/constants.h"
#include "analysis/sysid/gavish_donoho.h"
#include "analysis/sysid/random_system.h"

namespace chatterlab {
namespace sysid {
namespace {

constexpr double kRate = 10000.0;

// The FRF of a model on the grid f_m = m rate / (2M), m = 0..M.
void grid_frf(const DiscreteStateSpace& s, long M, Eigen::VectorXd* f, Eigen::VectorXcd* G) {
  *f = Eigen::VectorXd::LinSpaced(M + 1, 0.0, 0.5 * s.sample_rate_hz);
  *G = frequency_response(s, *f);
}

// Distance between two pole sets (each pole of `a` to its nearest in `b`, the largest).
double pole_set_distance(const Eigen::VectorXcd& a, const Eigen::VectorXcd& b) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    double best = 1e300;
    for (Eigen::Index j = 0; j < b.size(); ++j) best = std::min(best, std::abs(a[i] - b[j]));
    worst = std::max(worst, best);
  }
  return worst;
}

TEST(GavishDonoho, ConstantsOfTheSquareAndOblongCases) {
  // Reference: notes/001.md sec. 3 (values to the digits printed there) and 4/sqrt(3) exactly.
  EXPECT_NEAR(gavish_donoho_lambda(1.0), 4.0 / std::sqrt(3.0), 1e-14);
  EXPECT_NEAR(marchenko_pastur_median(1.0), 0.65278, 5e-6);
  EXPECT_NEAR(gavish_donoho_omega(1.0), kEraMedianRuleOmega, 5e-5);
  EXPECT_NEAR(marchenko_pastur_median(0.5), 0.83047, 5e-6);
  EXPECT_NEAR(gavish_donoho_omega(0.5), 2.1712, 5e-5);
  EXPECT_NEAR(marchenko_pastur_median(0.25), 0.91600, 5e-6);
  EXPECT_NEAR(gavish_donoho_omega(0.25), 1.8369, 5e-5);
  // The paper's cubic approximation 0.56 b^3 - 0.95 b^2 + 1.82 b + 1.43 is good to about 0.02.
  for (double b : {0.1, 0.3, 0.7, 1.0}) {
    EXPECT_NEAR(gavish_donoho_omega(b), 0.56 * b * b * b - 0.95 * b * b + 1.82 * b + 1.43, 0.02)
        << b;
  }
  EXPECT_THROW(gavish_donoho_omega(0.0), InputError);
  EXPECT_THROW(gavish_donoho_omega(1.5), InputError);
}

TEST(MarkovFromFrf, ConstantAndDelayAreImpulses) {
  // G = 2: y_0 = 2, every other y_k = 0. G = exp(-j w Ts): y_1 = 1 (a one-sample delay).
  const long M = 64;
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(M + 1, 0.0, 0.5 * kRate);
  const Eigen::VectorXcd two = Eigen::VectorXcd::Constant(M + 1, 2.0);
  const Eigen::VectorXd y = markov_parameters_from_frf(f, two, kRate);
  ASSERT_EQ(y.size(), 2 * M);
  EXPECT_NEAR(y[0], 2.0, 1e-14);
  EXPECT_LT(y.tail(2 * M - 1).cwiseAbs().maxCoeff(), 1e-14);
  Eigen::VectorXcd delay(M + 1);
  for (long m = 0; m <= M; ++m) delay[m] = std::polar(1.0, -kTwoPi * f[m] / kRate);
  const Eigen::VectorXd y1 = markov_parameters_from_frf(f, delay, kRate);
  EXPECT_NEAR(y1[1], 1.0, 1e-12);
  EXPECT_NEAR(y1[0], 0.0, 1e-12);
  EXPECT_LT(y1.tail(2 * M - 2).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(MarkovFromFrf, BandLimitedDataIsTaperedToZeroAndHeldBelow) {
  // A constant 1 measured on [1000, 2500] Hz, rate 10 kHz, df 10 Hz: the grid has M = 500,
  // the value at DC is held (1), and above 2500 Hz a raised cosine falls to 0 at 5000 Hz. The
  // IDFT's sum y_0 is then the mean of the Hermitian spectrum: (1/N)(1 + 2 sum_{m=1}^{M-1}
  // X_m + X_M), computed here independently.
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(151, 1000.0, 2500.0);
  const Eigen::VectorXcd G = Eigen::VectorXcd::Constant(151, 1.0);
  const Eigen::VectorXd y = markov_parameters_from_frf(f, G, kRate);
  ASSERT_EQ(y.size(), 1000);
  double sum = 1.0;
  for (int m = 1; m < 500; ++m) {
    const double fm = 10.0 * m;
    const double x = fm <= 2500.0 ? 1.0 : 0.5 * (1.0 + std::cos(kPi * (fm - 2500.0) / 2500.0));
    sum += 2.0 * x;
  }
  EXPECT_NEAR(y[0], sum / 1000.0, 1e-13);
}

// A rate whose half is not a whole grid step in floating point: the last grid point is rate/2
// exactly (m rate / N rounds one ulp above it, which divided the taper by zero).
TEST(MarkovFromFrf, DataEndingAtHalfAnOddRateStaysFinite) {
  const double rate = 10000.1;
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(110, 0.0, 0.5 * rate);
  const Eigen::VectorXcd G = Eigen::VectorXcd::Constant(110, std::complex<double>(1.0, 0.5));
  const Eigen::VectorXd y = markov_parameters_from_frf(f, G, rate);
  EXPECT_TRUE(y.allFinite());
  EXPECT_NEAR(y[0], 1.0, 1e-12);  // a constant real part: an impulse of 1 (Im ignored at 0, M)
}

TEST(MarkovFromFrf, BadGridsNameTheKey) {
  Eigen::VectorXd f(4);
  f << 0.0, 10.0, 20.0, 31.0;  // 3.3 % off the mean step
  const Eigen::VectorXcd G = Eigen::VectorXcd::Ones(4);
  try {
    markov_parameters_from_frf(f, G, kRate);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("freq_hz = 31"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("uniform"), std::string::npos) << e.what();
  }
  f << 0.0, 2000.0, 4000.0, 6000.0;  // beyond rate/2
  EXPECT_THROW(markov_parameters_from_frf(f, G, kRate), InputError);
  f << 30.0, 20.0, 10.0, 0.0;  // falling
  EXPECT_THROW(markov_parameters_from_frf(f, G, kRate), InputError);
  f << 0.0, 1e-4, 2e-4, 3e-4;  // a grid of 5e7 points for 10 kHz
  EXPECT_THROW(markov_parameters_from_frf(f, G, kRate), InputError);
}

// Noise-free: the order and the poles come back exactly (tolerance: rounding of a 10..30-state
// realization, whose closest poles are ill-conditioned: 1e-7 in z; measured 1.8e-8 at 30
// states), for every order the issue names.
TEST(Era, RecoversAKnownSystemExactlyWithoutNoise) {
  for (int order : {10, 20, 30}) {
    RandomSystemOptions o;
    o.order = order;
    o.max_radius = 0.95;  // 0.95^2048 = 1e-46: no time aliasing on N = 2048
    const DiscreteStateSpace truth = random_stable_system(o, kRate, 100 + order);
    Eigen::VectorXd f;
    Eigen::VectorXcd G;
    grid_frf(truth, 1024, &f, &G);
    const EraResult r = era_identify(f, G, kRate);
    ASSERT_TRUE(r.summary.ok()) << r.summary.full_report();
    EXPECT_EQ(r.realization.hankel_size, 512);
    EXPECT_EQ(r.model.order(), order);
    EXPECT_EQ(r.unstable_removed, 0);
    EXPECT_LT(pole_set_distance(poles(truth), r.poles), 1e-7) << order;
    EXPECT_LT(pole_set_distance(r.poles, poles(truth)), 1e-7) << order;
    EXPECT_NEAR(r.model.D, truth.D, 1e-10);
    EXPECT_NEAR(r.dc_gain, dc_gain(truth), 1e-8 * std::max(1.0, std::abs(dc_gain(truth))));
    EXPECT_GT(r.fit_pct, 99.9999) << order;
  }
}

TEST(Era, KnownNoiseRuleAndMedianRuleOnNoisyMarkovParameters) {
  // A 10-state system's impulse response with white noise of known sigma: both rules keep the
  // strong modes and neither keeps the noise (order between 2 and 10; the median rule is the
  // format's default, the known-sigma rule the one for simulations).
  RandomSystemOptions o;
  o.max_radius = 0.97;
  const DiscreteStateSpace truth = random_stable_system(o, kRate, 7);
  const int N = 2048;
  Eigen::VectorXd y(N);
  y[0] = truth.D;
  Eigen::VectorXd x = truth.B;
  for (int k = 1; k < N; ++k) {
    y[k] = (truth.C * x)(0);
    x = truth.A * x;
  }
  const double sigma = 0.01 * y.norm() / std::sqrt(static_cast<double>(N));
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, sigma);
  for (int k = 0; k < N; ++k) y[k] += noise(rng);
  const EraRealization median_rule = era_realize(y, kRate);
  EraOptions known;
  known.markov_noise_std = sigma;
  const EraRealization known_rule = era_realize(y, kRate, known);
  ASSERT_TRUE(median_rule.summary.ok());
  ASSERT_TRUE(known_rule.summary.ok());
  for (const auto* r : {&median_rule, &known_rule}) {
    EXPECT_GE(r->model.order(), 2);
    EXPECT_LE(r->model.order(), 10);
  }
  // The known-sigma threshold is lambda*(1) sqrt(alpha) sigma exactly.
  EXPECT_NEAR(known_rule.threshold, 4.0 / std::sqrt(3.0) * std::sqrt(512.0) * sigma, 1e-12 * sigma);
}

TEST(Era, AllZeroDataKeepsNoStateAndSaysSo) {
  const Eigen::VectorXd y = Eigen::VectorXd::Zero(64);
  const EraRealization r = era_realize(y, kRate);
  EXPECT_TRUE(r.summary.failed());
  EXPECT_NE(r.summary.message.find("kept no state"), std::string::npos);
}

TEST(Era, OrderIsCappedWithAWarning) {
  RandomSystemOptions o;
  o.order = 20;
  o.max_radius = 0.95;
  const DiscreteStateSpace truth = random_stable_system(o, kRate, 11);
  Eigen::VectorXd f;
  Eigen::VectorXcd G;
  grid_frf(truth, 512, &f, &G);
  EraOptions cap;
  cap.max_order = 8;
  const EraResult r = era_identify(f, G, kRate, cap);
  ASSERT_TRUE(r.summary.ok());
  EXPECT_EQ(r.realization.order_by_threshold, 20);
  EXPECT_EQ(r.realization.model.order(), 8);
  ASSERT_FALSE(r.summary.warnings.empty());
  EXPECT_NE(r.summary.warnings[0].find("capped at 8"), std::string::npos);
}

// Stable split (001 eqs 3.24-3.27): an unstable pair at |z| = 1.02 added to a stable system is
// removed, the off-diagonal block vanishes, and the kept part has the stable system's FRF.
TEST(StablePart, RemovesAnUnstablePairAndKeepsTheStableFrf) {
  RandomSystemOptions o;
  o.order = 12;
  const DiscreteStateSpace stable = random_stable_system(o, kRate, 21);
  DiscreteStateSpace both;
  both.sample_rate_hz = kRate;
  both.A = Eigen::MatrixXd::Zero(14, 14);
  both.A.topLeftCorner(12, 12) = stable.A;
  const double r = 1.02, th = 0.7;
  both.A.bottomRightCorner(2, 2) << r * std::cos(th), -r * std::sin(th), r * std::sin(th),
      r * std::cos(th);
  both.B.resize(14);
  both.B << stable.B, 0.3, -0.8;
  both.C.resize(14);
  both.C << stable.C, 1.1, 0.4;
  both.D = stable.D;
  // Mix the parts with a random similarity so that they are coupled in the given coordinates.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> nd;
  Eigen::MatrixXd T = Eigen::MatrixXd::Identity(14, 14);
  for (int i = 0; i < 14; ++i) {
    for (int j = 0; j < 14; ++j) T(i, j) += 0.3 * nd(rng);
  }
  const Eigen::MatrixXd Ti = T.inverse();
  DiscreteStateSpace mixed = both;
  mixed.A = Ti * both.A * T;
  mixed.B = Ti * both.B;
  mixed.C = both.C * T;
  const StableSplit split = stable_part(mixed);
  ASSERT_TRUE(split.summary.ok()) << split.summary.full_report();
  EXPECT_EQ(split.removed, 2);
  EXPECT_EQ(split.stable.order(), 12);
  EXPECT_LT(split.decoupling_residual, 1e-10);
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(200, 1.0, 4999.0);
  const Eigen::VectorXcd G_ref = frequency_response(stable, f);
  const Eigen::VectorXcd G_kept = frequency_response(split.stable, f);
  EXPECT_LT((G_ref - G_kept).cwiseAbs().maxCoeff() / G_ref.cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(pole_set_distance(poles(split.stable), poles(stable)), 1e-9);
}

TEST(StablePart, AStableModelIsKeptWhole) {
  RandomSystemOptions o;
  o.order = 6;
  const DiscreteStateSpace s = random_stable_system(o, kRate, 2);
  const StableSplit split = stable_part(s);
  ASSERT_TRUE(split.summary.ok());
  EXPECT_EQ(split.removed, 0);
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(50, 0.0, 5000.0);
  EXPECT_LT((frequency_response(s, f) - frequency_response(split.stable, f)).cwiseAbs().maxCoeff(),
            1e-10);
}

TEST(StateSpace, ModesFromPolePairs) {
  // z = exp(s Ts), s = -zeta wn + j wn sqrt(1 - zeta^2), fn = 500 Hz, zeta = 0.02.
  const double wn = kTwoPi * 500.0, zeta = 0.02;
  const std::complex<double> s(-zeta * wn, wn * std::sqrt(1.0 - zeta * zeta));
  Eigen::VectorXcd p(3);
  p << std::exp(s / kRate), std::conj(std::exp(s / kRate)), 0.5;
  const auto modes = modes_of(p, kRate);
  ASSERT_EQ(modes.size(), 1u);
  EXPECT_NEAR(modes[0].fn_hz, 500.0, 1e-9);
  EXPECT_NEAR(modes[0].zeta, 0.02, 1e-12);
}

}  // namespace
}  // namespace sysid
}  // namespace chatterlab
