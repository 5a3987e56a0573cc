// Symplectic Euler for the two uncoupled modal axes of 000 eqs 2.5-2.6 (000 sec. 5.2, [59]).
//
// One step of size h on one axis, with a = (F - c v - k (x - x_ref)) / m:
//   kick:  v <- v + h a = a_v v + a_x (x - x_ref) + b_F F,   a_v = 1 - h c/m, a_x = -h k/m,
//          b_F = h/m
//   drift: x <- x + h v
// Velocity first is kick(x_k) then drift; position first is drift then kick(x_{k+1}) (the
// velocity in the damping term is the old one in both). Each is a symplectic map when c = 0
// (determinant of the step matrix 1) and conserves the quadratic invariant
//   Q = v^2 + w^2 x^2 -/+ h w^2 x v   (velocity first: minus; position first: plus), w^2 = k/m,
// so the energy stays within a factor 1 +- w h / 2 of its start instead of drifting.
#pragma once

#include "analysis/milling/simulation_options.h"

namespace chatterlab {
namespace milling {

struct SymplecticEulerAxis {
  double h = 0.0;    // time step, s
  double a_v = 1.0;  // 1 - h c / m
  double a_x = 0.0;  // -h k / m
  double b_F = 0.0;  // h / m

  void kick(double& v, double x_minus_ref, double force_N) const {
    v = a_v * v + a_x * x_minus_ref + b_F * force_N;
  }
  void drift(double& x, double v) const { x += h * v; }
};

inline SymplecticEulerAxis symplectic_euler_axis(const AxisModal& a, double h) {
  SymplecticEulerAxis s;
  s.h = h;
  s.a_v = 1.0 - h * a.c_kg_s / a.m_kg;
  s.a_x = -h * a.k_N_m / a.m_kg;
  s.b_F = h / a.m_kg;
  return s;
}

// One full step of either order for a force that does not depend on the state (tests, static
// balance); the simulator interleaves the state-dependent force itself.
inline void symplectic_euler_step(const SymplecticEulerAxis& s, EulerOrder order, double& x,
                                  double& v, double force_N) {
  if (order == EulerOrder::kVelocityFirst) {
    s.kick(v, x, force_N);
    s.drift(x, v);
  } else {
    s.drift(x, v);
    s.kick(v, x, force_N);
  }
}

}  // namespace milling
}  // namespace chatterlab
