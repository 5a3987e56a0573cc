#include "app/kinds/cut/cut_step.h"

#include <cmath>
#include <cstdio>

#include "analysis/common/cutting_coefficients.h"
#include "analysis/dynamics/noise_level.h"
#include "analysis/dynamics/revolution_sampling.h"
#include "analysis/milling/simulation_options.h"
#include "analysis/sync/tip_deflection.h"
#include "app/core/format.h"
#include "app/core/signals.h"

namespace chatterlab::app {
namespace {

void run_offset(const TestSpec& t, const CutStepInputs& in, const sync::TipDeflection& tip,
                CutOutcome& out) {
  if (!in.hammer_x || !in.coefficients || !in.tool) {
    out.offset_status.fail(
        "offset angle needs the campaign's hammer-test modal parameters (a tap test on x) and "
        "dynamometer coefficients (a dyno-slot group), 000 sec. 5.1; " +
        std::string(!in.hammer_x ? "no tap result" : "no dyno-slot coefficients"));
    return;
  }
  const frf::Mode& my = in.hammer_y ? *in.hammer_y : *in.hammer_x;
  // The dyno coefficients for every tooth, without edge terms (000 sec. 5.1 uses Kt, Kr).
  const milling::SimulationOptions o =
      cut_model(t, *in.tool, *in.hammer_x, my,
                std::vector<CuttingCoefficients>(static_cast<std::size_t>(in.tool->teeth),
                                                 without_edge_terms(*in.coefficients)));
  sync::CutSchedule schedule{
      t.kind_spec<CutSpec>().cut_window_s.first, t.kind_spec<CutSpec>().cut_window_s.second,
      t.kind_spec<CutSpec>().axial_depth_m.first, t.kind_spec<CutSpec>().axial_depth_m.second};
  // Constant depth: the last settled revolutions. Ramp: revolutions around 1 mm or the middle
  // of the ramp when it does not reach 1 mm (000 figs 5.9-5.14 compare near 2 mm in chatter-
  // free cutting; a depth below the bifurcation keeps the comparison on the periodic orbit).
  const double lo = std::min(schedule.depth_start_m, schedule.depth_end_m);
  const double hi = std::max(schedule.depth_start_m, schedule.depth_end_m);
  const double depth = (lo <= 1e-3 && 1e-3 <= hi) ? 1e-3 : 0.5 * (lo + hi);
  const sync::ComparisonWindow w =
      sync::comparison_window(schedule, t.kind_spec<CutSpec>().spindle_rpm, 20, depth);
  const sync::RevolutionRange range = sync::whole_revolutions_in(out.tach, w.start_s, w.end_s);
  if (range.count < 1) {
    out.offset_status.fail("no whole tachometer revolution inside the comparison window " +
                           fmt_sig(w.start_s, 6) + " to " + fmt_sig(w.end_s, 6) + " s");
    return;
  }
  out.offset_measured = sync::mean_revolution(tip.x_m, tip.y_m, out.tach, range,
                                              sync::contour_phase_points(out.tach, {}));
  out.offset = sync::find_offset_angle(out.offset_measured, o, w.depth_m);
  out.offset_status = out.offset.summary;
  if (out.offset.summary.ok() && out.offset.search.ambiguous) {
    out.warnings.push_back("offset angle with the hammer/dyno values: the other half turn (" +
                           fmt_fixed(out.offset.search.runner_up_deg, 2) +
                           " deg) fits almost as well (error ratio " +
                           fmt_fixed(out.offset.search.runner_up_ratio, 3) + ")");
  }
}

// The once-per-revolution samples of the cut window (depth_n_m, x_n_m) and the measurement
// noise of the processed deflection (docs/bifurcation.md); the detector's options.
dynamics::BifurcationOptions sample_revolutions(const TestSpec& t, const sync::TipDeflection& tip,
                                                CutOutcome& out) {
  const double offset = out.offset_status.ok() ? out.offset.search.offset_angle_deg : 0.0;
  const Eigen::VectorXd theta = sync::theta1_unwrapped_rad(out.tach, offset);
  const dynamics::RevolutionCrossings c = dynamics::revolution_crossings(theta, 0.0);
  const Eigen::VectorXd x_all = dynamics::sample_at_crossings(c, tip.x_m);
  const double fs = t.sample_rate_hz;
  const sync::CutSchedule schedule{
      t.kind_spec<CutSpec>().cut_window_s.first, t.kind_spec<CutSpec>().cut_window_s.second,
      t.kind_spec<CutSpec>().axial_depth_m.first, t.kind_spec<CutSpec>().axial_depth_m.second};
  std::vector<double> depth, x;
  for (Eigen::Index n = 0; n < c.size(); ++n) {
    const double ts = c.sample_position[n] / fs;
    if (ts < schedule.cut_start_s || ts > schedule.cut_end_s) continue;
    depth.push_back(schedule.depth_at_m(ts));
    x.push_back(x_all[n]);
  }
  out.depth_n_m =
      Eigen::Map<Eigen::VectorXd>(depth.data(), static_cast<Eigen::Index>(depth.size()));
  out.x_n_m = Eigen::Map<Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
  // Measurement noise from the processed deflection itself (docs/bifurcation.md).
  const auto i0 = static_cast<Eigen::Index>(schedule.cut_start_s * fs);
  const auto i1 =
      std::min<Eigen::Index>(static_cast<Eigen::Index>(schedule.cut_end_s * fs), tip.x_m.size());
  dynamics::BifurcationOptions bo;
  bo.measurement_noise_m = dynamics::white_noise_sigma(tip.x_m.segment(i0, i1 - i0));
  out.detector_noise_m = bo.measurement_noise_m;
  return bo;
}

void run_measured_bifurcation(const TestSpec& t, const sync::TipDeflection& tip, CutOutcome& out) {
  const dynamics::BifurcationOptions bo = sample_revolutions(t, tip, out);
  if (out.x_n_m.size() <= bo.window_revolutions) {
    out.bifurcation_status.fail("the cut window holds " + std::to_string(out.x_n_m.size()) +
                                " revolutions: too few for the bifurcation detector (more than " +
                                std::to_string(bo.window_revolutions) + ")");
    return;
  }
  out.bifurcation = dynamics::detect_bifurcation(out.depth_n_m, out.x_n_m, bo);
  out.bifurcation_status = out.bifurcation.summary;
  if (out.bifurcation.summary.ok()) {
    const double lo = out.depth_n_m.minCoeff(), hi = out.depth_n_m.maxCoeff();
    std::vector<double> at;
    for (double d : {0.25, 0.75}) at.push_back(lo + d * (hi - lo));
    out.poincare = dynamics::poincare_maps(out.depth_n_m, out.x_n_m, at);
  }
}

// A constant-depth cut: its Poincare class at the middle of the cut window, against the noise
// floor the bifurcation detector finds over the whole window.
void run_constant_depth_orbit(const TestSpec& t, const sync::TipDeflection& tip, CutOutcome& out) {
  const dynamics::BifurcationOptions bo = sample_revolutions(t, tip, out);
  const dynamics::PoincareMapOptions po;
  if (out.x_n_m.size() <= std::max<Eigen::Index>(bo.window_revolutions, po.revolutions + 1)) {
    out.orbit_status.fail(
        "the cut window holds " + std::to_string(out.x_n_m.size()) +
        " revolutions: too few for a Poincare map and its noise floor (more "
        "than " +
        std::to_string(std::max<Eigen::Index>(bo.window_revolutions, po.revolutions + 1)) + ")");
    return;
  }
  const dynamics::BifurcationResult b = dynamics::detect_bifurcation(out.depth_n_m, out.x_n_m, bo);
  if (!b.summary.ok()) {
    out.orbit_status.fail("no noise floor: " + b.summary.message);
    return;
  }
  out.orbit_noise_floor_m = b.noise_floor_m;
  const dynamics::PoincareMap map =
      dynamics::poincare_map_at_revolution(out.depth_n_m, out.x_n_m, out.x_n_m.size() / 2, po);
  out.orbit = dynamics::classify_orbit(map, b.noise_floor_m);
  out.poincare = {map};
  out.orbit_status.succeed();
}

}  // namespace

std::string window_text(double s) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", s);
  return buf;
}

std::vector<std::string> cut_window_errors(const TestSpec& t, double duration_s) {
  const CutSpec& cut = t.kind_spec<CutSpec>();
  const std::string record = "the record (0 .. " + window_text(duration_s) + " s)";
  std::vector<std::string> e;
  const auto check = [&](const char* key, const std::pair<double, double>& w) {
    const std::string at = t.yaml_label + ": key '" + std::string(key) + "' ";
    if (!std::isfinite(w.first) || !std::isfinite(w.second) || !(w.second > w.first)) {
      e.push_back(at + "must be two finite numbers [start, end] with end > start, got [" +
                  window_text(w.first) + ", " + window_text(w.second) + "]");
    } else if (w.first < 0) {
      e.push_back(at + "starts at " + window_text(w.first) + " s, before " + record);
    } else if (w.first >= duration_s) {
      e.push_back(at + "starts at " + window_text(w.first) + " s, after " + record);
    } else if (w.second > duration_s * 1.0001) {  // the last sample's period: 0.01 %
      e.push_back(at + "ends at " + window_text(w.second) + " s, after " + record);
    }
  };
  check("cut_window_s", cut.cut_window_s);
  if (cut.air_window_s) check("air_window_s", *cut.air_window_s);
  if (cut.estimation_window_s) check("estimation_window_s", *cut.estimation_window_s);
  return e;
}

CutOutcome run_cut_test(const TestSpec& t, const CutStepInputs& in, const CutStepOptions& options) {
  CutOutcome out;
  const std::string label = t.data_label();
  const SignalTable table = SignalTable::open(t.data, label);
  // Normally found before the run (CutKind::check_record); checked again here because every
  // step below indexes the record with these windows.
  const std::vector<std::string> window_errors =
      cut_window_errors(t, static_cast<double>(table.samples()) / t.sample_rate_hz);
  if (!window_errors.empty()) {
    std::string why;
    for (const auto& e : window_errors) why += (why.empty() ? "" : "; ") + e;
    out.summary.fail(why);
    return out;
  }
  const Eigen::VectorXd x = table.channel("x", t.channel("x"));  // metres at the sensor
  const Eigen::VectorXd y = table.channel("y", t.channel("y"));
  const ChannelSpec tach_cal = t.channel("tach");
  const Eigen::VectorXd tach_v = table.channel("tach", tach_cal);

  sync::TachOptions to;
  to.threshold_V = tach_cal.threshold;
  out.tach = sync::tach_angle(tach_v, t.sample_rate_hz, t.kind_spec<CutSpec>().spindle_rpm, to);
  if (!out.tach.summary.ok()) {
    out.summary.fail(label + ": tachometer: " + out.tach.summary.message);
    return out;
  }
  out.warnings.insert(out.warnings.end(), out.tach.summary.warnings.begin(),
                      out.tach.summary.warnings.end());
  std::pair<double, double> air;
  if (t.kind_spec<CutSpec>().air_window_s) {
    air = *t.kind_spec<CutSpec>().air_window_s;
  } else {
    air = {0.0, t.kind_spec<CutSpec>().cut_window_s.first};
    out.warnings.push_back("no air_window_s: the runout contour is taken before the cut window");
  }
  const sync::TipDeflection tip = sync::tip_deflection(
      x, y, out.tach, t.kind_spec<CutSpec>().sensor_to_tip, air.first, air.second);
  if (!tip.summary.ok()) {
    out.summary.fail(t.yaml_label + ": air_window_s: " + tip.summary.message);
    return out;
  }
  out.contour = tip.contour;
  out.air_revolutions = tip.contour.revolutions.count;
  out.summary.succeed();

  // Excerpt for the figure: three revolutions from the middle of the cut window.
  const double fs = t.sample_rate_hz;
  const double t_mid = 0.5 * (t.kind_spec<CutSpec>().cut_window_s.first +
                              t.kind_spec<CutSpec>().cut_window_s.second);
  const auto n_ex = static_cast<Eigen::Index>(3 * 60.0 / t.kind_spec<CutSpec>().spindle_rpm * fs);
  const Eigen::Index i0 = std::clamp<Eigen::Index>(static_cast<Eigen::Index>(t_mid * fs), 0,
                                                   std::max<Eigen::Index>(x.size() - n_ex, 0));
  const Eigen::Index len = std::min<Eigen::Index>(n_ex, x.size() - i0);
  out.excerpt_t_s = Eigen::VectorXd::LinSpaced(len, static_cast<double>(i0) / fs,
                                               static_cast<double>(i0 + len - 1) / fs);
  out.excerpt_raw_x_m = x.segment(i0, len) * t.kind_spec<CutSpec>().sensor_to_tip;
  out.excerpt_x_m = tip.x_m.segment(i0, len);

  run_offset(t, in, tip, out);
  out.ramped =
      t.kind_spec<CutSpec>().axial_depth_m.first != t.kind_spec<CutSpec>().axial_depth_m.second;
  if (out.ramped) {
    run_measured_bifurcation(t, tip, out);
  } else {
    // Optional: a window the map cannot use (a few samples, a zero noise floor) leaves the
    // state undetermined with the reason and the rest of the test runs.
    try {
      run_constant_depth_orbit(t, tip, out);
    } catch (const InputError& e) {
      out.orbit_status.fail(std::string("stable or chatter not determined: ") + e.what());
    }
  }
  if (!options.estimation_errors.empty()) {
    std::string why;
    for (const auto& e : options.estimation_errors) why += (why.empty() ? "" : "; ") + e;
    out.estimation.summary.fail(why);
  } else if (!out.offset_status.ok()) {
    out.estimation.summary.fail(
        "the identification sequence (000 sec. 5.1) starts from the offset angle found with the "
        "hammer-test and dynamometer values, which is not available: " +
        out.offset_status.message);
  } else {
    out.estimation = run_cut_estimation(
        t, in, out.tach, tip, out.offset_measured, out.offset,
        out.ramped && out.bifurcation_status.ok() ? &out.bifurcation : nullptr,
        out.ramped ? out.detector_noise_m : 0.0, options.estimation, options.jobs);
    out.warnings.insert(out.warnings.end(), out.estimation.summary.warnings.begin(),
                        out.estimation.summary.warnings.end());
  }
  return out;
}

}  // namespace chatterlab::app
