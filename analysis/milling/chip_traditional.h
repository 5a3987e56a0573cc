// Traditional chip thickness, 000 eq. 2.7: a circular tooth path and a delay of one tooth
// period tau,
//   w_p(t) = h sin(theta_p) + [x(t) - x(t - tau)] sin(theta_p) + [y(t) - y(t - tau)] cos(theta_p),
// i.e. the feed plus the change of the deflection over one tooth period, both projected on the
// tooth's radial direction (sin theta_p, cos theta_p) (force_model.h conventions). The
// switching function uses the fixed engagement window of engagement.h.
#pragma once

namespace chatterlab {
namespace milling {

// @param feed_per_tooth_m h, m;  @param sin_theta, cos_theta of theta_p;
// @param dx_m x(t) - x(t - tau), m;  @param dy_m y(t) - y(t - tau), m.  Returns w_p, m (may be
// negative: the tooth is then behind the surface the previous tooth left).
inline double chip_thickness_traditional(double feed_per_tooth_m, double sin_theta,
                                         double cos_theta, double dx_m, double dy_m) {
  return (feed_per_tooth_m + dx_m) * sin_theta + dy_m * cos_theta;
}

}  // namespace milling
}  // namespace chatterlab
