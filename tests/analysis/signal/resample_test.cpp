// Rational polyphase resampling against analytic sinusoids sampled at the new rate.
#include "analysis/signal/resample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "analysis/common/constants.h"
#include "tests/support/count_allocations.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/record_property.h"

namespace chatterlab {
namespace signal {
namespace {

using chatterlab::testing::expect_input_error;

// Pass band: the Kaiser design ripples by ~1e-4; a tone up to 0.9 of the lower Nyquist frequency
// (0.45 x the rate: the last harmonic the sifs kinds analyse) keeps amplitude and phase to this
// fraction of its amplitude.
constexpr double kPassBandError = 1e-3;
// Stop band: >= 60 dB below the input amplitude (the design gives ~80 dB).
constexpr double kStopBandGain = 1e-3;
// Edge transient: the filter reaches half_length_per_phase max(up, down) up-sampled samples,
// i.e. 50 max(up, down) / up input samples each side; 200 output samples clear it for every
// ratio below.
constexpr Eigen::Index kEdgeSamples = 200;

Eigen::VectorXd tone(double rate_hz, Eigen::Index n, double f_hz, double phase_rad) {
  Eigen::VectorXd x(n);
  for (Eigen::Index k = 0; k < n; ++k)
    x[k] = std::sin(kTwoPi * f_hz * static_cast<double>(k) / rate_hz + phase_rad);
  return x;
}

// Largest |y[m] - sin(2 pi f m / to + phase)| away from the edges: amplitude and timing errors
// both show in it.
double interior_error(const RationalResampler& r, double f_hz, double phase_rad, double seconds) {
  const auto n = static_cast<Eigen::Index>(seconds * r.from_hz());
  const Eigen::VectorXd y = r.apply(tone(r.from_hz(), n, f_hz, phase_rad));
  const Eigen::VectorXd truth = tone(r.to_hz(), y.size(), f_hz, phase_rad);
  return (y - truth).segment(kEdgeSamples, y.size() - 2 * kEdgeSamples).cwiseAbs().maxCoeff();
}

// Largest |y| away from the edges for a unit tone (the gain of an aliased component).
double interior_gain(const RationalResampler& r, double f_hz, double seconds) {
  const auto n = static_cast<Eigen::Index>(seconds * r.from_hz());
  const Eigen::VectorXd y = r.apply(tone(r.from_hz(), n, f_hz, 0.3));
  return y.segment(kEdgeSamples, y.size() - 2 * kEdgeSamples).cwiseAbs().maxCoeff();
}

TEST(Resample, RatiosReduce) {
  const RationalResampler a(12800.0, 10000.0);
  EXPECT_EQ(a.up(), 25);
  EXPECT_EQ(a.down(), 32);
  const RationalResampler b(51200.0, 12800.0);
  EXPECT_EQ(b.up(), 1);
  EXPECT_EQ(b.down(), 4);
  // Rates rounded to 1e-6 Hz before the ratio is reduced.
  const RationalResampler c(12800.0000000004, 10000.0);
  EXPECT_EQ(c.up(), 25);
  EXPECT_EQ(c.down(), 32);
}

TEST(Resample, PassBandToneKeepsAmplitudeAndTime12800To10000) {
  const RationalResampler r(12800.0, 10000.0);
  double worst = 0.0;
  for (double f : {50.0, 1000.0, 2500.0, 3200.0, 4000.0, 4500.0}) {
    const double e = interior_error(r, f, 0.4, 1.0);
    EXPECT_LT(e, kPassBandError) << f << " Hz";
    worst = std::max(worst, e);
  }
  chatterlab::testing::record_and_print("pass_band_error_12800_10000", worst);
}

TEST(Resample, PassBandToneKeepsAmplitudeAndTime51200To12800) {
  const RationalResampler r(51200.0, 12800.0);
  double worst = 0.0;
  for (double f : {100.0, 2000.0, 4000.0, 5760.0}) {
    const double e = interior_error(r, f, -1.1, 0.5);
    EXPECT_LT(e, kPassBandError) << f << " Hz";
    worst = std::max(worst, e);
  }
  chatterlab::testing::record_and_print("pass_band_error_51200_12800", worst);
}

TEST(Resample, PassBandToneKeepsAmplitudeAndTimeUpsampling) {
  // 10000 -> 12800 (up 32, down 25): the filter removes the images of the input band.
  const RationalResampler r(10000.0, 12800.0);
  for (double f : {1000.0, 3000.0}) EXPECT_LT(interior_error(r, f, 0.9, 1.0), kPassBandError) << f;
}

TEST(Resample, ConstantKeepsItsLevel) {
  const RationalResampler r(12800.0, 10000.0);
  const Eigen::VectorXd y = r.apply(Eigen::VectorXd::Constant(6400, 2.5));
  const Eigen::VectorXd mid = y.segment(kEdgeSamples, y.size() - 2 * kEdgeSamples);
  EXPECT_LT((mid.array() - 2.5).abs().maxCoeff(), kPassBandError * 2.5);
}

TEST(Resample, ToneAboveNewNyquistIsAttenuated) {
  const RationalResampler a(12800.0, 10000.0);  // new Nyquist 5000 Hz
  const RationalResampler b(51200.0, 12800.0);  // new Nyquist 6400 Hz
  double worst = 0.0;
  // Just above the new Nyquist frequency (aliases into the top of the analysed band) and far.
  for (double f : {5100.0, 5500.0, 6000.0, 6200.0}) {  // alias to 4900 ... 3800 Hz
    const double g = interior_gain(a, f, 1.0);
    EXPECT_LT(g, kStopBandGain) << f << " Hz";
    worst = std::max(worst, g);
  }
  for (double f : {6500.0, 7800.0, 12000.0, 20000.0}) {
    const double g = interior_gain(b, f, 0.5);
    EXPECT_LT(g, kStopBandGain) << f << " Hz";
    worst = std::max(worst, g);
  }
  chatterlab::testing::record_and_print("stop_band_attenuation_db", -20.0 * std::log10(worst));
}

TEST(Resample, OutputLengthIsCeilOfScaledLength) {
  const RationalResampler r(12800.0, 10000.0);
  // ceil(n 25 / 32): 0 -> 0, 1 -> 1, 32 -> 25, 33 -> 26, 12800 -> 10000, 12801 -> 10001.
  EXPECT_EQ(r.output_size(0), 0);
  EXPECT_EQ(r.output_size(1), 1);
  EXPECT_EQ(r.output_size(32), 25);
  EXPECT_EQ(r.output_size(33), 26);
  EXPECT_EQ(r.output_size(12800), 10000);
  EXPECT_EQ(r.output_size(12801), 10001);
  EXPECT_EQ(r.apply(Eigen::VectorXd::Ones(12801)).size(), 10001);
  EXPECT_EQ(r.apply(Eigen::VectorXd()).size(), 0);
  const RationalResampler d(51200.0, 12800.0);
  EXPECT_EQ(d.apply(Eigen::VectorXd::Ones(1001)).size(), 251);
}

TEST(Resample, IdentityRatioCopies) {
  const RationalResampler r(12800.0, 12800.0);
  EXPECT_TRUE(r.identity());
  const Eigen::VectorXd x = tone(12800.0, 1000, 4321.0, 0.2);
  const Eigen::VectorXd y = r.apply(x);
  EXPECT_EQ(y, x);  // exact copy
}

TEST(Resample, ApplyAllocatesOnlyItsOutput) {
  if (!kCountingMalloc) GTEST_SKIP() << "malloc is interposed by the sanitizer";
  const RationalResampler r(12800.0, 10000.0);
  for (Eigen::Index n : {1000, 100000}) {
    const Eigen::VectorXd x = tone(12800.0, n, 1000.0, 0.0);
    chatterlab::testing::g_allocations = 0;
    chatterlab::testing::g_counting = true;
    const Eigen::VectorXd y = r.apply(x);
    chatterlab::testing::g_counting = false;
    EXPECT_EQ(chatterlab::testing::g_allocations, 1) << "n = " << n;
    EXPECT_EQ(y.size(), r.output_size(n));
  }
}

TEST(Resample, BadRatesThrow) {
  expect_input_error([] { RationalResampler(0.0, 10000.0); },
                     "from_hz = 0: must be finite and > 0");
  expect_input_error([] { RationalResampler(12800.0, -1.0); },
                     "to_hz = -1: must be finite and > 0");
  expect_input_error([] { RationalResampler(12800.0, std::nan("")); },
                     "to_hz = nan: must be finite and > 0");
  expect_input_error([] { RationalResampler(1e-7, 10000.0); },
                     "from_hz = 1e-07: must be >= 1e-6 Hz");
  // 12800 / 10000.5 reduces to 20001/25600 (in 1e-6 Hz units).
  expect_input_error([] { RationalResampler(12800.0, 10000.5); },
                     "resampling 12800 Hz -> 10000.5 Hz: the ratio reduces to 20001/25600, above "
                     "resample.max_factor = 10000");
  ResampleOptions o;
  o.cutoff_fraction = 1.5;
  expect_input_error([&] { RationalResampler(12800.0, 10000.0, o); },
                     "resample.cutoff_fraction = 1.5: must be in (0, 1]");
}

}  // namespace
}  // namespace signal
}  // namespace chatterlab
