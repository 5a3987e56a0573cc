// Static calibration of the spindle-integrated force sensor ring (003 sec. 3.2, format section 6
// "sifs-static"): drift removal, the washer pairs combined (003 eq. 3-1) and the 3x3
// calibration matrix C with cross-talk fitted by least squares over every load window of the
// campaign's static tests. C generalises 003 eqs 3-2..3-5 (eq. 3-5 is the special case
// C_xz = C_yx = C_yz = 0).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace sifs {

enum class Axis { kX = 0, kY = 1, kZ = 2 };
const char* to_string(Axis a);  // "x", "y", "z"

// Washer channels in nominal washer newtons, columns x1 x2 y1 y2 z1 z2 (format section 6).
using Washers = Eigen::Matrix<double, Eigen::Dynamic, 6>;
// Pair signals, columns s_x s_y s_z.
using Pairs = Eigen::Matrix<double, Eigen::Dynamic, 3>;

// 003 eq. 3-1: s_x = 0.5 (x1 - x2), s_y = -0.5 (y1 - y2), s_z = 0.5 (z1 + z2) (the Z pair summed:
// an axial load presses both washers alike; 003 eqs 3-5/3-7 print a difference, notes/003.md
// decision 1).
Pairs pair_signals(const Washers& w);

// One window of steady load: [start_s, end_s] seconds from the record start, load_n signed along
// the test's axis (0 = unloaded).
struct LoadWindow {
  double start_s = 0.0;
  double end_s = 0.0;
  double load_n = 0.0;
};

// One static test reduced to its windows.
struct StaticReduction {
  StepSummary summary;
  Axis axis = Axis::kX;
  // Drift per channel: a + b t fitted by least squares to every sample of the unloaded
  // windows, subtracted from the whole record (notes/003.md decision 7).
  Eigen::Matrix<double, 6, 1> drift_offset = Eigen::Matrix<double, 6, 1>::Zero();  // a
  Eigen::Matrix<double, 6, 1> drift_per_s = Eigen::Matrix<double, 6, 1>::Zero();   // b
  // Per window, in the order given: mean pair signals s_w (drift removed) and load vector f_w
  // (load_n on `axis`, zero elsewhere).
  std::vector<LoadWindow> windows;
  std::vector<Eigen::Vector3d> s;
  std::vector<Eigen::Vector3d> f;
};

// @param w       the record (washer newtons)
// @param fs_hz   sample rate, > 0
// @param axis    the load direction
// @param windows at least one unloaded window before the first loaded one and one after the
//                last, each inside the record and holding >= 2 samples
// @throws InputError naming the rule broken ("loads[2]: window [a, b] s ends after the record
//         (c s)", "loads: no unloaded window after the last load", ...); the caller prefixes the
//         file or key
StaticReduction reduce_static_test(const Washers& w, double fs_hz, Axis axis,
                                   const std::vector<LoadWindow>& windows);

struct CalibrationFit {
  StepSummary summary;  // fails when the loads do not span three independent axes
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();  // sensitivity: s = S f (least squares, no
                                                // intercept, over every window of the group)
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();  // calibration: f_m = C s, C = S^-1
  double cond_S = 0.0;                          // 2-norm condition number of S
  // Residuals C s_w - f_w of the loaded windows, in test order then window order.
  std::vector<Eigen::Vector3d> residuals_n;
  double residual_rms_n = 0.0;    // RMS over every component of every loaded window
  double residual_max_pct = 0.0;  // largest |residual| in % of the largest |load|
  int windows = 0;                // every window used in the fit (unloaded included)
  // Linearity per loaded axis (x, y, z; NaN for an axis no test loads): the pair signal of that
  // axis against its load, a straight line with intercept fitted over that axis's windows; the
  // largest deviation from it in % of the largest |s| of those windows (% of full-scale
  // output, the washers' data-sheet unit, 003 table 1).
  Eigen::Vector3d linearity_pct = Eigen::Vector3d::Constant(0.0);
};

// @param tests  the group's reductions (any order; each must have succeeded)
CalibrationFit fit_calibration(const std::vector<StaticReduction>& tests);

}  // namespace sifs
}  // namespace chatterlab
