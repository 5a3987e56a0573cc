// Tuning of the EKFs (000 ch. 6, eqs 6.1-6.7) and the few choices 000 leaves open. Every
// default is 000's value unless its comment says otherwise; docs/estimators.md has the tests
// behind each choice.
//
// Units: the filters run in SI (m, m/s, kg, kg/s, N/m, N/m^2). Q is the covariance of the noise
// vector w of 000 eqs 4.3, 4.15, 4.23: a force noise per axis (N^2) and one per parameter
// (parameter' = parameter + T w, so (parameter unit / s)^2). R is the deflection measurement
// variance (m^2). P0 is the initial covariance of the state (000 eqs 6.3, 6.6, 6.7). Only the
// ratios among Q, R and P0 shape the estimates (scaling all three by one factor changes no
// gain); 000's values are large in absolute terms (R = 5 m^2) but consistent in their ratios.
#pragma once

#include "analysis/estimate/tool_model.h"
#include "analysis/kalman/unscented_kalman_filter.h"

namespace chatterlab {
namespace estimate {

// How the per-tooth coefficient filters treat steps when their own tooth does not cut.
enum class ToothGate {
  // Plain EKF (the default): every filter corrects all its states at every step. While tooth p
  // is out of the cut its Kt_p, Kr_p stay unobservable (zero columns of F, 000 sec. 4.5) but are
  // still corrected through the cross-covariance built during its last pass, i.e. by the free
  // vibration that pass left behind.
  kNone,
  // Filter p corrects Kt_p, Kr_p only at steps whose prediction had tooth p engaged (g_p = 1);
  // at other steps it corrects its deflection states alone (Schmidt update, ekf.h). Keeps
  // another tooth's coefficient errors from being blamed on Kt_p, Kr_p, but discards the free
  // vibration after each pass: 2.5 to 5 times the error of kNone
  // (tests/analysis/estimate/estimate_coeff_test.cpp, docs/estimators.md).
  kEngaged,
};

// ekf-modal-x, ekf-modal-xy, ekf-modal-xy-mk, ekf-modal-xy-mc (000 secs 4.3, 6.1). The defaults
// are this project's tuning (docs/estimators.md, "Tuning"); modal_options_000() gives 000's.
struct ModalEkfOptions {
  // Time discretization of 000 eqs 2.5-2.6 at the record's step T (tool_model.h).
  // Default kSymplecticEuler: its decay per step is exact to first order in T (the determinant
  // of the step map is 1 - T c / m), while 000's forward Euler (eqs 4.3, 4.15) has
  // |1 + lambda T|^2 = 1 - 2 zeta w_n T + w_n^2 T^2 against exp(-2 zeta w_n T): a negative
  // damping of k T (0.49 kg/s at T = 5e-7 s, k = 9.84e5 N/m) that the filters absorb into c,
  // +2.6 % on 22.21 kg/s in the tests (docs/estimators.md).
  Discretization discretization = Discretization::kSymplecticEuler;
  // Q: force noise on each axis, N^2, >= 0 (000 eqs 6.1, 6.4: 1e14).
  double q_force_N2 = 1e2;
  // Q of the parameter noises w_M, w_C, w_K, >= 0 (000 eqs 6.1, 6.4: 0.1 each).
  double q_mass = 0.1;
  double q_damping = 0.1;
  double q_stiffness = 0.1;
  // R: variance of each measured deflection, m^2, > 0 (000 eqs 6.2, 6.5: 5).
  double r_m2 = 1e-10;
  // P0 diagonal, > 0 (000 eqs 6.3, 6.6: 1e12, 1e12, 1e8, 1e22, 5e13).
  double p0_deflection_m2 = 1e-8;    // sd 0.1 mm
  double p0_velocity_m2_s2 = 1.0;    // sd 1 m/s
  double p0_mass_kg2 = 1e-4;         // sd 0.01 kg
  double p0_damping_kg2_s2 = 1e2;    // sd 10 kg/s
  double p0_stiffness_N2_m2 = 1e11;  // sd 3.2e5 N/m
  // Unscented variants (ukf-modal-*): the sigma points, and the standard deviation of each
  // estimated parameter in P0 as a fraction of its start value, in (0, 1 / sqrt(n + lambda)):
  // every sigma point then keeps a positive mass (000's eq. 6.3 variance of 1e8 kg^2 puts half
  // of them at a mass of -1e4 kg, and the default sd of 0.01 kg at 0.0321 - 2.65 x 0.01 kg).
  // The deflection and velocity entries are p0_deflection_m2 and p0_velocity_m2_s2.
  kalman::UnscentedOptions ukf;
  double ukf_p0_relative_sd = 0.2;
  // Points of the decimated estimate history (the initial estimate, every ceil(steps /
  // (history_points - 1))-th step and the last step), >= 2.
  int history_points = 2000;
};

// ekf-coeff-xy and ekf-coeff-xy-per-tooth (000 secs 4.4, 6.2). Defaults: this project's tuning;
// coeff_options_000() gives 000's.
struct CoeffEkfOptions {
  Discretization discretization = Discretization::kSymplecticEuler;  // as ModalEkfOptions
  // Q: force noise per axis, N^2, and w_Kt, w_Kr, >= 0 (000 sec. 6.2 uses eq. 6.4: 1e14, 0.1).
  double q_force_N2 = 1e2;
  double q_Kt = 0.1;
  double q_Kr = 0.1;
  double r_m2 = 1e-10;  // R, m^2, > 0 (000 eq. 6.5: 5)
  // P0 diagonal, > 0 (000 eq. 6.7: 1e12, 1e12, 1e12, 1e12, 1e29, 1e29).
  double p0_deflection_m2 = 1e-8;
  double p0_velocity_m2_s2 = 1.0;
  double p0_Kt = 1e19;  // sd 3.2e9 N/m^2
  double p0_Kr = 1e19;
  // Unscented variants (ukf-coeff-*): the sigma points; P0 is the EKF's above (the model is
  // linear in its state, so a coefficient sigma point's sign does not matter).
  kalman::UnscentedOptions ukf;
  // ekf-coeff-xy-per-tooth and ukf-coeff-xy-per-tooth only.
  ToothGate gate = ToothGate::kNone;
  int history_points = 2000;  // as ModalEkfOptions
};

// 000's tuning and model: forward Euler (eqs 4.3, 4.15, 4.23), Q, R, P0 of eqs 6.1-6.7 (the
// x-only filter drops the y entries). On the tests' records the coefficient filters converge
// with them (within 1.4 %) but the modal filters do not: k never leaves its initial value (its
// P0 is tiny next to the force noise Q) and m, c diverge in most runs (docs/estimators.md).
// Kept selectable for comparison with 000.
ModalEkfOptions modal_options_000();
CoeffEkfOptions coeff_options_000();

// Throw InputError naming the first field that breaks its rule ("ekf.r_m2 = -1: must be > 0").
void validate(const ModalEkfOptions& o);
void validate(const CoeffEkfOptions& o);

}  // namespace estimate
}  // namespace chatterlab
