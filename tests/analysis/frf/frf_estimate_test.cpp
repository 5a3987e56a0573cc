// H1/H2/coherence from synthetic hits against the modes' receptance.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "analysis/frf/frf.h"
#include "analysis/frf/modal_response.h"

namespace chatterlab {
namespace frf {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

constexpr double kFs = 25600.0;
const Mode kTool = mode_from_mck(0.03134, 22.21, 9.840e5);  // 000 sec. 5.1

std::vector<HammerPulse> five_hits() {
  std::vector<HammerPulse> p;
  const double peaks[] = {100.0, 80.0, 120.0, 95.0, 110.0};
  for (int i = 0; i < 5; ++i) p.push_back({0.05 + 0.25 * i, peaks[i], 2e-4});
  return p;
}

// Worst relative error of h against the tool's receptance over [fn/2, 2 fn].
double worst_error(const Frf& frf, const Eigen::VectorXcd& h) {
  const Eigen::VectorXcd truth = receptance({kTool}, frf.f_hz);
  double worst = 0.0;
  for (Eigen::Index k = 0; k < frf.f_hz.size(); ++k) {
    if (frf.f_hz[k] < 0.5 * kTool.fn_hz || frf.f_hz[k] > 2.0 * kTool.fn_hz) continue;
    worst = std::max(worst, std::abs(h[k] - truth[k]) / std::abs(truth[k]));
  }
  return worst;
}

TEST(FrfEstimate, NoiseFreeH1AndH2AreTheReceptanceForEveryResponseKind) {
  // Without noise H1 = H2 = the receptance up to the generator's accuracy on [fn/2, 2 fn]
  // (hold bias <= 2.5e-4 at 2 fn plus its 3e-4 floor, modal_response_test) and the force
  // window's cut of the anti-alias FIR's ringing.
  constexpr double kRelTol = 6e-4;
  const char* names[] = {"acceleration", "velocity", "displacement"};
  for (ResponseKind kind :
       {ResponseKind::kAcceleration, ResponseKind::kVelocity, ResponseKind::kDisplacement}) {
    const TapRecord r = synthesize_tap_record({kTool}, five_hits(), kFs,
                                              static_cast<Eigen::Index>(1.3 * kFs), kind);
    const HitSet hits = detect_hits(r.force_n, r.response, kFs);
    const Frf frf = compute_frf(r.force_n, r.response, hits, kind);
    ASSERT_TRUE(frf.summary.ok()) << frf.summary.message;
    EXPECT_EQ(frf.hits_used, 5);
    EXPECT_EQ(frf.exp_window_tau_s, 0.0);  // the tool mode decays within 0.05 s
    EXPECT_NEAR(frf.df_hz, kFs / static_cast<double>(hits.record_samples), 1e-12);
    EXPECT_NEAR(frf.f_hz[0], frf.df_hz, 1e-12);  // DC excluded
    const double e1 = worst_error(frf, frf.h1);
    const double e2 = worst_error(frf, frf.h2);
    std::printf("%s: worst relative error over [fn/2, 2 fn]: H1 %.2e, H2 %.2e\n",
                names[static_cast<int>(kind)], e1, e2);
    EXPECT_LT(e1, kRelTol);
    EXPECT_LT(e2, kRelTol);
  }
}

TEST(FrfEstimate, NoiseLowersCoherenceAwayFromTheResonance) {
  TapSynthesisOptions o;
  o.force_noise_fraction = 0.01;
  o.response_noise_fraction = 0.01;
  const TapRecord r =
      synthesize_tap_record({kTool}, five_hits(), kFs, static_cast<Eigen::Index>(1.3 * kFs),
                            ResponseKind::kAcceleration, o);
  const HitSet hits = detect_hits(r.force_n, r.response, kFs);
  const Frf frf = compute_frf(r.force_n, r.response, hits, ResponseKind::kAcceleration);
  ASSERT_TRUE(frf.summary.ok());
  const auto at = [&](double f) {
    return static_cast<Eigen::Index>(std::lround(f / frf.df_hz)) - 1;
  };
  EXPECT_GT(frf.coherence[at(kTool.fn_hz)], 0.99);  // strong response at the resonance
  EXPECT_LT(frf.coherence[at(20.0)], 0.9);          // acceleration ~ w^2: buried in noise
  // H2 >= H1 in magnitude where noise enters the response (H1 = gamma^2 H2).
  for (Eigen::Index k = 0; k < frf.f_hz.size(); ++k) {
    EXPECT_NEAR(std::abs(frf.h1[k]), frf.coherence[k] * std::abs(frf.h2[k]),
                1e-9 * std::abs(frf.h2[k]));
  }
}

TEST(FrfEstimate, SingleHitWarnsThatCoherenceIsMeaningless) {
  const TapRecord r =
      synthesize_tap_record({kTool}, {{0.05, 100.0, 2e-4}}, kFs, 8192, ResponseKind::kAcceleration);
  const HitSet hits = detect_hits(r.force_n, r.response, kFs);
  const Frf frf = compute_frf(r.force_n, r.response, hits, ResponseKind::kAcceleration);
  ASSERT_TRUE(frf.summary.ok());
  EXPECT_EQ(frf.hits_used, 1);
  ASSERT_FALSE(frf.summary.warnings.empty());
  EXPECT_THAT(frf.summary.warnings[0], StartsWith("one hit only: coherence is 1"));
}

TEST(FrfEstimate, NoAcceptedHitFails) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(1000);
  const HitSet hits = detect_hits(zero, zero, kFs);
  const Frf frf = compute_frf(zero, zero, hits, ResponseKind::kAcceleration);
  EXPECT_FALSE(frf.summary.ok());
  EXPECT_THAT(frf.summary.message, StartsWith("no FRF: no accepted hit (no hit above threshold"));
}

TEST(FrfEstimate, AutomaticExponentialWindowOnlyWhenTheRecordIsTruncated) {
  // zeta = 0.002 at 891.8 Hz decays as exp(-11.2 t): over the 0.25 s records it falls to
  // about 7 % (> 1 %), so the automatic rule applies a window, with
  // tau = T / ln(r / 0.01) for the measured end ratio r.
  const Mode light = mode_from_modal(891.8, 0.002, 0.03134);
  const TapRecord r = synthesize_tap_record(
      {light}, five_hits(), kFs, static_cast<Eigen::Index>(1.3 * kFs), ResponseKind::kAcceleration);
  const HitSet hits = detect_hits(r.force_n, r.response, kFs);
  const Frf frf = compute_frf(r.force_n, r.response, hits, ResponseKind::kAcceleration);
  ASSERT_TRUE(frf.summary.ok());
  // Segments of 320 samples (5 % of L = 6400) start at the trigger and 6400 - 26 - 320
  // samples later: T = 6054 / fs = 0.2365 s, r = exp(-11.21 T) = 0.0706, so
  // tau = T / ln(r / 0.01) = 0.1209 s. Within 3 % (the RMS of 11-period segments of a
  // decaying sine tracks its envelope to a fraction of a percent).
  std::printf("tau %.4f s\n", frf.exp_window_tau_s);
  EXPECT_NEAR(frf.exp_window_tau_s / 0.1209, 1.0, 0.03);
  EXPECT_THAT(frf.summary.warnings.back(), StartsWith("exponential window tau = "));
}

TEST(FrfEstimate, BadInputIsRejected) {
  const Eigen::VectorXd a = Eigen::VectorXd::Zero(100);
  const Eigen::VectorXd b = Eigen::VectorXd::Zero(99);
  HitSet hits;
  try {
    compute_frf(a, b, hits, ResponseKind::kAcceleration);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "frf: force has 100 samples, response 99: must be equal");
  }
  FrfOptions o;
  o.exp_window_auto = false;
  o.exp_window_tau_s = -0.1;
  EXPECT_THROW(compute_frf(a, a, hits, ResponseKind::kAcceleration, o), InputError);
}

}  // namespace
}  // namespace frf
}  // namespace chatterlab
