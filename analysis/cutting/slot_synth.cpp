#include "analysis/cutting/slot_synth.h"

#include <cmath>
#include <random>
#include <sstream>

#include "analysis/common/angles.h"
#include "analysis/common/constants.h"
#include "analysis/common/require.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace cutting {

namespace {

template <typename T>
void require(bool rule_holds, const char* field, T value, const char* rule) {
  require_rule(rule_holds, std::string("slot_record.") + field, value, rule);
}

void validate(const SlotRecordSpec& s) {
  require(s.spindle_rpm > 0.0 && std::isfinite(s.spindle_rpm), "spindle_rpm", s.spindle_rpm,
          "must be > 0");
  require(s.feed_per_tooth_m >= 0.0 && std::isfinite(s.feed_per_tooth_m), "feed_per_tooth_m",
          s.feed_per_tooth_m, "must be >= 0");
  require(s.depth_m > 0.0 && std::isfinite(s.depth_m), "depth_m", s.depth_m, "must be > 0");
  const milling::CuttingCoefficients& k = s.coefficients;
  require(std::isfinite(k.Kt_N_m2), "coefficients.Kt_N_m2", k.Kt_N_m2, "must be finite");
  require(std::isfinite(k.Kte_N_m), "coefficients.Kte_N_m", k.Kte_N_m, "must be finite");
  require(std::isfinite(k.Kr_N_m2), "coefficients.Kr_N_m2", k.Kr_N_m2, "must be finite");
  require(std::isfinite(k.Kre_N_m), "coefficients.Kre_N_m", k.Kre_N_m, "must be finite");
  require(std::isfinite(s.theta_dyn_rad), "theta_dyn_rad", s.theta_dyn_rad, "must be finite");
  require(std::isfinite(s.initial_tool_angle_rad), "initial_tool_angle_rad",
          s.initial_tool_angle_rad, "must be finite");
  require(std::isfinite(s.offset_x_N), "offset_x_N", s.offset_x_N, "must be finite");
  require(std::isfinite(s.offset_y_N), "offset_y_N", s.offset_y_N, "must be finite");
  require(s.noise_std_N >= 0.0 && std::isfinite(s.noise_std_N), "noise_std_N", s.noise_std_N,
          "must be >= 0");
  require(s.zero_noise_std_V >= 0.0 && std::isfinite(s.zero_noise_std_V), "zero_noise_std_V",
          s.zero_noise_std_V, "must be >= 0");
  require(s.zero_pulse_amplitude_V > 0.0 && std::isfinite(s.zero_pulse_amplitude_V),
          "zero_pulse_amplitude_V", s.zero_pulse_amplitude_V, "must be > 0");
  require(s.zero_pulse_width_s > 0.0, "zero_pulse_width_s", s.zero_pulse_width_s, "must be > 0");
  require(s.zero_pulse_rise_s > 0.0, "zero_pulse_rise_s", s.zero_pulse_rise_s, "must be > 0");
  const double period_s = 60.0 / s.spindle_rpm;
  require(s.zero_pulse_width_s + 2.0 * s.zero_pulse_rise_s < 0.5 * period_s,
          "zero_pulse_width_s + 2 zero_pulse_rise_s",
          s.zero_pulse_width_s + 2.0 * s.zero_pulse_rise_s,
          "must be shorter than half a revolution");
  require(s.fs_hz > 0.0 && std::isfinite(s.fs_hz), "fs_hz", s.fs_hz, "must be > 0");
  require(s.duration_s > 0.0 && std::isfinite(s.duration_s), "duration_s", s.duration_s,
          "must be > 0");
}

// Trapezoidal pulse of unit height whose rising ramp is centred on tau = 0 (s).
double unit_pulse(double tau, double rise, double width) {
  const double up_start = -0.5 * rise;
  const double up_end = 0.5 * rise;
  const double down_start = up_end + width;
  const double down_end = down_start + rise;
  if (tau <= up_start || tau >= down_end) return 0.0;
  if (tau < up_end) return (tau - up_start) / rise;
  if (tau <= down_start) return 1.0;
  return 1.0 - (tau - down_start) / rise;
}

// Instants in [0, duration) at which the tool angle theta_0 + Omega t equals target (mod step).
std::vector<double> instants(double theta0, double omega, double target, double step,
                             double duration) {
  std::vector<double> t;
  double first = std::fmod(target - theta0, step);
  if (first < 0.0) first += step;
  for (int k = 0;; ++k) {
    const double tk = (first + k * step) / omega;
    if (tk >= duration) break;
    t.push_back(tk);
  }
  return t;
}

}  // namespace

SlotRecord generate_slot_record(const SlotRecordSpec& spec) {
  validate(spec);
  const Eigen::Index n = static_cast<Eigen::Index>(std::floor(spec.duration_s * spec.fs_hz));
  const double omega = kTwoPi * spec.spindle_rpm / 60.0;  // rad/s
  const double period_s = 60.0 / spec.spindle_rpm;
  const double c = std::cos(spec.theta_dyn_rad);
  const double s = std::sin(spec.theta_dyn_rad);
  constexpr int kTeeth = 2;

  SlotRecord rec;
  rec.fs_hz = spec.fs_hz;
  rec.Fx_N.resize(n);
  rec.Fy_N.resize(n);
  rec.zero_V.resize(n);

  std::mt19937_64 rng(spec.seed);
  std::normal_distribution<double> unit_normal(0.0, 1.0);

  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / spec.fs_hz;
    const double theta1 = spec.initial_tool_angle_rad + omega * t;
    double fx = 0.0;
    double fy = 0.0;
    for (int p = 1; p <= kTeeth; ++p) {
      const double theta_p = milling::tooth_angle_rad(theta1, p, kTeeth);
      const bool engaged = milling::in_cut(theta_p, 0.0, kPi);  // full slot, 000 eqs 2.8-2.9
      const double w = milling::static_chip_thickness_m(spec.feed_per_tooth_m, theta_p);
      const milling::ToothForce f =
          milling::tooth_force(spec.coefficients, w, spec.depth_m, engaged);
      const double sign = (p == 1) ? 1.0 : -1.0;  // tooth 2 is tooth 1 turned by pi
      fx += sign * (f.tangential_N * c - f.radial_N * s);
      fy += sign * (f.tangential_N * s + f.radial_N * c);
    }
    // Time since the nearest zero-count instant (theta1 = -theta_dyn mod 2 pi), in
    // [-T/2, T/2): the pulse is shorter than half a revolution (validated).
    double tau = wrap_2pi(theta1 + spec.theta_dyn_rad) / omega;
    if (tau >= 0.5 * period_s) tau -= period_s;
    const double pulse = spec.zero_pulse_amplitude_V *
                         unit_pulse(tau, spec.zero_pulse_rise_s, spec.zero_pulse_width_s);

    rec.Fx_N[i] = fx + spec.offset_x_N + spec.noise_std_N * unit_normal(rng);
    rec.Fy_N[i] = fy + spec.offset_y_N + spec.noise_std_N * unit_normal(rng);
    rec.zero_V[i] = pulse + spec.zero_noise_std_V * unit_normal(rng);
  }

  const double duration = static_cast<double>(n) / spec.fs_hz;
  rec.zero_count_times_s =
      instants(spec.initial_tool_angle_rad, omega, -spec.theta_dyn_rad, kTwoPi, duration);
  rec.tooth_change_times_s = instants(spec.initial_tool_angle_rad, omega, 0.0, kPi, duration);
  return rec;
}

}  // namespace cutting
}  // namespace chatterlab
