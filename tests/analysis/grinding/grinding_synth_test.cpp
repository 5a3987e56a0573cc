// Synthetic grinding series (analysis/grinding/grinding_synth.h, 002 sec. V): the record layout
// of the format's section 7, determinism for a seed, the noise of every channel against its
// specification, missing and late inspections, D_w and x1 restarting after a dressing, and the
// truth kept at the cycle ends against the trajectory.
#include "analysis/grinding/grinding_synth.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace grinding {
namespace {

GrindingSeriesSpec noise_free_spec() {
  GrindingSeriesSpec s;
  s.truth.vw_m_s = 0.533;
  s.truth.rm_um = 2.4;
  s.truth.r0 = 1.0;
  s.R0_walk_var_um2 = 0.0;
  s.R0_cycle_var_um2 = 0.0;
  s.process_var = {0.0, 0.0, 0.0};
  s.power_sd_W = s.Dw_sd_mm = s.ds_sd_mm = s.Ra_sd_um = s.roundness_sd_um = 0.0;
  return s;
}

// 002 table III case A process noise and the format's measurement noise.
GrindingSeriesSpec noisy_spec() {
  GrindingSeriesSpec s = noise_free_spec();
  s.process_var = {0.04, 4e-9, 4e-9};
  s.R0_walk_var_um2 = 4e-9;
  s.R0_cycle_var_um2 = 1e-4;
  s.power_sd_W = 100;
  s.Dw_sd_mm = 0.01;
  s.ds_sd_mm = 0.001;
  s.Ra_sd_um = 0.01;
  s.roundness_sd_um = 0.1;
  s.seed = 7;
  return s;
}

Eigen::Index first_row(const GrindingSeries& g, int cycle) {
  Eigen::Index r = 0;
  for (int i = 1; i < cycle; ++i) r += g.n[static_cast<std::size_t>(i - 1)] + 1;
  return r;
}

// Sample mean and standard deviation.
struct Stats {
  double mean = 0.0, sd = 0.0;
  long count = 0;
};
Stats stats(const std::vector<double>& v) {
  Stats s;
  s.count = static_cast<long>(v.size());
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  double ss = 0.0;
  for (double x : v) ss += (x - s.mean) * (x - s.mean);
  s.sd = std::sqrt(ss / static_cast<double>(v.size() - 1));
  return s;
}

// A sample sd of N normal draws has relative standard error ~ 1 / sqrt(2 (N - 1)) and a sample
// mean standard error sd / sqrt(N); checks allow kSigmas of these.
constexpr double kSigmas = 4.5;
void expect_normal(const std::vector<double>& residuals, double sd, const char* what) {
  const Stats s = stats(residuals);
  const double n = static_cast<double>(s.count);
  EXPECT_NEAR(s.sd, sd, kSigmas * sd / std::sqrt(2.0 * (n - 1.0))) << what << " (" << n << ")";
  EXPECT_NEAR(s.mean, 0.0, kSigmas * sd / std::sqrt(n)) << what;
}

TEST(GrindingSynth, RecordLayoutFollowsTheFormat) {
  const GrindingSeries g = synthesize_grinding_series(noise_free_spec());
  ASSERT_EQ(g.n.size(), 10u);
  for (int n : g.n) EXPECT_EQ(n, 850);  // 475 + 190 + 185 (002 sec. V)
  const Eigen::Index rows = 10 * 851;
  ASSERT_EQ(static_cast<Eigen::Index>(g.record.cycle.size()), rows);
  ASSERT_EQ(g.record.u_mm_s.size(), rows);
  ASSERT_EQ(g.record.power_W.size(), rows);
  ASSERT_EQ(g.record.Dw_mm.size(), rows);
  ASSERT_EQ(g.truth_trajectory.rows(), rows);
  for (int i = 1; i <= 10; ++i) {
    const Eigen::Index r0 = first_row(g, i);
    for (int j = 0; j <= 850; ++j) {
      ASSERT_EQ(g.record.cycle[static_cast<std::size_t>(r0 + j)], i);
      // The commanded u of the row; row n_i carries the last stage's (unused).
      const double u = j < 475 ? 0.0254 : (j < 665 ? 0.002 : 0.0);
      ASSERT_EQ(g.record.u_mm_s[r0 + j], u) << i << ", " << j;
    }
    EXPECT_EQ(g.truth_trajectory(r0, kV), 0.0) << "x2(i, 0) = 0 (002 notes 7.1)";
  }
}

TEST(GrindingSynth, NoiseFreeSeriesMatchesTheModel) {
  const GrindingSeriesSpec spec = noise_free_spec();
  const GrindingSeries g = synthesize_grinding_series(spec);
  // Reference: 002 eq. 8 run here step by step with the model, the transitions of eq. 12.
  ProcessState X(0.0, 0.0, spec.ds_start_mm, spec.R0_start_um);
  Eigen::Index row = 0;
  for (int i = 1; i <= 10; ++i) {
    X[kV] = 0.0;
    for (int j = 0; j <= 850; ++j, ++row) {
      ASSERT_EQ(g.truth_trajectory.row(row), X.transpose()) << i << ", " << j;
      const Outputs y = outputs(X, spec.truth);
      ASSERT_EQ(g.record.power_W[row], y[kPower]);
      ASSERT_EQ(g.record.Dw_mm[row], y[kDw]);
      if (j < 850) X = euler_step(X, g.record.u_mm_s[row], spec.sample_period_s, spec.truth);
    }
  }
  // d_s falls monotonically (within and across cycles; 002 notes 7.1).
  for (Eigen::Index r = 1; r < g.truth_trajectory.rows(); ++r)
    ASSERT_LE(g.truth_trajectory(r, kDs), g.truth_trajectory(r - 1, kDs));
  // The noise-free inspections are the true outputs at (i, n_i) (eq. 10).
  ASSERT_EQ(g.inspections.size(), 10u);
  for (const Inspection& ins : g.inspections) {
    const int i = ins.cycle;
    EXPECT_EQ(ins.available_cycle, i);
    EXPECT_EQ(ins.ds_mm, g.truth_at_cycle_end(i - 1, kDs));
    EXPECT_EQ(ins.Ra_um, g.Ra_true_um[i - 1]);
    EXPECT_EQ(ins.roundness_um, g.roundness_true_um[i - 1]);
  }
  // Notes section 5 [derived]: end-of-cycle R_a with R0 = 3.6 of 0.89 um (cycle 1) and
  // 0.33 um (cycle 10), r = 2.53 um; half a unit of the last digit.
  EXPECT_NEAR(g.Ra_true_um[0], 0.89, 0.005);
  EXPECT_NEAR(g.Ra_true_um[9], 0.33, 0.005);
  EXPECT_NEAR(g.roundness_true_um[0], 2.53, 0.005);
  EXPECT_EQ(g.negative_v_steps, 0);
}

TEST(GrindingSynth, TruthAtCycleEndIsTheTrajectoryAtNi) {
  const GrindingSeriesSpec spec = noisy_spec();
  const GrindingSeries g = synthesize_grinding_series(spec);
  ASSERT_EQ(g.truth_at_cycle_end.rows(), 10);
  // With 002 table III's v noise (stationary sd 3.9e-4 mm/s) the true v goes below 0 during
  // spark-out, where the noise-free v falls to 3.2e-4 mm/s (002 notes A6); the model's guards
  // keep every value finite.
  EXPECT_GT(g.negative_v_steps, 0);
  EXPECT_TRUE(g.truth_trajectory.allFinite());
  EXPECT_TRUE(g.record.power_W.allFinite());
  for (int i = 1; i <= 10; ++i) {
    const Eigen::Index end = first_row(g, i) + g.n[static_cast<std::size_t>(i - 1)];
    EXPECT_EQ(g.truth_at_cycle_end.row(i - 1), g.truth_trajectory.row(end)) << i;
    const Outputs y = outputs(g.truth_at_cycle_end.row(i - 1).transpose(), spec.truth);
    EXPECT_EQ(g.Ra_true_um[i - 1], y[kRa]);
    EXPECT_EQ(g.roundness_true_um[i - 1],
              roundness_um(g.truth_at_cycle_end.row(i - 1).transpose(), spec.truth));
    if (i == 1) {
      EXPECT_EQ(g.truth_trajectory.row(0), ProcessState(0.0, 0.0, 50.0, 3.6).transpose());
      continue;
    }
    // New cycle (002 eq. 12): x2 = 0, x1 and x3 carried over exactly; R0 stepped.
    const Eigen::Index start = first_row(g, i);
    EXPECT_EQ(g.truth_trajectory(start, kV), 0.0);
    EXPECT_EQ(g.truth_trajectory(start, kVw), g.truth_at_cycle_end(i - 2, kVw));
    EXPECT_EQ(g.truth_trajectory(start, kDs), g.truth_at_cycle_end(i - 2, kDs));
    EXPECT_NE(g.truth_trajectory(start, kR0), g.truth_at_cycle_end(i - 2, kR0));
  }
}

TEST(GrindingSynth, DeterministicForASeed) {
  GrindingSeriesSpec spec = noisy_spec();
  spec.late = {{2, 4}};
  spec.dressings = {{5, 0.04}};
  const GrindingSeries a = synthesize_grinding_series(spec);
  const GrindingSeries b = synthesize_grinding_series(spec);
  EXPECT_EQ(a.record.cycle, b.record.cycle);
  EXPECT_EQ(a.record.u_mm_s, b.record.u_mm_s);
  EXPECT_EQ(a.record.power_W, b.record.power_W);
  EXPECT_EQ(a.record.Dw_mm, b.record.Dw_mm);
  EXPECT_EQ(a.truth_trajectory, b.truth_trajectory);
  ASSERT_EQ(a.inspections.size(), b.inspections.size());
  for (std::size_t k = 0; k < a.inspections.size(); ++k) {
    EXPECT_EQ(a.inspections[k].ds_mm, b.inspections[k].ds_mm);
    EXPECT_EQ(a.inspections[k].Ra_um, b.inspections[k].Ra_um);
    EXPECT_EQ(a.inspections[k].roundness_um, b.inspections[k].roundness_um);
  }
  spec.seed = 8;
  const GrindingSeries c = synthesize_grinding_series(spec);
  EXPECT_NE(a.record.power_W, c.record.power_W);
  EXPECT_NE(a.truth_trajectory, c.truth_trajectory);
  // Each noise has its own stream: without process noise the same seed gives the same
  // measurement noise (power residuals), and dropping inspections leaves the others unchanged.
  GrindingSeriesSpec quiet = noisy_spec();
  quiet.process_var = {0.0, 0.0, 0.0};
  quiet.R0_walk_var_um2 = quiet.R0_cycle_var_um2 = 0.0;
  GrindingSeriesSpec fewer = quiet;
  fewer.uninspected_cycles = {1, 3};
  const GrindingSeries q = synthesize_grinding_series(quiet);
  const GrindingSeries f = synthesize_grinding_series(fewer);
  const GrindingSeries clean = synthesize_grinding_series(noise_free_spec());
  const GrindingSeries noisy = synthesize_grinding_series(noisy_spec());
  EXPECT_EQ((q.record.power_W - clean.record.power_W).eval(),
            (f.record.power_W - clean.record.power_W).eval());
  EXPECT_NE(noisy.truth_trajectory, clean.truth_trajectory);
  ASSERT_EQ(f.inspections.size(), 8u);
  for (const Inspection& ins : f.inspections)
    EXPECT_EQ(ins.ds_mm, q.inspections[static_cast<std::size_t>(ins.cycle - 1)].ds_mm);
}

TEST(GrindingSynth, FastChannelNoiseHasTheSpecifiedSd) {
  const GrindingSeriesSpec spec = noisy_spec();
  const GrindingSeries g = synthesize_grinding_series(spec);
  std::vector<double> eP, eD;
  for (Eigen::Index r = 0; r < g.truth_trajectory.rows(); ++r) {
    const Outputs y = outputs(g.truth_trajectory.row(r).transpose(), spec.truth);
    eP.push_back(g.record.power_W[r] - y[kPower]);
    eD.push_back(g.record.Dw_mm[r] - y[kDw]);
  }
  // 8510 rows: the sd is checked within 4.5 * 0.77 % = 3.4 % of its spec.
  expect_normal(eP, spec.power_sd_W, "power");
  expect_normal(eD, spec.Dw_sd_mm, "Dw");
  // The two channels' noises are independent: sample correlation within 4.5 / sqrt(N).
  double c = 0.0;
  for (std::size_t k = 0; k < eP.size(); ++k) c += eP[k] * eD[k];
  c /= static_cast<double>(eP.size()) * spec.power_sd_W * spec.Dw_sd_mm;
  EXPECT_LT(std::abs(c), kSigmas / std::sqrt(static_cast<double>(eP.size())));
}

// Many short cycles (30 rows each) for the per-step and per-cycle noises.
GrindingSeriesSpec many_short_cycles() {
  GrindingSeriesSpec s = noisy_spec();
  s.cycles = 1000;
  s.schedule = {{0.0254, 20}, {0.0, 10}};
  s.seed = 11;
  return s;
}

TEST(GrindingSynth, InspectionNoiseHasTheSpecifiedSd) {
  const GrindingSeriesSpec spec = many_short_cycles();
  const GrindingSeries g = synthesize_grinding_series(spec);
  ASSERT_EQ(g.inspections.size(), 1000u);
  std::vector<double> eds, eRa, er;
  for (const Inspection& ins : g.inspections) {
    eds.push_back(ins.ds_mm - g.truth_at_cycle_end(ins.cycle - 1, kDs));
    eRa.push_back(ins.Ra_um - g.Ra_true_um[ins.cycle - 1]);
    er.push_back(ins.roundness_um - g.roundness_true_um[ins.cycle - 1]);
  }
  // 1000 values: the sd within 4.5 * 2.2 % = 10 % of its spec.
  expect_normal(eds, spec.ds_sd_mm, "ds");
  expect_normal(eRa, spec.Ra_sd_um, "Ra");
  expect_normal(er, spec.roundness_sd_um, "roundness");
}

TEST(GrindingSynth, ProcessNoiseAndR0StepsHaveTheSpecifiedVariance) {
  const GrindingSeriesSpec spec = many_short_cycles();
  const GrindingSeries g = synthesize_grinding_series(spec);
  // Per fast step: X(i, j+1) - F_d(X(i, j)) ~ N(0, diag(process_var, R0_walk_var)) (002 eq. 8).
  std::vector<std::vector<double>> step(4);
  std::vector<double> cycle_step;
  Eigen::Index r = 0;
  for (int i = 1; i <= spec.cycles; ++i) {
    const int n_i = g.n[static_cast<std::size_t>(i - 1)];
    if (i > 1) cycle_step.push_back(g.truth_trajectory(r, kR0) - g.truth_trajectory(r - 1, kR0));
    for (int j = 0; j < n_i; ++j, ++r) {
      const ProcessState X = g.truth_trajectory.row(r).transpose();
      const ProcessState pred = euler_step(X, g.record.u_mm_s[r], spec.sample_period_s, spec.truth);
      for (int c = 0; c < 4; ++c) step[c].push_back(g.truth_trajectory(r + 1, c) - pred[c]);
    }
    ++r;  // row n_i
  }
  // 30000 steps: sd within 4.5 * 0.41 % = 1.8 %. (d_s steps are ~6e-5 mm on 50 mm: the
  // rounding of x3 + noise, ~1e-14 mm, is far below.)
  expect_normal(step[kVw], std::sqrt(spec.process_var[0]), "Vw");
  expect_normal(step[kV], std::sqrt(spec.process_var[1]), "v");
  expect_normal(step[kDs], std::sqrt(spec.process_var[2]), "ds");
  expect_normal(step[kR0], std::sqrt(spec.R0_walk_var_um2), "R0 walk");
  // Per new cycle (no propagation): R0 + N(0, R0_cycle_var) (002 sec. V); 999 steps.
  expect_normal(cycle_step, std::sqrt(spec.R0_cycle_var_um2), "R0 cycle step");
}

TEST(GrindingSynth, MissingLateAndUnmeasuredInspections) {
  GrindingSeriesSpec spec = noisy_spec();
  spec.uninspected_cycles = {3, 7};
  spec.late = {{2, 4}, {5, 12}, {10, 10}};
  spec.ds_unmeasured_cycles = {4};
  spec.Ra_unmeasured_cycles = {6, 8};
  spec.truth.r0 = std::numeric_limits<double>::quiet_NaN();  // no roundness model
  const GrindingSeries g = synthesize_grinding_series(spec);
  std::vector<int> cycles;
  for (const Inspection& ins : g.inspections) cycles.push_back(ins.cycle);
  EXPECT_EQ(cycles, (std::vector<int>{1, 2, 4, 5, 6, 8, 9, 10}));
  for (const Inspection& ins : g.inspections) {
    const int i = ins.cycle;
    const int expected_available = i == 2 ? 4 : (i == 5 ? 12 : i);
    EXPECT_EQ(ins.available_cycle, expected_available) << i;
    EXPECT_EQ(std::isnan(ins.ds_mm), i == 4) << i;
    EXPECT_EQ(std::isnan(ins.Ra_um), i == 6 || i == 8) << i;
    EXPECT_TRUE(std::isnan(ins.roundness_um)) << i;
  }
  EXPECT_TRUE(std::isnan(g.roundness_true_um[0]));
}

TEST(GrindingSynth, DwRestartsAfterADressing) {
  GrindingSeriesSpec spec = noise_free_spec();
  constexpr double kDepth = 0.04;
  spec.dressings = {{4, kDepth}};
  const GrindingSeries g = synthesize_grinding_series(spec);
  const GrindingSeries plain = synthesize_grinding_series(noise_free_spec());
  const Eigen::Index start = first_row(g, 4);
  // Before cycle 4: x1 = 0 (D_w restarts from 0), x3 - depth, x2 = 0 (format section 7).
  EXPECT_EQ(g.truth_trajectory(start, kVw), 0.0);
  EXPECT_EQ(g.truth_trajectory(start, kDs), g.truth_at_cycle_end(2, kDs) - kDepth);
  EXPECT_EQ(g.record.Dw_mm[start], 0.0);
  // Noise-free D_w at the end of cycle 4 is one cycle's reduction (0.497 mm, notes section 5),
  // equal to that of cycle 1, where it is four cycles' without the dressing.
  const Eigen::Index end4 = start + 850;
  constexpr double kDwTol = 1e-12;  // mm; same recursion, x1 from 0 in both
  EXPECT_NEAR(g.record.Dw_mm[end4], g.record.Dw_mm[850], kDwTol);
  EXPECT_NEAR(g.record.Dw_mm[end4], 0.497, 0.0005);
  EXPECT_NEAR(plain.record.Dw_mm[end4], 4 * 0.497, 4 * 0.0005);
  // The wheel: every later d_s is the undressed one minus the depth (wear does not depend on
  // x1 or x3, eq. 3 keeping d_s0); the truth keeps the true depth.
  constexpr double kDsTol = 1e-12;  // mm
  for (int i = 4; i <= 10; ++i)
    EXPECT_NEAR(g.truth_at_cycle_end(i - 1, kDs), plain.truth_at_cycle_end(i - 1, kDs) - kDepth,
                kDsTol);
  for (int i = 1; i <= 3; ++i)
    EXPECT_EQ(g.truth_at_cycle_end(i - 1, kDs), plain.truth_at_cycle_end(i - 1, kDs));
}

TEST(GrindingSynth, VariableCycleLengths) {
  GrindingSeriesSpec spec = noise_free_spec();
  spec.cycles = 3;
  spec.cycle_schedules = {
      {{0.0254, 475}, {0.002, 190}, {0.0, 185}}, {{0.0254, 400}, {0.0, 100}}, {{0.0254, 10}}};
  const GrindingSeries g = synthesize_grinding_series(spec);
  EXPECT_EQ(g.n, (std::vector<int>{850, 500, 10}));
  EXPECT_EQ(g.record.power_W.size(), 851 + 501 + 11);
  EXPECT_EQ(g.record.u_mm_s[851 + 501 + 10], 0.0254);  // row n_3: the last stage's u
}

TEST(GrindingSynth, RejectsBadSpecs) {
  const auto bad = [](auto edit) {
    GrindingSeriesSpec s = noise_free_spec();
    edit(s);
    return s;
  };
  EXPECT_THROW(synthesize_grinding_series(bad([](GrindingSeriesSpec& s) { s.cycles = 0; })),
               InputError);
  EXPECT_THROW(synthesize_grinding_series(bad([](GrindingSeriesSpec& s) { s.schedule = {}; })),
               InputError);
  EXPECT_THROW(synthesize_grinding_series(bad([](GrindingSeriesSpec& s) {
                 s.schedule = {{0.01, -1}};
               })),
               InputError);
  EXPECT_THROW(synthesize_grinding_series(bad([](GrindingSeriesSpec& s) { s.power_sd_W = -1.0; })),
               InputError);
  EXPECT_THROW(synthesize_grinding_series(bad([](GrindingSeriesSpec& s) {
                 s.late = {{3, 2}};
               })),
               InputError);
  EXPECT_THROW(synthesize_grinding_series(bad([](GrindingSeriesSpec& s) {
                 s.dressings = {{1, 0.04}};
               })),
               InputError);
  EXPECT_THROW(
      synthesize_grinding_series(bad([](GrindingSeriesSpec& s) { s.uninspected_cycles = {11}; })),
      InputError);
  EXPECT_THROW(synthesize_grinding_series(bad([](GrindingSeriesSpec& s) {
                 s.uninspected_cycles = {3};
                 s.late = {{3, 5}};
               })),
               InputError);
}

}  // namespace
}  // namespace grinding
}  // namespace chatterlab
