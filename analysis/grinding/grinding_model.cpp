#include "analysis/grinding/grinding_model.h"

#include <algorithm>
#include <cmath>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace grinding {

double wear_constant(const GrindingParameters& p) {
  // 002 eq. 3: the G-ratio law G = G1 (v_s / Q'_w)^g with Q'_w = pi d_w v on the wheel volume
  // pi d_s^2 / 4, with 1 / d_s replaced by the constant 1 / d_s0.
  return 2.0 * std::pow(kPi, p.g) * std::pow(p.dw_mm, 1.0 + p.g) * std::pow(p.vs_m_s, -p.g) /
         (p.ds0_mm * p.G1);
}

ProcessState process_derivative(const ProcessState& X, double u_mm_s, const GrindingParameters& p,
                                double wear_k, Eigen::Matrix<double, 4, 4>* J) {
  const double x2 = X[kV];
  const double x2p = std::max(x2, 0.0);
  const double x2p_g = x2 > 0.0 ? std::pow(x2p, p.g) : 0.0;  // x2+^g, once
  ProcessState F;
  F[kVw] = kPi * p.dw_mm * x2;      // eq. 2
  F[kV] = (u_mm_s - x2) / p.tau_s;  // eq. 1
  F[kDs] = -wear_k * x2p_g * x2p;   // eq. 3: -k x2+^(1+g)
  F[kR0] = 0.0;                     // a parameter
  if (J != nullptr) {
    J->setZero();
    (*J)(kVw, kV) = kPi * p.dw_mm;
    (*J)(kV, kV) = -1.0 / p.tau_s;
    (*J)(kDs, kV) = -wear_k * (1.0 + p.g) * x2p_g;
  }
  return F;
}

ProcessState euler_step(const ProcessState& X, double u_mm_s, double T_f_s,
                        const GrindingParameters& p, double wear_k,
                        Eigen::Matrix<double, 4, 4>* A) {
  Eigen::Matrix<double, 4, 4> J;
  const ProcessState F = process_derivative(X, u_mm_s, p, wear_k, A != nullptr ? &J : nullptr);
  if (A != nullptr) *A = Eigen::Matrix<double, 4, 4>::Identity() + T_f_s * J;
  return X + T_f_s * F;  // 002 eq. 8
}

Outputs outputs(const ProcessState& X, const GrindingParameters& p,
                Eigen::Matrix<double, 4, 4>* H) {
  const double x1 = X[kVw];
  const double x2 = X[kV];
  const double R0 = X[kR0];
  const double x1p = std::max(x1, 0.0);
  // x1+^delta and its derivative (delta = 1, 002 table II: no pow).
  const bool linear = p.delta == 1.0;
  const double x1d = linear ? x1p : std::pow(x1p, p.delta);
  const double dx1d = x1 > 0.0 ? (linear ? 1.0 : p.delta * std::pow(x1p, p.delta - 1.0)) : 0.0;
  const double specific = p.Ks_W_s_mm * (p.s0 + p.s1_per_mm2 * x1d);
  const double h_um = kPi * p.dw_mm * std::max(x2, kMinInfeedForRoughness_mm_s) / p.vs_m_s;
  const double h_gamma = std::pow(h_um, p.gamma);
  const double decay = std::exp(-x1 / p.V0_mm2);
  const double Ra = (p.Rg_um + (R0 - p.Rg_um) * decay) * h_gamma;  // eq. 11
  Outputs y;
  y[kPower] = specific * x2;
  y[kDw] = 2.0 * x1 / (kPi * p.dw_mm);
  y[kDsOut] = X[kDs];
  y[kRa] = Ra;
  if (H != nullptr) {
    H->setZero();
    (*H)(kPower, kVw) = p.Ks_W_s_mm * p.s1_per_mm2 * dx1d * x2;
    (*H)(kPower, kV) = specific;
    (*H)(kDw, kVw) = 2.0 / (kPi * p.dw_mm);
    (*H)(kDsOut, kDs) = 1.0;
    (*H)(kRa, kVw) = -(R0 - p.Rg_um) / p.V0_mm2 * decay * h_gamma;
    (*H)(kRa, kV) = x2 >= kMinInfeedForRoughness_mm_s ? p.gamma * Ra / x2 : 0.0;
    (*H)(kRa, kR0) = decay * h_gamma;
  }
  return y;
}

double roundness_um(const ProcessState& X, const GrindingParameters& p) {
  // 002 appendix A: r = r0 pi d_w x2 / v_w + r_m (pi d_w x2 / v_w in um for v_w in m/s).
  return p.r0 * kPi * p.dw_mm * X[kV] / p.vw_m_s + p.rm_um;
}

}  // namespace grinding
}  // namespace chatterlab
