// Synthetic series of grinding cycles (002 sec. V; spec notes section 5): the true process
// simulated by 002 eq. 8 (forward Euler at T_f) with process noise, the fast channels of eq. 9
// and the end-of-cycle inspections of eq. 10 with measurement noise, missing and late
// inspections and dressings, for `chatterlab synth` and the tests.
//
// The truth follows the cycle transitions the filters assume (format section 7): x2 = 0 at
// each new cycle, x1 and x3 carried over (002 eq. 12); a dressing before cycle i sets x1 = 0
// (D_w restarts from 0) and removes its depth from x3. R0 starts at R0_start_um in cycle 1,
// takes a random-walk step of variance R0_walk_var_um2 at every fast step (002 eq. 6) and an
// N(0, R0_cycle_var_um2) step at the start of each later cycle (002 sec. V, fig. 4).
//
// Randomness: four local std::mt19937_64 streams seeded with derive_seed(seed, tag, 0) for the
// tags "grinding.process", "grinding.R0", "grinding.fast" and "grinding.inspection"; uniforms
// from the top 53 bits, normals by Box-Muller on them (the same seed gives the same series on
// every platform). Every stream draws the same count whatever the variances and whichever
// cycles are inspected, so e.g. dropping an inspection leaves the other values unchanged.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "analysis/grinding/grinding_model.h"
#include "analysis/grinding/multirate_ekf.h"

namespace chatterlab {
namespace grinding {

// One stage of a cycle's infeed schedule: u held for `rows` fast steps.
struct InfeedStage {
  double u_mm_s = 0.0;
  int rows = 0;
};

struct GrindingSeriesSpec {
  GrindingParameters truth;  // the true process (G1 may differ from the lab's nominal)
  double sample_period_s = 0.02;
  int cycles = 10;
  // 002 sec. V: roughing 0.0254 mm/s for 475 rows, finishing 0.002 for 190, spark-out 0 for
  // 185: n_i = 850 rows of propagation; the cycle holds n_i + 1 rows (j = 0..850). Row n_i
  // carries the u of the last stage (unused by the filters).
  std::vector<InfeedStage> schedule{{0.0254, 475}, {0.002, 190}, {0.0, 185}};
  // Optional per-cycle schedules (variable n_i): when not empty, one entry per cycle replaces
  // `schedule`.
  std::vector<std::vector<InfeedStage>> cycle_schedules;
  double ds_start_mm = 50.0;  // true d_s at the start of cycle 1
  // True R0: starts at R0_start_um at cycle 1, random walk of variance R0_walk_var per fast
  // step, plus N(0, R0_cycle_var) at the start of every cycle after the first (002 fig. 4).
  double R0_start_um = 3.6;
  double R0_walk_var_um2 = 4e-9;
  double R0_cycle_var_um2 = 1e-4;
  // Process noise variances per fast step on Vw, v, ds (002 table III case A reads
  // 4 x (0.01, 1e-9, 1e-9); 002 eq. 8 adds them once per step).
  std::array<double, 3> process_var{0.0, 0.0, 0.0};
  // Measurement noise standard deviations (002 table III: R = diag(1e4, 1e-4, 1e-6, 1e-4)).
  double power_sd_W = 100, Dw_sd_mm = 0.01, ds_sd_mm = 0.001, Ra_sd_um = 0.01,
         roundness_sd_um = 0.1;
  std::vector<int> uninspected_cycles;  // no inspection row for these
  // An inspection row whose d_s (resp. R_a) field is NaN: not measured on that part.
  std::vector<int> ds_unmeasured_cycles, Ra_unmeasured_cycles;
  // Late inspections: {cycle, available_cycle} (available_cycle > cycles: never usable).
  std::vector<std::pair<int, int>> late;
  std::vector<Dressing> dressings;  // true depths
  std::uint64_t seed = 1;
};

struct GrindingSeries {
  FastRecord record;                    // measured fast channels (calibrated units)
  std::vector<Inspection> inspections;  // cycle order
  // True values at (i, n_i), one row per cycle: Vw_mm2, v_mm_s, ds_mm, R0_um.
  Eigen::MatrixX4d truth_at_cycle_end;
  std::vector<int> n;                             // n_i per cycle
  Eigen::VectorXd Ra_true_um, roundness_true_um;  // at (i, n_i); roundness NaN without r0
  // True state at every fast instant (rows in record order, j = 0..n_i of each cycle).
  Eigen::MatrixX4d truth_trajectory;
  long negative_v_steps = 0;  // fast steps whose true x2 ended below 0 (002 notes A6)
};

// Throws InputError for a spec it cannot honour (cycles < 1, a cycle with n_i < 1, a negative
// stage length, variance or standard deviation, T_f <= 0, a cycle number out of range, a late
// pair with available_cycle < cycle, a dressing before_cycle outside 2..cycles, several
// dressings before one cycle, non-finite values).
GrindingSeries synthesize_grinding_series(const GrindingSeriesSpec& spec);

// The commanded infeed of each of the n_i propagation rows of a schedule (stage by stage).
std::vector<double> expand_schedule(const std::vector<InfeedStage>& schedule);

}  // namespace grinding
}  // namespace chatterlab
