// What the EKFs of 000 ch. 4 take from a measured cut at each step: the chip of every tooth by
// the traditional model (000 eq. 2.7) computed from the MEASURED deflections x(t), y(t) and
// x(t - tau), y(t - tau) (000 sec. 4.4: "all delayed states used for chip thickness calculation
// were based on state measurements and not estimates"), and from it the cutting force with
// known coefficients (modal filters, 000 sec. 4.3) or the force's derivatives with respect to
// the coefficients (coefficient filters, 000 eqs 4.29-4.32).
//
// Conventions: force_model.h and chip_traditional.h (000 ch. 2). theta_p = theta_1 +
// (p - 1) 2 pi / n; per tooth, with g_p the switching function and b the depth,
//   Fx_p = -(Kt_p cos theta_p + Kr_p sin theta_p) b g_p w_p
//   Fy_p =  (Kt_p sin theta_p - Kr_p cos theta_p) b g_p w_p        (000 eqs 2.1-2.4, gamma = 1).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "analysis/common/cutting_coefficients.h"
#include "analysis/estimate/spline_resample.h"
#include "analysis/milling/simulation_options.h"

namespace chatterlab {
namespace estimate {

// The cut as the filters model it (000 ch. 2). Defaults: 000 sec. 5.2.
struct CutSetup {
  int teeth = 2;                         // n, 1..milling::kMaxTeeth
  double radius_m = 6.35e-3;             // r, m, > 0
  double spindle_rpm = 15000.0;          // > 0; the chip delay is tau = 60 / (rpm n)
  double feed_per_tooth_m = 0.0635e-3;   // h, m, >= 0
  double radial_immersion_m = 0.382e-3;  // r_i, m, 0 < r_i <= 2 r
  milling::Operation operation = milling::Operation::kUpMilling;  // engagement.h
  // g_p of the filters' force model: kContact (g = 1 in the window and w > 0, the simulator's
  // default) or kAngleOnly (g = 1 in the window, 000 sec. 2.2 read literally).
  milling::SwitchingRule switching = milling::SwitchingRule::kContact;
};

// A measured cut on a uniform grid (normally after resample_cubic_spline): sample i at time
// i time_step_s.
struct MeasuredCut {
  double time_step_s = std::numeric_limits<double>::quiet_NaN();  // T of 000 eq. 4.3, s, > 0
  Eigen::VectorXd x_m, y_m;    // tool-tip deflections, m (same length N)
  Eigen::VectorXd theta1_rad;  // theta_1 at each sample (tachometer and offset angle), length N
  Eigen::VectorXd depth_m;     // axial depth b, m, >= 0: length 1 (constant) or N
};

// The cut resampled to step_out_s by cubic spline (000 sec. 6.1; spline_resample.h): x, y, the
// unwrapped theta_1 (jumps of more than pi between samples are taken as wraps of 2 pi) and a
// per-sample depth; a constant depth stays one value. Throws InputError as
// resample_cubic_spline and for the sizes CutChips checks.
MeasuredCut resample_cut(const MeasuredCut& cut, double step_out_s,
                         SplineEnd end = SplineEnd::kNotAKnot);

// The cut with theta_1 shifted by an offset angle: theta1_rad + offset_angle_deg (in rad). A
// window is resampled once with the tachometer phase as theta_1 (offset 0); each offset the
// identification tries adds to it (000 sec. 5.1: theta_1 = phase + offset).
MeasuredCut with_offset_angle(const MeasuredCut& cut, double offset_angle_deg);

// One tooth at one step.
struct ToothChip {
  double sin_theta = 0.0;
  double cos_theta = 1.0;
  double bw_m2 = 0.0;  // b g_p w_p, m^2 (0: not cutting)
};

// Every tooth at one step (fixed size: built per step without allocating).
struct StepChips {
  int teeth = 0;
  std::uint32_t engaged = 0;  // bit p-1 set when g_p = 1
  std::array<ToothChip, milling::kMaxTeeth> tooth;
};

// Force input of one filter step: F = known_N + regressor [Kt; Kr]. Modal filters: the whole
// force with known coefficients in known_N. Coefficient filters: the estimated teeth in
// regressor (000 eqs 4.29-4.32 times m / T) and the rest in known_N.
//
// A filter whose chips come from its own estimates (ekf-coeff-xy-feedback) makes the force depend
// on the current deflection: F = known_N + regressor [Kt; Kr] + stiffness (p - position), with
// p = (x, y) the state's deflection, `position` the deflection the chips were computed from and
// `stiffness` = dF/dp there (the regenerative term; zero for the other filters).
struct ForceInput {
  Eigen::Vector2d known_N = Eigen::Vector2d::Zero();        // (Fx, Fy), N
  Eigen::Matrix2d regressor_m2 = Eigen::Matrix2d::Zero();   // rows Fx, Fy; columns Kt, Kr; m^2
  Eigen::Matrix2d stiffness_N_m = Eigen::Matrix2d::Zero();  // rows Fx, Fy; columns x, y; N/m
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();     // (x, y) of the linearization, m
};

// Per-tooth regressor d(Fx, Fy) / d(Kt_p, Kr_p) = b g w [[-cos, -sin], [sin, -cos]].
inline Eigen::Matrix2d tooth_regressor_m2(const ToothChip& c) {
  Eigen::Matrix2d r;
  r << -c.cos_theta, -c.sin_theta, c.sin_theta, -c.cos_theta;
  return c.bw_m2 * r;
}

// The inputs of one filter step (000 sec. 4.4): all measured, none estimated.
struct StepMeasurement {
  double theta1_rad = 0.0;                      // theta_1 (tachometer and offset angle)
  double depth_m = 0.0;                         // b
  double x_m = 0.0, y_m = 0.0;                  // x(t), y(t)
  double x_delayed_m = 0.0, y_delayed_m = 0.0;  // x(t - tau), y(t - tau)
};

// 000 eq. 2.7 with the engagement window of engagement.h and setup.switching, per step.
class TraditionalChips {
 public:
  // Throws InputError naming the setup.* field that breaks its rule.
  explicit TraditionalChips(const CutSetup& setup);
  // Allocates nothing.
  StepChips operator()(const StepMeasurement& s) const;
  const CutSetup& setup() const { return setup_; }

 private:
  CutSetup setup_;
  double entry_rad_ = 0.0, exit_rad_ = 0.0;
  std::array<double, milling::kMaxTeeth> sin_pitch_{}, cos_pitch_{};  // (p - 1) 2 pi / n
};

// Chips of a recorded cut, step by step, from its measured signals. Construction validates and
// precomputes; chips(k) allocates nothing.
class CutChips {
 public:
  // Throws InputError naming the field (cut.*, setup.*) that breaks its rule: sizes, finite
  // values, a record shorter than the delay plus two samples. `cut` must outlive this object.
  CutChips(const MeasuredCut& cut, const CutSetup& setup);

  // Chips at sample k, first_step() <= k < samples(). x(t - tau) is interpolated linearly when
  // tau / T is not an integer.
  StepChips chips(Eigen::Index k) const;

  // First sample with a delayed sample x(t - tau) inside the record: ceil(tau / T).
  Eigen::Index first_step() const { return first_step_; }
  Eigen::Index samples() const { return n_; }
  // tau / T, tau = 60 / (rpm n) (the chip delay in samples).
  double delay_samples() const { return delay_; }
  // The delayed value of a series at sample k: v(k - delay_int) and, when tau / T is not an
  // integer, the linear interpolation towards v(k - delay_int - 1) (as chips() does).
  double delayed(const Eigen::VectorXd& v, Eigen::Index k) const {
    double d = v[k - delay_int_];
    if (delay_frac_ > 0.0) d += delay_frac_ * (v[k - delay_int_ - 1] - d);
    return d;
  }
  // The chip model (000 eq. 2.7, engagement and switching of the setup).
  const TraditionalChips& model() const { return model_; }
  const MeasuredCut& cut() const { return cut_; }

 private:
  const MeasuredCut& cut_;
  TraditionalChips model_;
  Eigen::Index n_ = 0;
  Eigen::Index first_step_ = 0;
  double delay_ = 0.0;
  Eigen::Index delay_int_ = 0;  // floor(delay)
  double delay_frac_ = 0.0;     // delay - floor(delay); 0 when tau / T is an integer
};

// Kt_p, Kr_p of one tooth (000 eqs 2.1-2.2; common/cutting_coefficients.h, edge terms 0: the
// filters' force model has none).
using ToothCoefficients = CuttingCoefficients;

// The modal filters' input: the whole cutting force with known per-tooth coefficients
// (coefficients.size() >= chips.teeth, not checked: called per step).
Eigen::Vector2d cutting_force_N(const StepChips& chips,
                                const std::vector<ToothCoefficients>& coefficients);

}  // namespace estimate
}  // namespace chatterlab
