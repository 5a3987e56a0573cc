// Hit detection on synthetic hammer records with known pulse times.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "analysis/frf/hits.h"
#include "analysis/frf/modal_response.h"

namespace chatterlab {
namespace frf {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

constexpr double kFs = 25600.0;
const Mode kTool = mode_from_mck(0.03134, 22.21, 9.840e5);  // 000 sec. 5.1
// A trigger lands within 2 samples of the pulse start: the 5 % threshold is crossed in the
// first 2 % of a 0.2 ms (5-sample) half-sine, and the anti-alias FIR spreads it by ~1 sample.
constexpr double kTriggerTolS = 2.0 / kFs;

TapRecord record(const std::vector<HammerPulse>& pulses, double duration_s,
                 std::uint64_t seed = 3) {
  TapSynthesisOptions o;
  o.force_noise_fraction = 0.01;
  o.response_noise_fraction = 0.01;
  o.seed = seed;
  return synthesize_tap_record({kTool}, pulses, kFs, static_cast<Eigen::Index>(duration_s * kFs),
                               ResponseKind::kAcceleration, o);
}

std::vector<HammerPulse> five_hits(double width_s = 2e-4) {
  std::vector<HammerPulse> p;
  const double peaks[] = {100.0, 80.0, 120.0, 95.0, 110.0};
  for (int i = 0; i < 5; ++i) p.push_back({0.05 + 0.25 * i, peaks[i], width_s});
  return p;
}

// The time in "double hit at t = 0.303040 s".
double time_in(const std::string& reason) {
  const std::string key = "t = ";
  return std::stod(reason.substr(reason.find(key) + key.size()));
}

TEST(Hits, FiveCleanHitsAreFoundAndShareOneRecordLength) {
  const auto pulses = five_hits();
  const TapRecord r = record(pulses, 1.3);
  const HitSet set = detect_hits(r.force_n, r.response, kFs);
  ASSERT_TRUE(set.summary.ok()) << set.summary.message;
  ASSERT_EQ(set.hits.size(), 5u);
  EXPECT_EQ(set.accepted_count(), 5);
  EXPECT_TRUE(set.summary.warnings.empty());
  // Records start 1 ms (26 samples) before the trigger and are as long as the hit spacing
  // (0.25 s = 6400 samples, less the trigger jitter of <= 2 samples).
  EXPECT_NEAR(static_cast<double>(set.record_samples), 6400.0, 2.0);
  for (size_t i = 0; i < 5; ++i) {
    const Hit& h = set.hits[i];
    EXPECT_NEAR(h.time_s, pulses[i].time_s, kTriggerTolS) << "hit " << i;
    EXPECT_EQ(h.trigger - h.start, 26);
    EXPECT_EQ(h.end - h.start, set.record_samples);
    EXPECT_GT(h.pulse_end, h.trigger);
    // Peak after the FIR is a little below the half-sine's: within 5 %.
    EXPECT_NEAR(h.peak_force_n / pulses[i].peak_n, 1.0, 0.05) << "hit " << i;
    if (i + 1 < 5) {
      EXPECT_LE(h.end, set.hits[i + 1].start);
    }
  }
  // The MAD noise estimate finds the 1.2 N std (1 % of the 120 N peak) within its 2 %
  // sampling error (33280 samples) plus the pulses' small share; the threshold is then the
  // larger of 5 % of the largest peak (~5.8 N) and 10 x noise (~12 N).
  EXPECT_NEAR(set.force_noise_n / 1.2, 1.0, 0.05);
  EXPECT_DOUBLE_EQ(set.threshold_n,
                   std::max(0.05 * set.hits[2].peak_force_n, 10.0 * set.force_noise_n));
}

TEST(Hits, DoubleHitIsRejected) {
  auto pulses = five_hits();
  pulses.push_back({0.303, 30.0, 2e-4});  // a bounce 3 ms after the second hit
  const TapRecord r = record(pulses, 1.3);
  const HitSet set = detect_hits(r.force_n, r.response, kFs);
  ASSERT_TRUE(set.summary.ok());
  ASSERT_EQ(set.hits.size(), 5u);
  EXPECT_EQ(set.accepted_count(), 4);
  EXPECT_FALSE(set.hits[1].accepted);
  EXPECT_THAT(set.hits[1].rejection, StartsWith("double hit at t = "));
  EXPECT_NEAR(time_in(set.hits[1].rejection), 0.303, kTriggerTolS);
  ASSERT_EQ(set.summary.warnings.size(), 1u);
  EXPECT_THAT(set.summary.warnings[0], HasSubstr("hit 2 at t = 0.30"));
}

TEST(Hits, ClippedResponseIsRejected) {
  auto pulses = five_hits();
  pulses[2].peak_n = 250.0;  // the third hit drives the response past the clip level
  TapRecord r = record(pulses, 1.3);
  const double limit = 0.7 * r.response.cwiseAbs().maxCoeff();  // others reach <= 0.45
  r.response = r.response.cwiseMin(limit).cwiseMax(-limit);
  const HitSet set = detect_hits(r.force_n, r.response, kFs);
  ASSERT_TRUE(set.summary.ok());
  EXPECT_EQ(set.accepted_count(), 4);
  EXPECT_FALSE(set.hits[2].accepted);
  EXPECT_THAT(set.hits[2].rejection, StartsWith("clipped: response flat at its extreme"));
}

TEST(Hits, ClippedForceIsRejected) {
  auto pulses = five_hits(5e-4);  // 0.5 ms pulses: 13 samples, a flat top spans several
  pulses[4].peak_n = 250.0;
  TapRecord r = record(pulses, 1.3);
  const double limit = 0.8 * r.force_n.maxCoeff();
  r.force_n = r.force_n.cwiseMin(limit);
  const HitSet set = detect_hits(r.force_n, r.response, kFs);
  ASSERT_TRUE(set.summary.ok());
  EXPECT_EQ(set.accepted_count(), 4);
  EXPECT_THAT(set.hits[4].rejection, StartsWith("clipped: force flat at its extreme"));
}

TEST(Hits, NoHitAboveThresholdFails) {
  const TapRecord r = record({}, 0.5);  // noise only (force std 0, response std 0)
  Eigen::VectorXd force = Eigen::VectorXd::Zero(r.force_n.size());
  std::mt19937_64 rng(9);
  std::normal_distribution<double> normal(0.0, 0.02);
  for (Eigen::Index i = 0; i < force.size(); ++i) force[i] = normal(rng);
  const HitSet set = detect_hits(force, r.response, kFs);
  EXPECT_FALSE(set.summary.ok());
  EXPECT_THAT(set.summary.message, StartsWith("no hit above threshold: largest force peak "));
  EXPECT_THAT(set.summary.message, HasSubstr("(10 x noise std 0.02"));
  EXPECT_TRUE(set.hits.empty());
}

TEST(Hits, NegativePulsesHintAtAnInvertedChannel) {
  const auto pulses = five_hits();
  const TapRecord r = record(pulses, 1.3);
  const HitSet set = detect_hits(-r.force_n, r.response, kFs);
  EXPECT_FALSE(set.summary.ok());
  EXPECT_THAT(set.summary.message, HasSubstr("is the hammer channel's sign inverted?"));
}

TEST(Hits, HitTooCloseToTheEndIsRejected) {
  auto pulses = five_hits();
  pulses.push_back({1.31, 100.0, 2e-4});  // 0.03 s before the end of a 1.34 s record
  const TapRecord r = record(pulses, 1.34);
  const HitSet set = detect_hits(r.force_n, r.response, kFs);
  ASSERT_EQ(set.hits.size(), 6u);
  EXPECT_EQ(set.accepted_count(), 5);
  // 0.03 s plus the 1 ms pre-trigger, less the trigger's lag.
  EXPECT_THAT(set.hits[5].rejection, StartsWith("record too short: only 0.03"));
  EXPECT_NEAR(std::stod(set.hits[5].rejection.substr(23)), 0.031, kTriggerTolS);
  EXPECT_NEAR(static_cast<double>(set.record_samples), 6400.0, 2.0);
}

TEST(Hits, GivenWindowsMatchAutomaticDetection) {
  const auto pulses = five_hits();
  const TapRecord r = record(pulses, 1.3);
  const HitSet automatic = detect_hits(r.force_n, r.response, kFs);
  std::vector<std::array<double, 2>> windows;
  for (const HammerPulse& p : pulses) windows.push_back({p.time_s - 0.01, p.time_s + 0.2});
  windows.push_back({1.27, 1.29});  // no hit in this one
  const HitSet given = hits_from_windows(r.force_n, r.response, kFs, windows);
  ASSERT_TRUE(given.summary.ok());
  EXPECT_EQ(given.accepted_count(), 5);
  EXPECT_EQ(given.record_samples, 512);  // the shortest window, 0.02 s
  for (size_t i = 0; i < 5; ++i) EXPECT_EQ(given.hits[i].trigger, automatic.hits[i].trigger);
  EXPECT_THAT(given.hits[5].rejection, StartsWith("no force above the threshold"));
}

TEST(Hits, BadInputIsRejected) {
  const Eigen::VectorXd a = Eigen::VectorXd::Zero(100);
  const Eigen::VectorXd b = Eigen::VectorXd::Zero(99);
  try {
    detect_hits(a, b, kFs);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "tap force has 100 samples, response 99: must be equal");
  }
  Eigen::VectorXd nan = a;
  nan[7] = std::nan("");
  try {
    detect_hits(nan, a, kFs);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), StartsWith("tap sample 7 (force nan"));
  }
  HitOptions o;
  o.threshold_fraction = 1.5;
  try {
    detect_hits(a, a, kFs, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "hits.threshold_fraction = 1.500000: must be in (0, 1)");
  }
  try {
    hits_from_windows(a, a, 1000.0, {{0.05, 0.2}});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(
        e.what(),
        "hits[0] = [0.05, 0.2] s: must satisfy 0 <= start < end <= 0.1 s (the data length)");
  }
}

}  // namespace
}  // namespace frf
}  // namespace chatterlab
