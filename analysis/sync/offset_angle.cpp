#include "analysis/sync/offset_angle.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "analysis/common/angles.h"
#include "analysis/common/constants.h"
#include "analysis/common/number_text.h"
#include "analysis/common/stopwatch.h"
#include "analysis/milling/simulation.h"

namespace chatterlab {
namespace sync {

namespace {

// Every tooth has the same coefficients (the simulated revolution repeats every tooth pitch).
bool teeth_alike(const milling::SimulationOptions& o) {
  const milling::CuttingCoefficients& k0 = o.coefficients.front();
  for (const milling::CuttingCoefficients& k : o.coefficients) {
    if (k.Kt_N_m2 != k0.Kt_N_m2 || k.Kr_N_m2 != k0.Kr_N_m2 || k.Kte_N_m != k0.Kte_N_m ||
        k.Kre_N_m != k0.Kre_N_m) {
      return false;
    }
  }
  return true;
}

}  // namespace

ComparisonWindow comparison_window(const CutSchedule& cut, double spindle_rpm, int revolutions,
                                   double depth_m) {
  if (!std::isfinite(cut.cut_start_s) || !std::isfinite(cut.cut_end_s) ||
      !(cut.cut_end_s > cut.cut_start_s)) {
    throw InputError("comparison_window: cut_window_s = [" + stream_text(cut.cut_start_s) + ", " +
                     stream_text(cut.cut_end_s) + "]: must be finite with start < end");
  }
  if (!std::isfinite(cut.depth_start_m) || !std::isfinite(cut.depth_end_m) ||
      cut.depth_start_m < 0.0 || cut.depth_end_m < 0.0) {
    throw InputError("comparison_window: axial depth [" + stream_text(cut.depth_start_m) + ", " +
                     stream_text(cut.depth_end_m) + "] m: must be finite and >= 0");
  }
  if (!(spindle_rpm > 0.0) || !std::isfinite(spindle_rpm)) {
    throw InputError("comparison_window: spindle_rpm = " + stream_text(spindle_rpm) +
                     ": must be > 0");
  }
  if (revolutions < 1) {
    throw InputError("comparison_window: revolutions = " + std::to_string(revolutions) +
                     ": must be >= 1");
  }
  const double T = 60.0 / spindle_rpm;
  const double length = (revolutions + 1) * T;
  const double lo = cut.cut_start_s + T;  // one revolution inside the cut at both ends
  const double hi = cut.cut_end_s - T;
  if (hi - lo < length) {
    throw InputError("comparison_window: " + std::to_string(revolutions) +
                     " revolutions (+1, and one at each end) do not fit in cut_window_s = [" +
                     stream_text(cut.cut_start_s) + ", " + stream_text(cut.cut_end_s) + "] at " +
                     stream_text(spindle_rpm) + " rpm");
  }
  ComparisonWindow w;
  if (cut.depth_end_m == cut.depth_start_m) {
    w.end_s = hi;
  } else {
    const double d0 = std::min(cut.depth_start_m, cut.depth_end_m);
    const double d1 = std::max(cut.depth_start_m, cut.depth_end_m);
    if (!(depth_m >= d0 && depth_m <= d1)) {
      throw InputError("comparison_window: depth " + stream_text(depth_m * 1e3) +
                       " mm: must lie within the ramp's depths [" + stream_text(d0 * 1e3) + ", " +
                       stream_text(d1 * 1e3) + "] mm");
    }
    const double t = cut.cut_start_s + (depth_m - cut.depth_start_m) /
                                           (cut.depth_end_m - cut.depth_start_m) *
                                           (cut.cut_end_s - cut.cut_start_s);
    w.end_s = std::clamp(t + 0.5 * length, lo + length, hi);
  }
  w.start_s = w.end_s - length;
  w.depth_m = cut.depth_at_m(0.5 * (w.start_s + w.end_s));
  return w;
}

namespace {

// A measured revolution whose variation is below this fraction of the simulated one is flat.
constexpr double kFlatFraction = 1e-3;

// RMS of (x, y) about their means, over both axes.
double rms_about_mean(const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  if (x.size() == 0) return 0.0;
  return std::sqrt(((x.array() - x.mean()).square().sum() + (y.array() - y.mean()).square().sum()) /
                   (2.0 * static_cast<double>(x.size())));
}

}  // namespace

OffsetAngleResult find_offset_angle(const RevolutionMean& measured,
                                    const milling::SimulationOptions& parameters, double depth_m,
                                    const OffsetSearchOptions& options) {
  validate(options);
  if (!(depth_m > 0.0) || !std::isfinite(depth_m)) {
    throw InputError("find_offset_angle: depth_m = " + stream_text(depth_m) +
                     ": must be finite and > 0");
  }
  milling::SimulationOptions o = parameters;
  o.depth = milling::DepthProfile::constant(depth_m, options.simulated_revolutions);
  milling::validate(o);
  OffsetAngleResult r;
  r.depth_m = depth_m;
  r.measured_revolutions = measured.revolutions;

  const int R = options.simulated_revolutions;
  milling::RecordingRequest rec;
  rec.full_revolutions = {R - 2, R - 1};
  const auto t_sim = std::chrono::steady_clock::now();
  const milling::SimulationResult sim = milling::simulate(o, rec);
  r.simulation_runtime_s = seconds_since(t_sim);
  r.simulated_revolutions = sim.revolutions;
  if (!sim.summary.ok()) {
    r.summary.fail("simulation at " + stream_text(depth_m * 1e3) +
                   " mm failed: " + sim.summary.message);
    return r;
  }
  const milling::RevolutionRecord& prev = sim.records[0];
  const milling::RevolutionRecord& last = sim.records[1];
  const double last_rms =
      std::sqrt((last.x_m.squaredNorm() + last.y_m.squaredNorm()) / (2.0 * last.x_m.size()));
  const double change_rms =
      std::sqrt(((last.x_m - prev.x_m).squaredNorm() + (last.y_m - prev.y_m).squaredNorm()) /
                (2.0 * last.x_m.size()));
  r.settle_change = last_rms > 0.0 ? change_rms / last_rms : 0.0;

  const auto t_search = std::chrono::steady_clock::now();
  const RevolutionMatcher matcher(measured.x_m, measured.y_m, last.x_m, last.y_m);
  // A measured revolution that does not vary (deflection channels of zeros or of a constant:
  // a sensor not connected) matches every angle equally: no offset is found, rather than the
  // search's arbitrary best (issue 16). Compared about the means, as the sensors' static
  // offsets are arbitrary.
  const double measured_ac = rms_about_mean(measured.x_m, measured.y_m);
  const double simulated_ac = rms_about_mean(last.x_m, last.y_m);
  if (!(measured_ac > kFlatFraction * simulated_ac)) {
    r.summary.fail(
        "the measured deflection does not vary over the revolution (RMS about its mean " +
        stream_text(measured_ac, 3) + " m, below " + stream_text(100.0 * kFlatFraction, 2) +
        " % of the simulated revolution's " + stream_text(simulated_ac, 3) + " m at " +
        stream_text(depth_m * 1e3) +
        " mm): no offset angle can be found; are the deflection channels connected "
        "and scaled?");
    return r;
  }

  r.search = search_offset(matcher, o.teeth, options);
  r.model_teeth_alike = teeth_alike(o);
  if (r.model_teeth_alike && r.search.ambiguous) {
    // A settled simulated revolution repeats every 360 / n deg, so E does too and the best and
    // the runner-up tie up to rounding: report the representative in [0, 360 / n).
    OffsetSearch& s = r.search;
    const double folded = std::fmod(s.offset_angle_deg, 360.0 / o.teeth);
    if (folded != s.offset_angle_deg) {
      const double old_deg = s.offset_angle_deg;
      const double old_error = s.rms_error_m;
      s.offset_angle_deg = folded;
      s.rms_error_m = matcher.rms_error_m(folded * kDegToRad);
      if (circular_distance_deg(s.runner_up_deg, folded) < options.coarse_step_deg) {
        s.runner_up_deg = old_deg;
        s.runner_up_error_m = old_error;
      }
      s.runner_up_ratio = s.rms_error_m > 0.0 ? s.runner_up_error_m / s.rms_error_m : 1.0;
    }
  }
  r.search_runtime_s = seconds_since(t_search);
  const double m_rms = matcher.measured_rms_m();
  r.relative_error =
      m_rms > 0.0 ? r.search.rms_error_m / m_rms : std::numeric_limits<double>::quiet_NaN();

  // Synchronized revolution on the measured grid, as theta_1.
  const Eigen::Index N = measured.x_m.size();
  const double offset_rad = r.search.offset_angle_deg * kDegToRad;
  r.theta1_deg.resize(N);
  r.simulated_x_m.resize(N);
  r.simulated_y_m.resize(N);
  r.measured_x_m.resize(N);
  r.measured_y_m.resize(N);
  for (Eigen::Index j = 0; j < N; ++j) {
    const double theta = 2.0 * kPi * static_cast<double>(j) / static_cast<double>(N);
    r.theta1_deg[j] = theta / kDegToRad;
    r.simulated_x_m[j] = periodic_interpolate(last.x_m, theta);
    r.simulated_y_m[j] = periodic_interpolate(last.y_m, theta);
    r.measured_x_m[j] = periodic_interpolate(measured.x_m, theta - offset_rad);
    r.measured_y_m[j] = periodic_interpolate(measured.y_m, theta - offset_rad);
  }

  r.summary.succeed();
  if (r.settle_change > options.settle_tolerance) {
    r.summary.warnings.push_back("simulated revolution not settled after " + std::to_string(R) +
                                 " revolutions: the last two differ by " +
                                 stream_text(100.0 * r.settle_change, 3) +
                                 " % RMS (chatter or slow decay at " + stream_text(depth_m * 1e3) +
                                 " mm): the offset compares with a revolution that is not steady");
  }
  if (r.search.ambiguous) {
    r.summary.warnings.push_back(
        "the other tooth alignment fits almost as well: offset " +
        stream_text(r.search.offset_angle_deg, 5) + " deg (RMS error " +
        stream_text(r.search.rms_error_m, 3) + " m) and " + stream_text(r.search.runner_up_deg, 5) +
        " deg (" + stream_text(r.search.runner_up_error_m, 3) + " m, ratio " +
        stream_text(r.search.runner_up_ratio, 4) +
        "): with alike teeth the offset is defined modulo " + stream_text(360.0 / o.teeth, 4) +
        " deg and tooth numbering follows the better fit");
  }
  return r;
}

}  // namespace sync
}  // namespace chatterlab
