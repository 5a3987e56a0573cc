// The plunge-grinding model of 002 (C. W. Lee, IEEE TCST 2007): a series of cycles ground one
// after another with one wheel, in the unit system of the campaign format (kind `grinding`,
// docs/format/test-kinds.md), since 002's table II units do not close (docs/grinding.md):
//
//   state x = (x1, x2, x3) = (V'_w in mm^2, v in mm/s, d_s in mm), parameter R0 in um;
//   inputs u1 = commanded infeed u (mm/s), u2 = wheel speed v_s (m/s, a constant);
//
//   x1' = pi d_w x2                                                     002 eq. 2
//   x2' = (u1 - x2) / tau                                               002 eq. 1
//   x3' = -k x2^(1+g),  k = 2 pi^g d_w^(1+g) v_s^-g / (d_s0 G1)         002 eq. 3
//
//   P   = K_s (s0 + s1 x1^delta) x2                 (W)                  002 app. A
//   D_w = 2 x1 / (pi d_w)                           (mm)                 002 app. A
//   d_s = x3                                        (mm)
//   R_a = [R_g + (R0 - R_g) exp(-x1 / V'_0)] h^gamma,  h = pi d_w x2 / v_s  (um)  002 eq. 11
//   r   = r0 pi d_w x2 / v_w + r_m                  (um)                 002 app. A
//
// with v_s in m/s in eq. 3 and in h (h is then in um and eq. 3 gives G-ratios near 70). Eq. 3
// keeps the constant d_s0 of 002, not x3. Guards (format section 7): x1^delta is
// max(x1, 0)^delta (derivative 0 for x1 <= 0); x2 is max(x2, 0) in x2^(1+g) and its derivative,
// max(x2, 1e-6 mm/s) in h, and dR_a/dx2 = 0 below 1e-6 mm/s.
//
// Discretized by forward Euler over the fast period T_f (002 eq. 8): X+ = X + T_f F(X, u).
#pragma once

#include <Eigen/Core>
#include <limits>

namespace chatterlab {
namespace grinding {

// test.yaml `model:` (002 eqs 1-3, appendix A, table II), in the units of the key names.
struct GrindingParameters {
  double dw_mm = 70;   // workpiece diameter d_w
  double ds0_mm = 50;  // wheel diameter at the start of cycle 1; d_s0 of eq. 3
  double vs_m_s = 37;  // wheel speed v_s = u2
  double vw_m_s = std::numeric_limits<double>::quiet_NaN();  // work speed (roundness only)
  double tau_s = 1.5;       // time constant of eq. 1 (002 gives none)
  double Ks_W_s_mm = 2380;  // K_s: K_s (s0 + s1 x1^delta) in W s/mm
  double s0 = 49.6;
  double s1_per_mm2 = 0.08;  // per (mm^2)^delta
  double delta = 1.0;
  double gamma = 0.2;
  double Rg_um = 0.7;
  double R0_um = 3.0;                                       // nominal R0: the filters start from it
  double V0_mm2 = 300;                                      // V'_0
  double rm_um = std::numeric_limits<double>::quiet_NaN();  // roundness r_m (optional)
  double r0 = std::numeric_limits<double>::quiet_NaN();     // roundness r_0 (optional)
  double G1 = 13;
  double g = 0.9;  // wear exponent (002 table II prints it as "G")
};

// Below this infeed (mm/s) h and dR_a/dx2 use the guard of the format's section 7.
constexpr double kMinInfeedForRoughness_mm_s = 1e-6;

// k of eq. 3 (mm^-g s^g ... such that x3' = -k x2^(1+g) in mm/s for x2 in mm/s).
double wear_constant(const GrindingParameters& p);

// The full state of the process: x1, x2, x3 and R0.
using ProcessState = Eigen::Matrix<double, 4, 1>;
enum StateIndex : int { kVw = 0, kV = 1, kDs = 2, kR0 = 3 };

// F(X, u) of eqs 1-3 (R0 constant: its derivative is 0), and its Jacobian dF/dX when `J` is
// not null (row kR0 zero). `wear_k` = wear_constant(p) (a filter computes it once).
ProcessState process_derivative(const ProcessState& X, double u_mm_s, const GrindingParameters& p,
                                double wear_k, Eigen::Matrix<double, 4, 4>* J = nullptr);
inline ProcessState process_derivative(const ProcessState& X, double u_mm_s,
                                       const GrindingParameters& p,
                                       Eigen::Matrix<double, 4, 4>* J = nullptr) {
  return process_derivative(X, u_mm_s, p, wear_constant(p), J);
}

// One fast step of eq. 8: X + T_f F(X, u); A = I + T_f dF/dX when `A` is not null.
ProcessState euler_step(const ProcessState& X, double u_mm_s, double T_f_s,
                        const GrindingParameters& p, double wear_k,
                        Eigen::Matrix<double, 4, 4>* A = nullptr);
inline ProcessState euler_step(const ProcessState& X, double u_mm_s, double T_f_s,
                               const GrindingParameters& p,
                               Eigen::Matrix<double, 4, 4>* A = nullptr) {
  return euler_step(X, u_mm_s, T_f_s, p, wear_constant(p), A);
}

// The measured outputs, in the order of the filters' measurement vector.
enum OutputIndex : int { kPower = 0, kDw = 1, kDsOut = 2, kRa = 3 };
using Outputs = Eigen::Matrix<double, 4, 1>;

// (P in W, D_w in mm, d_s in mm, R_a in um) at X, and dH/dX (4 x 4) when `H` is not null.
Outputs outputs(const ProcessState& X, const GrindingParameters& p,
                Eigen::Matrix<double, 4, 4>* H = nullptr);

// Roundness r (um) at X (NaN when the model has no r0, r_m or v_w).
double roundness_um(const ProcessState& X, const GrindingParameters& p);

}  // namespace grinding
}  // namespace chatterlab
