// Observability of the grinding model (analysis/grinding/observability.h): 002 table I at
// operating points drawn from the trajectory of 002 sec. V, the format's four estimator
// settings, and the loss of x1 at x2 = 0 (spec notes on 002, section 3).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "analysis/common/summary.h"
#include "analysis/grinding/grinding_synth.h"
#include "analysis/grinding/observability.h"

namespace chatterlab {
namespace grinding {
namespace {

// More than ten points (002 sec. III: "more than ten operating points taken at random").
constexpr int kPoints = 25;

void record(const std::string& key, double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", value);
  ::testing::Test::RecordProperty(key, buf);
}

// The 10-cycle series of 002 sec. V with table III case B process noise (x2 noise 4e-11 per
// step, so v stays positive through most of the spark-out) and R0 stepping.
const GrindingSeries& series() {
  static const GrindingSeries g = [] {
    GrindingSeriesSpec s;
    s.process_var = {0.04, 4e-11, 4e-9};
    s.seed = 3;
    return synthesize_grinding_series(s);
  }();
  return g;
}

TrajectoryObservability along(const ObservabilityCase& c, std::uint64_t seed) {
  const GrindingSeries& g = series();
  GrindingParameters p;  // the lab's nominal model (002 table II)
  return observability_along_trajectory(g.truth_trajectory, g.record.u_mm_s, p, c.states,
                                        c.channels, kPoints, seed, {});
}

// The margins of the rank decision: a full rank's smallest relative singular value stays
// above kFullMargin (measured: >= 4.3e-5 over every row of this series, at case 2 "P + (d_s,
// R_a)" late in spark-out) and a deficient rank's dropped ones below kZeroLevel (structural
// zeros: a zero column of O~), both far from the default tolerance 1e-9.
constexpr double kFullMargin = 1e-6;
constexpr double kZeroLevel = 1e-15;

void expect_rank(const ObservabilityCase& c, int expected_rank, std::uint64_t seed) {
  const TrajectoryObservability t = along(c, seed);
  ASSERT_EQ(static_cast<int>(t.points.size()), kPoints) << c.name;
  for (const ObservabilityPoint& pt : t.points) {
    EXPECT_GT(series().truth_trajectory(pt.row, kV), 0.0) << c.name;
    EXPECT_EQ(pt.result.rank, expected_rank) << c.name << " at row " << pt.row;
    EXPECT_EQ(pt.result.states, c.states);
  }
  EXPECT_EQ(t.min_rank, expected_rank) << c.name;
  EXPECT_EQ(t.max_rank, expected_rank) << c.name;
  EXPECT_GT(t.smallest_kept, kFullMargin) << c.name;
  EXPECT_LE(t.largest_dropped, kZeroLevel) << c.name;
  record(std::string(c.name) + " smallest kept", t.smallest_kept);
  record(std::string(c.name) + " largest dropped", t.largest_dropped);
}

TEST(GrindingObservability, TableIIsReproduced) {
  const std::array<ObservabilityCase, 4> cases = table_i_cases();
  // 002 table I: case 1 "P, D_w" deficient (x3 unseen: rank 2 of 3), "P + (d_s)" full (3);
  // case 2 "P, D_w + (d_s)" deficient (R0 unseen: 3 of 4), "P + (d_s, R_a)" full (4).
  EXPECT_EQ(cases[0].states, 3);
  EXPECT_EQ(cases[2].states, 4);
  expect_rank(cases[0], 2, 1);
  expect_rank(cases[1], 3, 2);
  expect_rank(cases[2], 3, 3);
  expect_rank(cases[3], 4, 4);
}

TEST(GrindingObservability, TableIHoldsAtEveryRowWithPositiveX1AndX2) {
  // Not only at 25 random points: at every row of the series with x1, x2 > 0.
  const GrindingSeries& g = series();
  GrindingParameters p;
  const std::array<int, 4> ranks{2, 3, 3, 4};
  const std::array<ObservabilityCase, 4> cases = table_i_cases();
  for (std::size_t k = 0; k < 4; ++k) {
    const TrajectoryObservability t = observability_along_trajectory(
        g.truth_trajectory, g.record.u_mm_s, p, cases[k].states, cases[k].channels, 1 << 30, 1);
    EXPECT_GT(t.points.size(), 8000u);  // of 8510 rows; x2 = 0 at each cycle's j = 0
    EXPECT_EQ(t.min_rank, ranks[k]) << cases[k].name;
    EXPECT_EQ(t.max_rank, ranks[k]) << cases[k].name;
    EXPECT_GT(t.smallest_kept, kFullMargin) << cases[k].name;
    EXPECT_LE(t.largest_dropped, kZeroLevel) << cases[k].name;
  }
}

TEST(GrindingObservability, FormatEstimatorSettings) {
  // Format section 7 (002 table I with D_w kept, notes A10): x-inprocess (P, D_w) 2 of 3,
  // x (P, D_w, d_s) 3 of 3, xr-inprocess (P, D_w, d_s; R0) 3 of 4, xr (P, D_w, d_s, R_a; R0)
  // 4 of 4.
  const std::array<std::pair<GrindingEstimatorId, int>, 4> expected{{
      {GrindingEstimatorId::kXInprocess, 2},
      {GrindingEstimatorId::kX, 3},
      {GrindingEstimatorId::kXrInprocess, 3},
      {GrindingEstimatorId::kXr, 4},
  }};
  for (const auto& [id, rank] : expected) {
    const ObservabilityCase c = estimator_observability_case(id);
    EXPECT_TRUE(c.channels.power && c.channels.Dw) << c.name;
    expect_rank(c, rank, 10 + static_cast<std::uint64_t>(rank));
  }
  EXPECT_STREQ(estimator_observability_case(GrindingEstimatorId::kXr).name, "multirate-ekf-xr");
}

TEST(GrindingObservability, X1IsLostAtZeroInfeed) {
  // Notes section 3: dP/dx1 = K_s s1 x2 vanishes at x2 = 0, so case 1 "P + (d_s)" drops to
  // rank 2 there (and D_w restores it).
  GrindingParameters p;
  const ProcessState X(100.0, 0.0, 49.99, 3.0);
  const ObservabilityCase c = table_i_cases()[1];
  EXPECT_EQ(grinding_observability(X, 0.0, p, c.states, c.channels).rank, 2);
  GrindingChannels with_Dw = c.channels;
  with_Dw.Dw = true;
  EXPECT_EQ(grinding_observability(X, 0.0, p, c.states, with_Dw).rank, 3);
  // The format's guard sets dP/dx1 = 0 at x1 <= 0: at row j = 1 of the noise-free cycle 1
  // (x1 = 0 exactly, x2 = T_f u / tau > 0) P does not see x1 either, so the trajectory draws
  // skip x1 <= 0.
  const ProcessState X1(0.0, 0.02 * 0.0254 / p.tau_s, 50.0, 3.6);
  EXPECT_EQ(grinding_observability(X1, 0.0254, p, c.states, c.channels).rank, 2);
  EXPECT_EQ(grinding_observability(X1, 0.0254, p, c.states, with_Dw).rank, 3);
}

TEST(GrindingObservability, RankDoesNotDependOnTheScaling) {
  // Scaling changes no rank: unit scales (time in tau still) give the same ranks at a
  // roughing point and at the end of spark-out.
  GrindingParameters p;
  GrindingObservabilityOptions unit;
  unit.state_scale.setOnes();
  unit.output_scale.setOnes();
  unit.relative_tolerance = 1e-13;  // unscaled entries span more decades
  const std::array<int, 4> ranks{2, 3, 3, 4};
  for (const ProcessState& X :
       {ProcessState(120.0, 0.02, 49.99, 3.3), ProcessState(54.6, 3.2e-4, 49.99, 3.6)}) {
    for (std::size_t k = 0; k < 4; ++k) {
      const ObservabilityCase c = table_i_cases()[k];
      EXPECT_EQ(grinding_observability(X, 0.0254, p, c.states, c.channels).rank, ranks[k])
          << c.name;
      EXPECT_EQ(grinding_observability(X, 0.0254, p, c.states, c.channels, unit).rank, ranks[k])
          << c.name << " unscaled";
    }
  }
}

TEST(GrindingObservability, PointsAreDrawnReproducibly) {
  const ObservabilityCase c = table_i_cases()[3];
  const TrajectoryObservability a = along(c, 5), b = along(c, 5), d = along(c, 6);
  ASSERT_EQ(a.points.size(), b.points.size());
  bool differ = false;
  for (std::size_t k = 0; k < a.points.size(); ++k) {
    EXPECT_EQ(a.points[k].row, b.points[k].row);
    if (k > 0) {
      EXPECT_LT(a.points[k - 1].row, a.points[k].row);  // distinct, in row order
    }
    differ = differ || a.points[k].row != d.points[k].row;
  }
  EXPECT_TRUE(differ);
}

TEST(GrindingObservability, RejectsBadInput) {
  GrindingParameters p;
  const ProcessState X(100.0, 0.01, 49.99, 3.0);
  EXPECT_THROW(grinding_observability(X, 0.0, p, 5, {true, true, false, false}), InputError);
  EXPECT_THROW(grinding_observability(X, 0.0, p, 3, {}), InputError);
  const GrindingSeries& g = series();
  EXPECT_THROW(observability_along_trajectory(g.truth_trajectory, Eigen::VectorXd(3), p, 3,
                                              {true, false, true, false}, kPoints, 1),
               InputError);
  Eigen::MatrixX4d still = g.truth_trajectory;
  still.col(kV).setZero();
  EXPECT_THROW(observability_along_trajectory(still, g.record.u_mm_s, p, 3,
                                              {true, false, true, false}, kPoints, 1),
               InputError);
}

}  // namespace
}  // namespace grinding
}  // namespace chatterlab
