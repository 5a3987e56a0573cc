// Per-tooth milling force model: 000 eqs 2.1-2.4 with gamma = 1, plus the edge terms of
// 000 eqs 3.3-3.4. Scalar and fixed-size types so that a simulator can call it per tooth and
// per time step.
//
// Conventions (000 ch. 2, Fig. 2.1): tooth p sits at angle
//   theta_p = theta_1 + (p - 1) 2 pi / n,                  p = 1..n,
// measured from the +y axis towards +x, its tip at (r sin theta_p, r cos theta_p), the tool
// turning with increasing theta. F_t opposes the cutting velocity, F_r points at the tool axis;
// both are positive in these directions and act on the tool.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "analysis/common/cutting_coefficients.h"

namespace chatterlab {
namespace milling {

// Cutting-force coefficients of 000 eqs 3.3-3.4 (Kt, Kr: eqs 2.1-2.2's; Kte, Kre the edge
// terms), common/cutting_coefficients.h.
using CuttingCoefficients = chatterlab::CuttingCoefficients;

// Force on one tooth, in its own tangential/radial directions (N).
struct ToothForce {
  double tangential_N = 0.0;
  double radial_N = 0.0;
};

// theta_p = theta_1 + (p - 1) 2 pi / n (000 ch. 2), not wrapped. Throws InputError unless
// 1 <= p <= n.
double tooth_angle_rad(double theta1_rad, int p, int n);

// Tooth tip relative to the tool centre, (r sin theta, r cos theta) (000 eqs 2.10-2.11 without
// deflection and feed).
Eigen::Vector2d tooth_tip_position_m(double radius_m, double theta_rad);

// Static chip thickness h sin theta, the first term of 000 eq. 2.7.
double static_chip_thickness_m(double feed_per_tooth_m, double theta_rad);

// True when theta (wrapped to [0, 2 pi)) lies in the engagement window [entry, exit) of the
// traditional model (000 eqs 2.8-2.9: up-milling, entry 0). Full slot: entry 0, exit pi.
// Half-open so that at a tooth change of a two-tooth slot exactly one tooth cuts.
// Requires 0 <= entry <= exit <= 2 pi (not checked: called per tooth and time step).
bool in_cut(double theta_rad, double entry_rad, double exit_rad);

// Per-tooth forces, 000 eqs 2.1-2.2 (gamma = 1) with the edge terms of eqs 3.3-3.4:
//   F_t = g (Ktc b w + Kte b),   F_r = g (Krc b w + Kre b).
// Zero when the tooth is not engaged (g = 0) or when w <= 0: a tooth with no chip (it left the
// material, e.g. a negative dynamic chip of eq. 2.7) neither cuts nor rubs.
// @param chip_thickness_m w_p, m;  @param depth_m axial depth b, m
ToothForce tooth_force(const CuttingCoefficients& k, double chip_thickness_m, double depth_m,
                       bool engaged);

// Projection of one tooth's force on the x/y axes, the summand of 000 eqs 2.3-2.4:
//   Fx = -(F_t cos theta + F_r sin theta),   Fy = F_t sin theta - F_r cos theta.
Eigen::Vector2d tooth_force_xy_N(const ToothForce& f, double theta_rad);

// Per-tooth forces with the chip's sign kept, for the switching function by angle alone
// (000 sec. 2.2 read literally: g = 1 in the engagement window whatever the chip):
//   F_t = g (Ktc b w + Kte b),   F_r = g (Krc b w + Kre b)   for any w (negative: pulling).
inline ToothForce tooth_force_signed(const CuttingCoefficients& k, double chip_thickness_m,
                                     double depth_m, bool engaged) {
  ToothForce f;
  if (!engaged) return f;
  f.tangential_N = k.Kt_N_m2 * depth_m * chip_thickness_m + k.Kte_N_m * depth_m;
  f.radial_N = k.Kr_N_m2 * depth_m * chip_thickness_m + k.Kre_N_m * depth_m;
  return f;
}

// tooth_force_xy_N with sin(theta) and cos(theta) given (a simulator precomputes them per step).
inline Eigen::Vector2d tooth_force_xy_N(const ToothForce& f, double sin_theta, double cos_theta) {
  return {-(f.tangential_N * cos_theta + f.radial_N * sin_theta),
          f.tangential_N * sin_theta - f.radial_N * cos_theta};
}

}  // namespace milling
}  // namespace chatterlab
