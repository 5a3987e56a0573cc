// Centrifugal and Coriolis inertial forces and the eccentric spring reference of 000 ch. 7.
//
// With the deflection d = (x, y) from the rotation axis, R = |d| (eq. 7.2), phi its angle from +x
// (eq. 7.7, i.e. atan2(y, x)), Rdot = d . v / R (eq. 7.4) and the spindle speed w in rad/s:
//   centrifugal  m R w^2 (cos phi, sin phi)           = m w^2 d                 (eqs 7.1, 7.5-7.6)
//   Coriolis     2 m Rdot w (-sin phi, cos phi)       = 2 m w (d . v / R^2) (-y, x)
// Eq. 7.3 prints F_Cor = 2 Rdot w, an acceleration; the mass is restored here (the text calls it
// a force and Fig. 7.3 plots it in newtons). The Coriolis force points along +phi
// (counter-clockwise), against the tool's clockwise rotation (increasing theta), as the text
// says. At R = 0 its direction is undefined (000 sec. 7.2 starts at 1e-8 m for that reason); it
// is taken as 0 there.
//
// Eccentric spring reference (eqs 7.8-7.9): the springs pull towards
//   x_ref = r0 (sin(theta_1 - theta0), cos(theta_1 - theta0)),
// a point turning with the tool at r0 from the axis; with the angle convention of the tooth
// tips it trails tooth 1 by theta0 (docs/simulator.md on the text's "clockwise from y").
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace chatterlab {
namespace milling {

struct InertialForces {
  Eigen::Vector2d centrifugal_N = Eigen::Vector2d::Zero();
  Eigen::Vector2d coriolis_N = Eigen::Vector2d::Zero();
};

// @param deflection_m d = (x, y), m;  @param velocity_m_s (xdot, ydot), m/s;
// @param mass_kg modal mass m (m_x = m_y);  @param omega_rad_s spindle speed, rad/s
inline InertialForces inertial_forces(const Eigen::Vector2d& deflection_m,
                                      const Eigen::Vector2d& velocity_m_s, double mass_kg,
                                      double omega_rad_s) {
  InertialForces f;
  f.centrifugal_N = mass_kg * omega_rad_s * omega_rad_s * deflection_m;
  const double R2 = deflection_m.squaredNorm();
  if (R2 > 0.0) {
    const double scale = 2.0 * mass_kg * omega_rad_s * deflection_m.dot(velocity_m_s) / R2;
    f.coriolis_N = scale * Eigen::Vector2d(-deflection_m.y(), deflection_m.x());
  }
  return f;
}

// r0 (sin(theta_1 - theta0), cos(theta_1 - theta0)), m (eqs 7.8-7.9).
inline Eigen::Vector2d eccentric_spring_reference_m(double eccentricity_m,
                                                    double eccentricity_angle_rad,
                                                    double theta1_rad) {
  const double a = theta1_rad - eccentricity_angle_rad;
  return {eccentricity_m * std::sin(a), eccentricity_m * std::cos(a)};
}

}  // namespace milling
}  // namespace chatterlab
