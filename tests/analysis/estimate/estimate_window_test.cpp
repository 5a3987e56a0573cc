// The estimation window rule (estimation_window.h) against windows worked out by hand for the
// 000 sec. 5.2 cut (15,000 rpm: T = 4 ms a revolution; two teeth: tau = 2 ms chip delay; window
// 0.2 s + tau = 0.202 s; 20 settling revolutions = 0.08 s).
#include <gtest/gtest.h>

#include <string>

#include "analysis/common/summary.h"
#include "analysis/estimate/estimation_window.h"

namespace chatterlab {
namespace estimate {
namespace {

constexpr double kRpm = 15000.0;
constexpr int kTeeth = 2;
constexpr double kTimeTol = 1e-12;   // s: sums of a few values of order 1 s
constexpr double kDepthTol = 1e-15;  // m

dynamics::BifurcationResult measured(std::optional<double> depth_m, dynamics::RunVerdict v) {
  dynamics::BifurcationResult b;
  b.summary.succeed();
  b.bifurcation_depth_m = depth_m;
  b.verdict = v;
  return b;
}

TEST(EstimationWindow, ConstantDepthEndsOneRevolutionBeforeTheCutEnds) {
  const sync::CutSchedule cut{0.2, 1.2, 1e-3, 1e-3};
  const EstimationWindow w = choose_estimation_window(cut, kRpm, kTeeth, std::nullopt, nullptr);
  EXPECT_NEAR(w.end_s, 1.196, kTimeTol);    // 1.2 - 0.004
  EXPECT_NEAR(w.start_s, 0.994, kTimeTol);  // 1.196 - 0.202
  EXPECT_EQ(w.depth_start_m, 1e-3);
  EXPECT_EQ(w.depth_end_m, 1e-3);
  EXPECT_EQ(w.rule, "the last 0.2 s of the constant-depth cut");
  EXPECT_TRUE(w.warnings.empty());
}

TEST(EstimationWindow, RampIsCentredAtThreeQuartersOfTheMeasuredBifurcationDepth) {
  // 0 to 4 mm over 0.2 .. 2.2 s, bifurcation at 3 mm: target 2.25 mm, reached at
  // 0.2 + 2 * 2.25 / 4 = 1.325 s; the window runs 1.325 -+ 0.101 s.
  const sync::CutSchedule cut{0.2, 2.2, 0.0, 4e-3};
  const auto b = measured(3e-3, dynamics::RunVerdict::kChanges);
  const EstimationWindow w = choose_estimation_window(cut, kRpm, kTeeth, std::nullopt, &b);
  EXPECT_NEAR(w.start_s, 1.224, kTimeTol);
  EXPECT_NEAR(w.end_s, 1.426, kTimeTol);
  EXPECT_NEAR(w.depth_start_m, cut.depth_at_m(1.224), kDepthTol);
  EXPECT_NEAR(w.depth_end_m, cut.depth_at_m(1.426), kDepthTol);
  EXPECT_NEAR(0.5 * (w.depth_start_m + w.depth_end_m), 2.25e-3, kDepthTol);
  EXPECT_EQ(w.rule, "centred at 3/4 of the measured bifurcation depth");
  EXPECT_TRUE(w.warnings.empty());
}

TEST(EstimationWindow, RampWithoutBifurcationIsCentredAtThreeQuartersOfTheDeepest) {
  // Target 3 mm: 0.2 + 2 * 3 / 4 = 1.7 s. No detector result and a run that never changes
  // state give the same window.
  const sync::CutSchedule cut{0.2, 2.2, 0.0, 4e-3};
  const auto stable = measured(std::nullopt, dynamics::RunVerdict::kAllStable);
  const dynamics::BifurcationResult* cases[] = {&stable, nullptr};
  for (const dynamics::BifurcationResult* b : cases) {
    const EstimationWindow w = choose_estimation_window(cut, kRpm, kTeeth, std::nullopt, b);
    EXPECT_NEAR(w.start_s, 1.599, kTimeTol);
    EXPECT_NEAR(w.end_s, 1.801, kTimeTol);
    EXPECT_EQ(w.rule, "centred at 3/4 of the deepest depth (no bifurcation measured)");
  }
}

TEST(EstimationWindow, RampThatChattersThroughoutSitsNearTheShallowEndWithAWarning) {
  // A decline from 4 to 0 mm: target 1/4 up from the shallowest, 1 mm, at
  // 0.2 + 2 * (1 - 4) / (0 - 4) = 1.7 s.
  const sync::CutSchedule cut{0.2, 2.2, 4e-3, 0.0};
  const auto b = measured(std::nullopt, dynamics::RunVerdict::kAllChatter);
  const EstimationWindow w = choose_estimation_window(cut, kRpm, kTeeth, std::nullopt, &b);
  EXPECT_NEAR(w.start_s, 1.599, kTimeTol);
  EXPECT_NEAR(w.end_s, 1.801, kTimeTol);
  EXPECT_EQ(w.rule, "centred near the shallow end (the run chatters throughout)");
  ASSERT_EQ(w.warnings.size(), 1u);
  EXPECT_EQ(w.warnings[0],
            "estimation: the bifurcation detector finds chatter over the whole run; the filters' "
            "model assumes chatter-free cutting");
}

TEST(EstimationWindow, ShortCutShortensTheWindowWithAWarning) {
  // Settled cutting from 0.28 s (20 revolutions after 0.2 s) to 0.446 s (one revolution before
  // 0.45 s): 0.166 s, of which 0.164 s after the chip delay.
  const sync::CutSchedule cut{0.2, 0.45, 1e-3, 1e-3};
  const EstimationWindow w = choose_estimation_window(cut, kRpm, kTeeth, std::nullopt, nullptr);
  EXPECT_NEAR(w.start_s, 0.28, kTimeTol);
  EXPECT_NEAR(w.end_s, 0.446, kTimeTol);
  ASSERT_EQ(w.warnings.size(), 1u);
  EXPECT_EQ(w.warnings[0],
            "estimation: the cut holds 0.164 s of settled cutting, less than estimation.window_s "
            "= 0.2 s");
}

TEST(EstimationWindow, GivenWindowIsUsedAsItIs) {
  const sync::CutSchedule cut{0.2, 2.2, 0.0, 4e-3};
  const EstimationWindow w =
      choose_estimation_window(cut, kRpm, kTeeth, std::make_pair(0.5, 0.6), nullptr);
  EXPECT_EQ(w.start_s, 0.5);
  EXPECT_EQ(w.end_s, 0.6);
  EXPECT_NEAR(w.depth_start_m, 0.6e-3, kDepthTol);
  EXPECT_NEAR(w.depth_end_m, 0.8e-3, kDepthTol);
  EXPECT_EQ(w.rule, "test.yaml estimation_window_s");
}

TEST(EstimationWindow, FourRevolutionsOrLessIsAnError) {
  // Settled cutting 0.28 .. 0.295 s: 3.75 revolutions.
  try {
    choose_estimation_window({0.2, 0.299, 1e-3, 1e-3}, kRpm, kTeeth, std::nullopt, nullptr);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "estimation window 0.28 to 0.295 s: the filters need at least four revolutions "
                 "of settled cutting (after 20 settling revolutions)");
  }
}

TEST(EstimationWindow, BadOptionsNameTheField) {
  EstimationWindowOptions o;
  o.window_s = 0.0;
  try {
    choose_estimation_window({0.2, 1.2, 1e-3, 1e-3}, kRpm, kTeeth, std::nullopt, nullptr, o);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "estimation.window_s = 0: must be > 0");
  }
  o = EstimationWindowOptions{};
  o.settle_revolutions = -1.0;
  EXPECT_THROW(
      choose_estimation_window({0.2, 1.2, 1e-3, 1e-3}, kRpm, kTeeth, std::nullopt, nullptr, o),
      InputError);
  EXPECT_THROW(choose_estimation_window({0.2, 1.2, 1e-3, 1e-3}, kRpm, 0, std::nullopt, nullptr),
               InputError);
}

TEST(WindowSamples, TakesTheSamplesInsideTheWindowWithTheirDepth) {
  // Sample i of a 1 kHz record holds i: the window 10.5 .. 20.5 ms holds samples 11 .. 20.
  const Eigen::VectorXd ramp = Eigen::VectorXd::LinSpaced(100, 0.0, 99.0);
  EstimationWindow w;
  w.start_s = 0.0105;
  w.end_s = 0.0205;
  const sync::CutSchedule flat{0.0, 0.1, 1e-3, 1e-3};
  const MeasuredCut c = window_samples(ramp, 2 * ramp, 3 * ramp, 1000.0, flat, w);
  EXPECT_EQ(c.time_step_s, 1e-3);
  ASSERT_EQ(c.x_m.size(), 10);
  EXPECT_EQ(c.x_m[0], 11.0);
  EXPECT_EQ(c.x_m[9], 20.0);
  EXPECT_EQ(c.y_m[0], 22.0);
  EXPECT_EQ(c.theta1_rad[9], 60.0);
  ASSERT_EQ(c.depth_m.size(), 1);  // constant depth: one value
  EXPECT_EQ(c.depth_m[0], 1e-3);
  const sync::CutSchedule ramped{0.0, 0.1, 0.0, 1e-3};  // 0.01 mm per ms
  const MeasuredCut r = window_samples(ramp, ramp, ramp, 1000.0, ramped, w);
  ASSERT_EQ(r.depth_m.size(), 10);
  EXPECT_NEAR(r.depth_m[0], 0.11e-3, kDepthTol);
  EXPECT_NEAR(r.depth_m[9], 0.20e-3, kDepthTol);
}

TEST(WindowSamples, WindowOutsideTheRecordIsAnError) {
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(100);
  EstimationWindow w;
  w.start_s = 5.0;
  w.end_s = 6.0;
  try {
    window_samples(v, v, v, 1000.0, {0.0, 0.1, 1e-3, 1e-3}, w);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "estimation window 5 to 6 s lies outside the record");
  }
  EXPECT_THROW(window_samples(v, v.head(50), v, 1000.0, {0.0, 0.1, 1e-3, 1e-3}, w), InputError);
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
