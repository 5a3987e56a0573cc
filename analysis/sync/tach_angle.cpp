#include "analysis/sync/tach_angle.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "analysis/common/constants.h"
#include "analysis/common/number_text.h"
#include "analysis/signal/pulses.h"
#include "analysis/signal/unwrap.h"

namespace chatterlab {
namespace sync {

namespace {

double median(std::vector<double>* v) {
  const auto mid = v->begin() + static_cast<std::ptrdiff_t>(v->size() / 2);
  std::nth_element(v->begin(), mid, v->end());
  return *mid;
}

}  // namespace

double wrap_phase_rad(double phase_rad) {
  double w = std::fmod(phase_rad, kTwoPi);
  if (w < 0.0) w += kTwoPi;
  if (w >= kTwoPi) w = 0.0;  // fmod of a tiny negative value rounds up to 2 pi
  return w;
}

TachAngle tach_angle(const Eigen::Ref<const Eigen::VectorXd>& tach_V, double fs_hz,
                     double spindle_rpm, const TachOptions& options) {
  validate(options);
  if (!(fs_hz > 0.0) || !std::isfinite(fs_hz)) {
    throw InputError("tach_angle: fs_hz = " + stream_text(fs_hz) + ": must be finite and > 0");
  }
  if (!(spindle_rpm > 0.0) || !std::isfinite(spindle_rpm)) {
    throw InputError("tach_angle: spindle_rpm = " + stream_text(spindle_rpm) +
                     ": must be finite and > 0");
  }
  TachAngle r;
  r.fs_hz = fs_hz;
  r.expected_rpm = spindle_rpm;

  // Levels: medians of the samples below and above the mid-range.
  std::vector<double> finite;
  finite.reserve(static_cast<std::size_t>(tach_V.size()));
  for (Eigen::Index i = 0; i < tach_V.size(); ++i) {
    if (std::isfinite(tach_V[i])) finite.push_back(tach_V[i]);
  }
  if (finite.empty()) {
    r.summary.fail("no tachometer edges: the tach channel has no finite sample (" +
                   std::to_string(tach_V.size()) + " samples)");
    return r;
  }
  const auto [lo_it, hi_it] = std::minmax_element(finite.begin(), finite.end());
  const double lo = *lo_it;
  const double hi = *hi_it;
  if (!(hi > lo)) {
    r.summary.fail("no tachometer edges: the tach channel is flat at " + stream_text(lo) + " V");
    return r;
  }
  const double mid = 0.5 * (lo + hi);
  std::vector<double> below;
  std::vector<double> above;
  for (double v : finite) (v < mid ? below : above).push_back(v);
  r.low_V = median(&below);
  r.high_V = median(&above);
  r.threshold_V = options.threshold_V.value_or(0.5 * (r.low_V + r.high_V));
  r.hysteresis_V = options.hysteresis_fraction * (r.high_V - r.low_V);

  r.edges = signal::rising_edges(tach_V, r.threshold_V, r.hysteresis_V);
  if (r.edges.empty()) {
    r.summary.fail("no tachometer edges: tach never rises through " + stream_text(r.threshold_V) +
                   " V after being below " + stream_text(r.threshold_V - r.hysteresis_V) +
                   " V (levels " + stream_text(r.low_V) + " and " + stream_text(r.high_V) + " V, " +
                   std::to_string(tach_V.size()) + " samples)");
    return r;
  }
  if (r.edges.size() < 2) {
    r.summary.fail("fewer than 2 tachometer edges: one edge at t = " +
                   stream_text(r.edges[0] / fs_hz) + " s; a revolution needs two");
    return r;
  }
  r.revolutions = static_cast<int>(r.edges.size()) - 1;

  // Speed of every revolution against the nominal one.
  const double expected_samples = fs_hz * 60.0 / spindle_rpm;
  r.min_rpm = std::numeric_limits<double>::infinity();
  r.max_rpm = 0.0;
  int off = 0;
  std::size_t first_off = 0;
  for (std::size_t k = 0; k + 1 < r.edges.size(); ++k) {
    const double interval = r.edges[k + 1] - r.edges[k];
    const double rpm = fs_hz * 60.0 / interval;
    r.min_rpm = std::min(r.min_rpm, rpm);
    r.max_rpm = std::max(r.max_rpm, rpm);
    if (std::abs(interval / expected_samples - 1.0) > options.rpm_tolerance) {
      if (off++ == 0) first_off = k;
    }
  }
  r.measured_rpm = fs_hz * 60.0 * r.revolutions / (r.edges.back() - r.edges.front());
  if (off > 0) {
    const double interval = r.edges[first_off + 1] - r.edges[first_off];
    std::ostringstream m;
    m << "tachometer speed disagrees with spindle_rpm: revolution " << first_off
      << " (edges at t = " << stream_text(r.edges[first_off] / fs_hz) << " and "
      << stream_text(r.edges[first_off + 1] / fs_hz) << " s) measures "
      << stream_text(fs_hz * 60.0 / interval) << " rpm, expected " << stream_text(spindle_rpm)
      << " rpm (more than " << stream_text(100.0 * options.rpm_tolerance) << " % apart; " << off
      << " of " << r.revolutions
      << " revolutions off: a missed or spurious pulse, or a wrong spindle_rpm)";
    r.summary.fail(m.str());
    return r;
  }

  // Unwrapped phase, linear between edges, extrapolated at the first/last revolution's rate.
  const Eigen::Index n = tach_V.size();
  r.phase_rad.resize(n);
  std::size_t k = 0;  // revolution whose rate applies: edges[k] .. edges[k + 1]
  const std::size_t last_rev = r.edges.size() - 2;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    while (k < last_rev && t >= r.edges[k + 1]) ++k;
    const double e0 = r.edges[k];
    const double e1 = r.edges[k + 1];
    r.phase_rad[i] = kTwoPi * (static_cast<double>(k) + (t - e0) / (e1 - e0));
  }
  r.summary.succeed();
  return r;
}

Eigen::VectorXd theta1_rad(const TachAngle& tach, double offset_angle_deg) {
  const double offset = offset_angle_deg * kPi / 180.0;
  Eigen::VectorXd theta(tach.phase_rad.size());
  for (Eigen::Index i = 0; i < theta.size(); ++i) {
    theta[i] = wrap_phase_rad(tach.phase_rad[i] + offset);
  }
  return theta;
}

Eigen::VectorXd theta1_unwrapped_rad(const TachAngle& tach, double offset_angle_deg) {
  return signal::unwrap_phase_rad(theta1_rad(tach, offset_angle_deg));
}

}  // namespace sync
}  // namespace chatterlab
