#include "analysis/estimate/cut_input.h"

#include <cmath>
#include <sstream>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"
#include "analysis/common/summary.h"
#include "analysis/milling/chip_traditional.h"
#include "analysis/milling/engagement.h"
#include "analysis/milling/force_model.h"
#include "analysis/signal/unwrap.h"

namespace chatterlab {
namespace estimate {

namespace {

void require_finite(const Eigen::VectorXd& v, const char* name) {
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) {
      require_rule(false, std::string("cut.") + name + "[" + std::to_string(i) + "]", v[i],
                   "must be finite");
    }
  }
}

void validate(const CutSetup& s) {
  require_rule(s.teeth >= 1 && s.teeth <= milling::kMaxTeeth, "setup.teeth", s.teeth,
               "must be in [1, " + std::to_string(milling::kMaxTeeth) + "]");
  require_rule(std::isfinite(s.radius_m) && s.radius_m > 0.0, "setup.radius_m", s.radius_m,
               "must be > 0");
  require_rule(std::isfinite(s.spindle_rpm) && s.spindle_rpm > 0.0, "setup.spindle_rpm",
               s.spindle_rpm, "must be > 0");
  require_rule(std::isfinite(s.feed_per_tooth_m) && s.feed_per_tooth_m >= 0.0,
               "setup.feed_per_tooth_m", s.feed_per_tooth_m, "must be >= 0");
  require_rule(std::isfinite(s.radial_immersion_m) && s.radial_immersion_m > 0.0 &&
                   s.radial_immersion_m <= 2.0 * s.radius_m,
               "setup.radial_immersion_m", s.radial_immersion_m, "must be in (0, 2 radius_m]");
}

void validate(const MeasuredCut& c) {
  require_rule(std::isfinite(c.time_step_s) && c.time_step_s > 0.0, "cut.time_step_s",
               c.time_step_s, "must be finite and > 0");
  const Eigen::Index n = c.x_m.size();
  require_rule(c.y_m.size() == n, "cut.y_m.size()", c.y_m.size(),
               "must equal cut.x_m.size() = " + std::to_string(n));
  require_rule(c.theta1_rad.size() == n, "cut.theta1_rad.size()", c.theta1_rad.size(),
               "must equal cut.x_m.size() = " + std::to_string(n));
  require_rule(c.depth_m.size() == 1 || c.depth_m.size() == n, "cut.depth_m.size()",
               c.depth_m.size(),
               "must be 1 (constant depth) or cut.x_m.size() = " + std::to_string(n));
  require_finite(c.x_m, "x_m");
  require_finite(c.y_m, "y_m");
  require_finite(c.theta1_rad, "theta1_rad");
  require_finite(c.depth_m, "depth_m");
  for (Eigen::Index i = 0; i < c.depth_m.size(); ++i) {
    require_rule(c.depth_m[i] >= 0.0, "cut.depth_m[" + std::to_string(i) + "]", c.depth_m[i],
                 "must be >= 0");
  }
}

}  // namespace

TraditionalChips::TraditionalChips(const CutSetup& setup) : setup_(setup) {
  validate(setup);
  const milling::EngagementWindow w =
      milling::engagement_window(setup.operation, setup.radius_m, setup.radial_immersion_m);
  entry_rad_ = w.entry_rad;
  exit_rad_ = w.exit_rad;
  for (int p = 0; p < setup.teeth; ++p) {
    const double a = kTwoPi * p / setup.teeth;
    sin_pitch_[static_cast<std::size_t>(p)] = std::sin(a);
    cos_pitch_[static_cast<std::size_t>(p)] = std::cos(a);
  }
}

StepChips TraditionalChips::operator()(const StepMeasurement& s) const {
  StepChips out;
  out.teeth = setup_.teeth;
  const double dx = s.x_m - s.x_delayed_m;
  const double dy = s.y_m - s.y_delayed_m;
  const double s1 = std::sin(s.theta1_rad);
  const double c1 = std::cos(s.theta1_rad);
  const bool angle_only = setup_.switching == milling::SwitchingRule::kAngleOnly;
  for (int p = 0; p < setup_.teeth; ++p) {
    const std::size_t i = static_cast<std::size_t>(p);
    ToothChip& t = out.tooth[i];
    // theta_p = theta_1 + (p - 1) 2 pi / n by the angle-sum formulas.
    t.sin_theta = s1 * cos_pitch_[i] + c1 * sin_pitch_[i];
    t.cos_theta = c1 * cos_pitch_[i] - s1 * sin_pitch_[i];
    const double theta_p = s.theta1_rad + kTwoPi * p / setup_.teeth;
    if (!milling::in_cut(theta_p, entry_rad_, exit_rad_)) continue;
    const double w = milling::chip_thickness_traditional(setup_.feed_per_tooth_m, t.sin_theta,
                                                         t.cos_theta, dx, dy);
    if (!angle_only && w <= 0.0) continue;
    t.bw_m2 = s.depth_m * w;
    out.engaged |= 1u << p;
  }
  return out;
}

CutChips::CutChips(const MeasuredCut& cut, const CutSetup& setup) : cut_(cut), model_(setup) {
  validate(cut);
  n_ = cut.x_m.size();
  const double tau_s = 60.0 / (setup.spindle_rpm * setup.teeth);
  delay_ = tau_s / cut.time_step_s;
  const double nearest = std::round(delay_);
  // A delay within 1e-9 sample of an integer is that integer (15,000 rpm, 2 teeth, 5e-7 s:
  // 4,000 samples).
  if (std::abs(delay_ - nearest) <= 1e-9 * std::max(1.0, delay_)) {
    delay_int_ = static_cast<Eigen::Index>(nearest);
    delay_frac_ = 0.0;
  } else {
    delay_int_ = static_cast<Eigen::Index>(std::floor(delay_));
    delay_frac_ = delay_ - std::floor(delay_);
  }
  first_step_ = delay_frac_ > 0.0 ? delay_int_ + 1 : delay_int_;
  require_rule(n_ >= first_step_ + 2, "cut.x_m.size()", n_,
               "must be >= the chip delay tau / T + 2 = " + std::to_string(first_step_ + 2) +
                   " samples (one tooth period plus one filter step)");
}

StepChips CutChips::chips(Eigen::Index k) const {
  StepMeasurement s;
  s.theta1_rad = cut_.theta1_rad[k];
  s.depth_m = cut_.depth_m.size() == 1 ? cut_.depth_m[0] : cut_.depth_m[k];
  s.x_m = cut_.x_m[k];
  s.y_m = cut_.y_m[k];
  s.x_delayed_m = cut_.x_m[k - delay_int_];
  s.y_delayed_m = cut_.y_m[k - delay_int_];
  if (delay_frac_ > 0.0) {  // x(t - tau) between samples k - delay_int - 1 and k - delay_int
    s.x_delayed_m += delay_frac_ * (cut_.x_m[k - delay_int_ - 1] - s.x_delayed_m);
    s.y_delayed_m += delay_frac_ * (cut_.y_m[k - delay_int_ - 1] - s.y_delayed_m);
  }
  return model_(s);
}

MeasuredCut resample_cut(const MeasuredCut& cut, double step_out_s, SplineEnd end) {
  validate(cut);
  MeasuredCut out;
  out.time_step_s = step_out_s;
  out.x_m = resample_cubic_spline(cut.x_m, cut.time_step_s, step_out_s, end);
  out.y_m = resample_cubic_spline(cut.y_m, cut.time_step_s, step_out_s, end);
  out.theta1_rad = resample_cubic_spline(signal::unwrap_phase_rad(cut.theta1_rad), cut.time_step_s,
                                         step_out_s, end);
  out.depth_m = cut.depth_m.size() == 1
                    ? cut.depth_m
                    : resample_cubic_spline(cut.depth_m, cut.time_step_s, step_out_s, end);
  return out;
}

MeasuredCut with_offset_angle(const MeasuredCut& cut, double offset_angle_deg) {
  MeasuredCut c = cut;
  c.theta1_rad.array() += offset_angle_deg * kDegToRad;
  return c;
}

Eigen::Vector2d cutting_force_N(const StepChips& chips,
                                const std::vector<ToothCoefficients>& coefficients) {
  Eigen::Vector2d f = Eigen::Vector2d::Zero();
  for (int p = 0; p < chips.teeth; ++p) {
    const std::size_t i = static_cast<std::size_t>(p);
    const ToothChip& t = chips.tooth[i];
    if (t.bw_m2 == 0.0) continue;
    const double ft = coefficients[i].Kt_N_m2 * t.bw_m2;
    const double fr = coefficients[i].Kr_N_m2 * t.bw_m2;
    f.x() -= ft * t.cos_theta + fr * t.sin_theta;
    f.y() += ft * t.sin_theta - fr * t.cos_theta;
  }
  return f;
}

}  // namespace estimate
}  // namespace chatterlab
