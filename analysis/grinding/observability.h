// Local observability of the grinding model (002 sec. III, table I; spec notes section 3): the
// rank of
//   O = [C; C A; C A^2; ...; C A^(n-1)]
// with A = dF/dX of 002 eqs 1-3 (process_derivative, the leading n x n block for n = 3 or 4
// states; R0 has F = 0, 002 eq. 6) and C the rows of dH/dX (outputs: P, D_w of appendix A,
// d_s = x3, R_a of eq. 11) of the channels in use. The discrete A_d = I + T_f A of eq. 8 gives
// the same rank (A_d^k is a combination of I, A, ..., A^k with a triangular change of basis).
//
// Computation in scaled coordinates, which change no rank but keep the entries (which span
// more than ten decades) comparable: X = S_x X~ with S_x the typical state magnitudes, outputs
// in units of S_y, time in units of tau:
//   C~ = S_y^-1 C S_x,  A~ = tau S_x^-1 A S_x,  O~ = [C~; C~ A~; ...; C~ A~^(n-1)].
// The rank is the number of singular values of O~ (JacobiSVD) above relative_tolerance times
// the largest.
//
// 002 table I: case 1 (x1..x3) with P, D_w is deficient (x3 drives nothing and only d_s sees
// it) and with P + d_s full; case 2 (x1..x3, R0) with P, D_w, d_s is deficient (R0 enters R_a
// only) and with P + d_s, R_a full. x1 is seen by P only through dP/dx1 = K_s s1 delta
// x1^(delta-1) x2, which vanishes at x2 = 0: operating points are taken where x2 > 0.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "analysis/grinding/grinding_model.h"
#include "analysis/grinding/multirate_ekf.h"

namespace chatterlab {
namespace grinding {

// The measured outputs in use (in-process and postprocess alike).
struct GrindingChannels {
  bool power = false;
  bool Dw = false;
  bool ds = false;
  bool Ra = false;
};

struct GrindingObservabilityOptions {
  // A singular value of O~ at or below this fraction of the largest is zero. Structural
  // deficiency gives exact zeros here (a zero column of O~, or 1e-17 relative); over every
  // point with x1, x2 > 0 of 002's ten cycles the smallest nonzero ones are >= 9e-7 relative
  // with table III case A process noise (v near 0+ at spark-out), >= 4e-5 with case B's and
  // >= 5e-5 noise-free (tests/analysis/grinding/grinding_observability_test.cpp).
  double relative_tolerance = 1e-9;
  // Typical state magnitudes S_x (Vw_mm2, v_mm_s, ds_mm, R0_um): by default the standard
  // deviations of the format's example P0 (section 7: 10, 1e-7, 1e-6, 0.01).
  Eigen::Vector4d state_scale{3.1622776601683795, 3.1622776601683794e-4, 1e-3, 0.1};
  // Typical output magnitudes S_y (P in W, D_w in mm, d_s in mm, R_a in um): by default the
  // measurement standard deviations of 002 table III (100 W, 0.01 mm, 1 um, 0.01 um).
  Eigen::Vector4d output_scale{100.0, 0.01, 1e-3, 0.01};
  // Operating points along a trajectory need x2 above this (mm/s) and x1 > 0.
  double min_v_mm_s = 0.0;
};

struct GrindingObservability {
  int rank = 0;
  int states = 0;                   // n: 3 or 4
  Eigen::VectorXd singular_values;  // of O~, relative to the largest, descending
  double relative_tolerance = 0.0;
  bool observable() const { return states > 0 && rank == states; }
};

// At the operating point X (with R0 = X[kR0] held as a known parameter when states = 3) and
// commanded infeed u. Throws InputError for states other than 3 or 4, no channel, a
// non-finite X or u, a non-positive tau, scale or tolerance.
GrindingObservability grinding_observability(const ProcessState& X, double u_mm_s,
                                             const GrindingParameters& p, int states,
                                             const GrindingChannels& channels,
                                             const GrindingObservabilityOptions& o = {});

struct ObservabilityPoint {
  Eigen::Index row = 0;  // row of the trajectory
  GrindingObservability result;
};

struct TrajectoryObservability {
  std::vector<ObservabilityPoint> points;  // in row order
  int min_rank = 0, max_rank = 0;
  // Over the points: the smallest relative singular value counted in the rank (the margin of
  // a full rank) and the largest one not counted (0 when none was dropped or all were 0).
  double smallest_kept = 0.0, largest_dropped = 0.0;
};

// The rank at `points` operating points drawn without replacement, uniformly, from the rows of
// `trajectory` (columns Vw_mm2, v_mm_s, ds_mm, R0_um; e.g. GrindingSeries::truth_trajectory)
// whose x2 > o.min_v_mm_s and x1 > 0, with the u of the same row (002: "more than ten
// operating points taken at random from a typical trajectory"). x1 > 0 because the format's
// guard sets dP/dx1 = 0 for x1 <= 0 (the first rows of cycle 1 and after a dressing, or x1
// pushed below 0 by process noise there), where P no longer sees x1 and the settings without
// D_w lose a rank (x2 = 0 does the same). Draws by a local std::mt19937_64 seeded with
// `seed` (top-53-bit uniforms). Fewer eligible rows than `points`: all of them. Throws
// InputError for mismatched sizes, points < 1 or no eligible row.
TrajectoryObservability observability_along_trajectory(const Eigen::MatrixX4d& trajectory,
                                                       const Eigen::VectorXd& u_mm_s,
                                                       const GrindingParameters& p, int states,
                                                       const GrindingChannels& channels, int points,
                                                       std::uint64_t seed,
                                                       const GrindingObservabilityOptions& o = {});

// A state set and a channel set.
struct ObservabilityCase {
  const char* name;
  int states;
  GrindingChannels channels;
};

// The four rows of 002 table I, in its order: case 1 "P, D_w" and "P + (d_s)", case 2
// "P, D_w + (d_s)" and "P + (d_s, R_a)".
std::array<ObservabilityCase, 4> table_i_cases();

// The state and channel set of one of the format's estimators (section 7; kGrindingEstimators):
// P and D_w always, d_s and R_a as the id uses them, R0 for the xr ids.
ObservabilityCase estimator_observability_case(GrindingEstimatorId id);

}  // namespace grinding
}  // namespace chatterlab
