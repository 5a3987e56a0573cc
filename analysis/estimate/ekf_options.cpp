#include "analysis/estimate/ekf_options.h"

#include <cmath>
#include <sstream>

#include "analysis/common/require.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace estimate {

namespace {

template <typename T>
void require_ekf(bool rule_holds, const char* field, T value, const char* rule) {
  require_rule(rule_holds, std::string("ekf.") + field, value, rule);
}

void require_nonnegative(const char* field, double v) {
  require_ekf(std::isfinite(v) && v >= 0.0, field, v, "must be finite and >= 0");
}
void require_positive(const char* field, double v) {
  require_ekf(std::isfinite(v) && v > 0.0, field, v, "must be finite and > 0");
}
void require_discretization(Discretization d) {
  require_ekf(d == Discretization::kForwardEuler || d == Discretization::kSymplecticEuler,
              "discretization", static_cast<int>(d), "unknown discretization");
}

void require_unscented(const kalman::UnscentedOptions& u) {
  require_ekf(std::isfinite(u.alpha) && u.alpha > 0.0, "ukf.alpha", u.alpha,
              "must be finite and > 0");
  require_ekf(std::isfinite(u.beta), "ukf.beta", u.beta, "must be finite");
  // n + kappa > 0 for the smallest filter (5 states) and every larger one.
  require_ekf(std::isfinite(u.kappa) && u.kappa > -5.0, "ukf.kappa", u.kappa, "must be > -5");
}

}  // namespace

ModalEkfOptions modal_options_000() {
  ModalEkfOptions o;
  o.discretization = Discretization::kForwardEuler;
  o.q_force_N2 = 1e14;  // eqs 6.1, 6.4
  o.q_mass = o.q_damping = o.q_stiffness = 0.1;
  o.r_m2 = 5.0;               // eqs 6.2, 6.5
  o.p0_deflection_m2 = 1e12;  // eqs 6.3, 6.6
  o.p0_velocity_m2_s2 = 1e12;
  o.p0_mass_kg2 = 1e8;
  o.p0_damping_kg2_s2 = 1e22;
  o.p0_stiffness_N2_m2 = 5e13;
  return o;
}

CoeffEkfOptions coeff_options_000() {
  CoeffEkfOptions o;
  o.discretization = Discretization::kForwardEuler;
  o.q_force_N2 = 1e14;  // eq. 6.4
  o.q_Kt = o.q_Kr = 0.1;
  o.r_m2 = 5.0;               // eq. 6.5
  o.p0_deflection_m2 = 1e12;  // eq. 6.7
  o.p0_velocity_m2_s2 = 1e12;
  o.p0_Kt = o.p0_Kr = 1e29;
  o.gate = ToothGate::kNone;  // 000 sec. 4.4: two plain EKFs in parallel
  return o;
}

void validate(const ModalEkfOptions& o) {
  require_discretization(o.discretization);
  require_nonnegative("q_force_N2", o.q_force_N2);
  require_nonnegative("q_mass", o.q_mass);
  require_nonnegative("q_damping", o.q_damping);
  require_nonnegative("q_stiffness", o.q_stiffness);
  require_positive("r_m2", o.r_m2);
  require_positive("p0_deflection_m2", o.p0_deflection_m2);
  require_positive("p0_velocity_m2_s2", o.p0_velocity_m2_s2);
  require_positive("p0_mass_kg2", o.p0_mass_kg2);
  require_positive("p0_damping_kg2_s2", o.p0_damping_kg2_s2);
  require_positive("p0_stiffness_N2_m2", o.p0_stiffness_N2_m2);
  require_unscented(o.ukf);
  // The widest modal UKF has 7 states: its points reach sqrt(alpha^2 (7 + kappa)) sd.
  const double reach = std::sqrt(o.ukf.alpha * o.ukf.alpha * (7.0 + o.ukf.kappa));
  require_ekf(std::isfinite(o.ukf_p0_relative_sd) && o.ukf_p0_relative_sd > 0.0 &&
                  o.ukf_p0_relative_sd * reach < 1.0,
              "ukf_p0_relative_sd", o.ukf_p0_relative_sd,
              ("must be > 0 and below 1 / sqrt(alpha^2 (7 + kappa)) = " +
               std::to_string(1.0 / reach) + " (no sigma point with a negative mass)")
                  .c_str());
  require_ekf(o.history_points >= 2, "history_points", o.history_points, "must be >= 2");
}

void validate(const CoeffEkfOptions& o) {
  require_discretization(o.discretization);
  require_nonnegative("q_force_N2", o.q_force_N2);
  require_nonnegative("q_Kt", o.q_Kt);
  require_nonnegative("q_Kr", o.q_Kr);
  require_positive("r_m2", o.r_m2);
  require_positive("p0_deflection_m2", o.p0_deflection_m2);
  require_positive("p0_velocity_m2_s2", o.p0_velocity_m2_s2);
  require_positive("p0_Kt", o.p0_Kt);
  require_positive("p0_Kr", o.p0_Kr);
  require_unscented(o.ukf);
  require_ekf(o.gate == ToothGate::kEngaged || o.gate == ToothGate::kNone, "gate",
              static_cast<int>(o.gate), "unknown gate");
  require_ekf(o.history_points >= 2, "history_points", o.history_points, "must be >= 2");
}

}  // namespace estimate
}  // namespace chatterlab
