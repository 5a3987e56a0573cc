// Process model of the EKFs of 000 ch. 4: the tool as a mass-spring-damper on x (and y)
// (000 eqs 2.5-2.6, same m, c, k on both axes) with some of m, c, k or the cutting
// coefficients Kt, Kr appended to the state as constants driven by noise.
//
// State (000 sec. 4.3-4.4 order): x, xdot, [y, ydot], then the estimated parameters among
// (m, c, k) in that order, or (Kt, Kr). Per axis a with position p_a, velocity v_a,
//   acc_a = (F_a + w_a - c v_a - k p_a) / m,       F = known_N + regressor [Kt; Kr]
// and one step of T:
//   kForwardEuler (000 eqs 4.3, 4.15, 4.23):  p_a' = p_a + T v_a,   v_a' = v_a + T acc_a
//   kSymplecticEuler (the simulator's velocity-first order, symplectic_euler.h):
//                                             v_a' = v_a + T acc_a,  p_a' = p_a + T v_a'
//   parameters:                               theta' = theta + T w_theta
// Jacobians (000 eqs 4.10-4.11, 4.17-4.18, 4.25-4.26), rows of the velocity of axis a:
//   J_v'_p = -T k/m, J_v'_v = 1 - T c/m, J_v'_m = -T acc/m (000 eqs 4.14, 4.21-4.22: F_3,3 of
//   eq. 4.10 sits in row 2, column 3), J_v'_c = -T v/m, J_v'_k = -T p/m,
//   J_v'_Kt = T regressor(a, 0)/m, J_v'_Kr = T regressor(a, 1)/m (000 eqs 4.29-4.32, which
//   name them d(xddot)/dKt: they are derivatives of the next velocity), J_v'_w_a = T/m;
// position rows: forward J_p' = e_p + T e_v; symplectic J_p' = e_p + T J_v'.
// The measurement is the deflection of each axis, H = [1 0 0 ...] (eqs 4.12, 4.19, 4.27), M = I.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "analysis/common/modal_parameters.h"
#include "analysis/estimate/cut_input.h"

namespace chatterlab {
namespace estimate {

enum class Discretization { kForwardEuler, kSymplecticEuler };

// m, c, k of 000 eqs 2.5-2.6 (equal on x and y, 000 sec. 4.3): the project's one type.
using ::chatterlab::ModalParameters;

// Which quantities a filter carries in its state.
template <bool kYAxis, bool kMass, bool kDamping, bool kStiffness, bool kCoefficients>
struct ToolLayout {
  static constexpr bool y_axis = kYAxis;
  static constexpr bool mass = kMass;
  static constexpr bool damping = kDamping;
  static constexpr bool stiffness = kStiffness;
  static constexpr bool coefficients = kCoefficients;
};

template <class Layout>
class ToolModel {
 public:
  static constexpr int kAxes = Layout::y_axis ? 2 : 1;
  static constexpr int kParameters = int{Layout::mass} + int{Layout::damping} +
                                     int{Layout::stiffness} + 2 * int{Layout::coefficients};
  static constexpr int kStates = 2 * kAxes + kParameters;
  static constexpr int kNoises = kAxes + kParameters;  // w_x, [w_y], one per parameter
  static constexpr int kMeasurements = kAxes;
  static constexpr int kFirstParameter = 2 * kAxes;
  static constexpr int kMass = Layout::mass ? kFirstParameter : -1;
  static constexpr int kDamping = Layout::damping ? kFirstParameter + int{Layout::mass} : -1;
  static constexpr int kStiffness =
      Layout::stiffness ? kFirstParameter + int{Layout::mass} + int{Layout::damping} : -1;
  static constexpr int kKt = Layout::coefficients ? kFirstParameter : -1;
  static constexpr int kKr = Layout::coefficients ? kFirstParameter + 1 : -1;
  static_assert(!Layout::coefficients || Layout::y_axis, "the coefficient layouts have x and y");

  using State = Eigen::Matrix<double, kStates, 1>;
  using Noise = Eigen::Matrix<double, kNoises, 1>;
  using Measurement = Eigen::Matrix<double, kMeasurements, 1>;
  using StateMatrix = Eigen::Matrix<double, kStates, kStates>;
  using NoiseJacobian = Eigen::Matrix<double, kStates, kNoises>;

  // State index measured by measurement i (H of 000 eqs 4.12, 4.19, 4.27).
  static constexpr int measured_state(int i) { return 2 * i; }

  // @param time_step_s T, s;  @param held the values of m, c, k not in the state (others
  // ignored).
  ToolModel(double time_step_s, Discretization discretization, const ModalParameters& held)
      : T_(time_step_s),
        symplectic_(discretization == Discretization::kSymplecticEuler),
        held_(held) {}

  double time_step_s() const { return T_; }
  const ModalParameters& held() const { return held_; }

  double mass(const State& x) const {
    if constexpr (kMass >= 0) return x[kMass];
    return held_.m_kg;
  }
  double damping(const State& x) const {
    if constexpr (kDamping >= 0) return x[kDamping];
    return held_.c_kg_s;
  }
  double stiffness(const State& x) const {
    if constexpr (kStiffness >= 0) return x[kStiffness];
    return held_.k_N_m;
  }

  // f of 000 eq. 4.1 and its Jacobians J_f_x (F) and J_f_w (L) at (x, u, w).
  State propagate(const State& x, const ForceInput& u, const Noise& w, StateMatrix* J_f_x = nullptr,
                  NoiseJacobian* J_f_w = nullptr) const {
    const double m = mass(x), c = damping(x), k = stiffness(x);
    const double inv_m = 1.0 / m;
    Eigen::Vector2d force = u.known_N;
    if constexpr (Layout::coefficients) {
      force.noalias() += u.regressor_m2 * x.template segment<2>(kKt);
      // Chips from the filter's own deflection (ForceInput): zero stiffness for the others.
      const Eigen::Vector2d dp(x[0] - u.position_m[0], x[2] - u.position_m[1]);
      force.noalias() += u.stiffness_N_m * dp;
    }
    State out;
    if (J_f_x) J_f_x->setIdentity();
    if (J_f_w) J_f_w->setZero();
    for (int a = 0; a < kAxes; ++a) {
      const int ip = 2 * a, iv = 2 * a + 1;
      const double p = x[ip], v = x[iv];
      const double acc = (force[a] + w[a] - c * v - k * p) * inv_m;
      out[iv] = v + T_ * acc;
      out[ip] = p + T_ * (symplectic_ ? out[iv] : v);
      if (J_f_x) {
        StateMatrix& J = *J_f_x;
        J(iv, ip) = -T_ * k * inv_m;
        J(iv, iv) = 1.0 - T_ * c * inv_m;
        if constexpr (kMass >= 0) J(iv, kMass) = -T_ * acc * inv_m;
        if constexpr (kDamping >= 0) J(iv, kDamping) = -T_ * v * inv_m;
        if constexpr (kStiffness >= 0) J(iv, kStiffness) = -T_ * p * inv_m;
        if constexpr (Layout::coefficients) {
          J(iv, kKt) = T_ * u.regressor_m2(a, 0) * inv_m;
          J(iv, kKr) = T_ * u.regressor_m2(a, 1) * inv_m;
          J(iv, 0) += T_ * u.stiffness_N_m(a, 0) * inv_m;  // dF_a / dx (feedback chips)
          J(iv, 2) += T_ * u.stiffness_N_m(a, 1) * inv_m;  // dF_a / dy
        }
        if (symplectic_) {
          J.row(ip) = T_ * J.row(iv);
          J(ip, ip) += 1.0;
        } else {
          J(ip, iv) = T_;
        }
      }
      if (J_f_w) {
        (*J_f_w)(iv, a) = T_ * inv_m;
        if (symplectic_) (*J_f_w)(ip, a) = T_ * T_ * inv_m;
      }
    }
    for (int i = 0; i < kParameters; ++i) {
      out[kFirstParameter + i] = x[kFirstParameter + i] + T_ * w[kAxes + i];
      if (J_f_w) (*J_f_w)(kFirstParameter + i, kAxes + i) = T_;
    }
    return out;
  }

  // P += L Q L^T with L = J_f_w at x (000 eq. 4.6's second term) and Q = diag(q), using L's
  // structure: each noise reaches one velocity (and, symplectic, its position) or one parameter.
  void add_process_noise(const State& x, const Noise& q, StateMatrix* P) const {
    const double inv_m = 1.0 / mass(x);
    const double lv = T_ * inv_m;
    for (int a = 0; a < kAxes; ++a) {
      const int ip = 2 * a, iv = 2 * a + 1;
      (*P)(iv, iv) += lv * lv * q[a];
      if (symplectic_) {
        const double lp = T_ * lv;
        (*P)(ip, ip) += lp * lp * q[a];
        (*P)(ip, iv) += lp * lv * q[a];
        (*P)(iv, ip) += lp * lv * q[a];
      }
    }
    for (int i = 0; i < kParameters; ++i) {
      (*P)(kFirstParameter + i, kFirstParameter + i) += T_ * T_ * q[kAxes + i];
    }
  }

 private:
  double T_;
  bool symplectic_;
  ModalParameters held_;
};

// The five single-filter variants of EXPERIMENT_FORMAT.md (the per-tooth variant runs one
// CoeffXyModel per tooth).
using ModalXModel = ToolModel<ToolLayout<false, true, true, true, false>>;     // 5 states
using ModalXyModel = ToolModel<ToolLayout<true, true, true, true, false>>;     // 7 states
using ModalXyMkModel = ToolModel<ToolLayout<true, true, false, true, false>>;  // 6 states
using ModalXyMcModel = ToolModel<ToolLayout<true, true, true, false, false>>;  // 6 states
using CoeffXyModel = ToolModel<ToolLayout<true, false, false, false, true>>;   // 6 states

}  // namespace estimate
}  // namespace chatterlab
