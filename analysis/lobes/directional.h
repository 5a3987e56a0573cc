// The directional matrix of the linearized milling force (lobes.h) integrated over angles:
// shared by the semi-discretization (per time interval) and the zero-order approximation
// (over the engagement window).
#pragma once

#include <Eigen/Core>

namespace chatterlab {
namespace lobes {

// Integral over theta in [a, b] (a <= b, unwrapped) of one tooth's
//   h(theta) = [-(Kt cos + Kr sin); Kt sin - Kr cos] [sin, cos]
// (lobes.h; force_model.h directions), by the antiderivatives
//   int sin^2 = theta/2 - sin(2 theta)/4, int cos^2 = theta/2 + sin(2 theta)/4,
//   int sin cos = -cos(2 theta)/4.
Eigen::Matrix2d directional_integral(double Kt_N_m2, double Kr_N_m2, double a_rad, double b_rad);

// Integral of h over the engaged part of the tooth's path [theta0, theta0 + dtheta]
// (0 <= dtheta < 2 pi, theta0 any angle): the parts inside the engagement window
// [entry, exit] (milling/engagement.h, 0 <= entry <= exit <= pi) or its copy 2 pi later.
Eigen::Matrix2d engaged_integral(double Kt_N_m2, double Kr_N_m2, double theta0_rad,
                                 double dtheta_rad, double entry_rad, double exit_rad);

}  // namespace lobes
}  // namespace chatterlab
