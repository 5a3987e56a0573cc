#include "analysis/sync/tip_deflection.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "analysis/common/number_text.h"

namespace chatterlab {
namespace sync {

int contour_phase_points(const TachAngle& tach, const ContourOptions& options) {
  if (options.phase_points > 0) return options.phase_points;
  const double per_rev = tach.fs_hz * 60.0 / tach.expected_rpm;
  return std::max(8, static_cast<int>(std::lround(per_rev)));
}

TipDeflection tip_deflection(const Eigen::Ref<const Eigen::VectorXd>& x_sensor_m,
                             const Eigen::Ref<const Eigen::VectorXd>& y_sensor_m,
                             const TachAngle& tach, double sensor_to_tip, double air_start_s,
                             double air_end_s, const ContourOptions& options) {
  validate(options);
  if (!(sensor_to_tip > 0.0) || !std::isfinite(sensor_to_tip)) {
    throw InputError("tip_deflection: sensor_to_tip = " + stream_text(sensor_to_tip) +
                     ": must be finite and > 0");
  }
  if (!std::isfinite(air_start_s) || !std::isfinite(air_end_s) || !(air_end_s > air_start_s)) {
    throw InputError("tip_deflection: air_window_s = [" + stream_text(air_start_s) + ", " +
                     stream_text(air_end_s) + "]: must be finite with start < end");
  }
  TipDeflection r;
  if (!tach.summary.ok()) {
    r.summary.fail("no tachometer angle: " + tach.summary.message);
    return r;
  }
  const Eigen::Index n = tach.phase_rad.size();
  if (x_sensor_m.size() != n || y_sensor_m.size() != n) {
    std::ostringstream m;
    m << "tip_deflection: x has " << x_sensor_m.size() << " samples, y " << y_sensor_m.size()
      << ", the tachometer record " << n << ": must be equal";
    throw InputError(m.str());
  }

  const RevolutionRange air = whole_revolutions_in(tach, air_start_s, air_end_s);
  if (air.count < options.min_air_revolutions) {
    std::ostringstream m;
    m << "air window too short: air_window_s = [" << stream_text(air_start_s) << ", "
      << stream_text(air_end_s) << "] holds " << air.count << " whole tachometer revolution"
      << (air.count == 1 ? "" : "s") << " (between rising edges), need at least "
      << options.min_air_revolutions << " for the runout contour";
    r.summary.fail(m.str());
    return r;
  }

  const Eigen::VectorXd x_tip = sensor_to_tip * x_sensor_m;
  const Eigen::VectorXd y_tip = sensor_to_tip * y_sensor_m;
  r.contour = mean_revolution(x_tip, y_tip, tach, air, contour_phase_points(tach, options));
  if (!r.contour.x_m.allFinite() || !r.contour.y_m.allFinite()) {
    const double a = tach.edges[static_cast<std::size_t>(air.first)] / tach.fs_hz;
    const double b = tach.edges[static_cast<std::size_t>(air.first + air.count)] / tach.fs_hz;
    r.summary.fail("runout contour not finite: NaN or infinite x or y samples between t = " +
                   stream_text(a) + " and " + stream_text(b) + " s (the air revolutions)");
    r.contour = RevolutionMean{};
    return r;
  }

  r.x_m.resize(n);
  r.y_m.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double phi = tach.phase_rad[i];
    r.x_m[i] = x_tip[i] - periodic_interpolate(r.contour.x_m, phi);
    r.y_m[i] = y_tip[i] - periodic_interpolate(r.contour.y_m, phi);
  }

  // Residual over the air revolutions: the samples from edge e_first to e_(first + count).
  const auto i0 =
      static_cast<Eigen::Index>(std::ceil(tach.edges[static_cast<std::size_t>(air.first)]));
  const auto i1 = static_cast<Eigen::Index>(
      std::floor(tach.edges[static_cast<std::size_t>(air.first + air.count)]));
  const Eigen::Index len = std::max<Eigen::Index>(0, i1 - i0 + 1);
  if (len > 0) {
    r.air_residual_rms_x_m = std::sqrt(r.x_m.segment(i0, len).squaredNorm() / len);
    r.air_residual_rms_y_m = std::sqrt(r.y_m.segment(i0, len).squaredNorm() / len);
  }
  r.summary.succeed();
  return r;
}

}  // namespace sync
}  // namespace chatterlab
