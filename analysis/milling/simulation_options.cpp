#include "analysis/milling/simulation_options.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace milling {

namespace {

// Largest run accepted: 2^31 steps (a 0-6 mm incline at 800 steps per tooth is 1.24e7).
constexpr std::int64_t kMaxSteps = std::int64_t{1} << 31;

[[noreturn]] void fail_text(const std::string& field, const std::string& value,
                            const std::string& rule) {
  throw InputError("simulation." + field + " = " + value + ": " + rule);
}

[[noreturn]] void fail(const std::string& field, double value, const std::string& rule) {
  std::ostringstream v;
  v << value;
  fail_text(field, v.str(), rule);
}

void require(bool ok, const std::string& field, double value, const std::string& rule) {
  if (!ok) fail(field, value, rule);
}

void check_axis(const AxisModal& a, const std::string& name) {
  require(std::isfinite(a.m_kg) && a.m_kg > 0.0, name + ".m_kg", a.m_kg, "must be finite and > 0");
  require(std::isfinite(a.c_kg_s) && a.c_kg_s >= 0.0, name + ".c_kg_s", a.c_kg_s,
          "must be finite and >= 0");
  require(std::isfinite(a.k_N_m) && a.k_N_m > 0.0, name + ".k_N_m", a.k_N_m,
          "must be finite and > 0");
}

void check_coefficient(double v, const std::string& field, const std::string& unit_hint) {
  require(std::isfinite(v) && v >= 0.0, field, v, "must be finite and >= 0" + unit_hint);
}

int ramp_revolutions(const DepthProfile& d) {
  const double change_mm = std::abs(d.end_m - d.start_m) * 1e3;
  return static_cast<int>(std::ceil(change_mm * d.revolutions_per_mm - 1e-9));
}

}  // namespace

DepthProfile DepthProfile::ramp(double start_m, double end_m, double revolutions_per_mm) {
  DepthProfile d;
  d.kind = Kind::kRamp;
  d.start_m = start_m;
  d.end_m = end_m;
  d.revolutions_per_mm = revolutions_per_mm;
  return d;
}

DepthProfile DepthProfile::constant(double depth_m, int revolutions) {
  DepthProfile d;
  d.kind = Kind::kConstant;
  d.start_m = depth_m;
  d.end_m = depth_m;
  d.revolutions = revolutions;
  return d;
}

CuttingCoefficients cutting_coefficients(double Kt_N_m2, double Kr_N_m2, double Kte_N_m,
                                         double Kre_N_m) {
  CuttingCoefficients k;
  k.Kt_N_m2 = Kt_N_m2;
  k.Kr_N_m2 = Kr_N_m2;
  k.Kte_N_m = Kte_N_m;
  k.Kre_N_m = Kre_N_m;
  return k;
}

void validate(const SimulationOptions& o) {
  require(o.teeth >= 1 && o.teeth <= kMaxTeeth, "teeth", o.teeth,
          "must be in [1, " + std::to_string(kMaxTeeth) + "]");
  require(std::isfinite(o.radius_m) && o.radius_m > 0.0, "radius_m", o.radius_m,
          "must be finite and > 0");
  check_axis(o.modal_x, "modal_x");
  if (o.modal_y) check_axis(*o.modal_y, "modal_y");
  if (static_cast<int>(o.coefficients.size()) != o.teeth) {
    fail("coefficients.size()", static_cast<double>(o.coefficients.size()),
         "must equal teeth = " + std::to_string(o.teeth) + " (one entry per tooth)");
  }
  for (std::size_t p = 0; p < o.coefficients.size(); ++p) {
    const std::string f = "coefficients[" + std::to_string(p) + "].";
    const CuttingCoefficients& k = o.coefficients[p];
    check_coefficient(k.Kt_N_m2, f + "Kt_N_m2", "");
    check_coefficient(k.Kr_N_m2, f + "Kr_N_m2", "");
    check_coefficient(k.Kte_N_m, f + "Kte_N_m", " (0 for no edge force)");
    check_coefficient(k.Kre_N_m, f + "Kre_N_m", " (0 for no edge force)");
  }
  require(std::isfinite(o.spindle_rpm) && o.spindle_rpm > 0.0, "spindle_rpm", o.spindle_rpm,
          "must be finite and > 0");
  require(std::isfinite(o.feed_per_tooth_m) && o.feed_per_tooth_m >= 0.0, "feed_per_tooth_m",
          o.feed_per_tooth_m, "must be finite and >= 0");
  require(std::isfinite(o.radial_immersion_m) && o.radial_immersion_m > 0.0 &&
              o.radial_immersion_m <= 2.0 * o.radius_m,
          "radial_immersion_m", o.radial_immersion_m,
          "must satisfy 0 < r_i <= 2 radius_m = " + std::to_string(2.0 * o.radius_m));
  const DepthProfile& d = o.depth;
  require(std::isfinite(d.start_m) && d.start_m >= 0.0, "depth.start_m", d.start_m,
          "must be finite and >= 0");
  if (d.kind == DepthProfile::Kind::kRamp) {
    require(std::isfinite(d.end_m) && d.end_m >= 0.0, "depth.end_m", d.end_m,
            "must be finite and >= 0");
    require(d.end_m != d.start_m, "depth.end_m", d.end_m,
            "must differ from depth.start_m for a ramp (use DepthProfile::constant)");
    require(std::isfinite(d.revolutions_per_mm) && d.revolutions_per_mm > 0.0,
            "depth.revolutions_per_mm", d.revolutions_per_mm, "must be finite and > 0");
    require(ramp_revolutions(d) >= 1, "depth.revolutions_per_mm", d.revolutions_per_mm,
            "gives less than one revolution for the depth change");
  } else {
    require(d.revolutions >= 1, "depth.revolutions", d.revolutions, "must be >= 1");
  }
  require(o.steps_per_tooth >= 8, "steps_per_tooth", o.steps_per_tooth, "must be >= 8");
  const std::int64_t revs =
      d.kind == DepthProfile::Kind::kRamp ? ramp_revolutions(d) : d.revolutions;
  require(revs * o.teeth * o.steps_per_tooth <= kMaxSteps, "steps_per_tooth", o.steps_per_tooth,
          "gives more than 2^31 steps for the run (revolutions * teeth * steps_per_tooth)");
  if (o.switching == SwitchingRule::kAngleOnly && o.chip_model == ChipModel::kNumerical) {
    fail_text(
        "switching", "angle-only",
        "angle-only switching applies to the traditional chip model only (the numerical model "
        "cuts exactly when it finds a positive chip)");
  }
  const InertialOptions& in = o.inertial;
  require(std::isfinite(in.eccentricity_m) && in.eccentricity_m >= 0.0, "inertial.eccentricity_m",
          in.eccentricity_m, "must be finite and >= 0");
  require(std::isfinite(in.eccentricity_angle_rad), "inertial.eccentricity_angle_rad",
          in.eccentricity_angle_rad, "must be finite");
  if (in.enabled && o.modal_y) {
    require(o.modal_y->m_kg == o.modal_x.m_kg, "modal_y.m_kg", o.modal_y->m_kg,
            "must equal modal_x.m_kg when inertial forces are enabled (000 eq. 7.1: m = m_x = "
            "m_y)");
  }
  require(std::isfinite(o.sample_angle_rad), "sample_angle_rad", o.sample_angle_rad,
          "must be finite");
  require(o.initial_deflection_m.allFinite(), "initial_deflection_m", o.initial_deflection_m.norm(),
          "must be finite");
  const NumericalChipOptions& nm = o.numerical;
  require(std::isfinite(nm.all_history_until_revolutions) &&
              nm.all_history_until_revolutions >= 0.0 && nm.all_history_until_revolutions <= 20.0,
          "numerical.all_history_until_revolutions", nm.all_history_until_revolutions,
          "must be in [0, 20]");
  require(std::isfinite(nm.long_window_revolutions) && nm.long_window_revolutions >= 1.0 &&
              nm.long_window_revolutions <= 10.0,
          "numerical.long_window_revolutions", nm.long_window_revolutions, "must be in [1, 10]");
  require(std::isfinite(nm.long_until_revolutions) &&
              nm.long_until_revolutions >= nm.all_history_until_revolutions,
          "numerical.long_until_revolutions", nm.long_until_revolutions,
          "must be >= numerical.all_history_until_revolutions");
  require(std::isfinite(nm.short_window_margin_revolutions) &&
              nm.short_window_margin_revolutions > 0.0 &&
              1.0 / o.teeth + nm.short_window_margin_revolutions <= nm.long_window_revolutions,
          "numerical.short_window_margin_revolutions", nm.short_window_margin_revolutions,
          "must be > 0 with 1/teeth + margin <= numerical.long_window_revolutions");
  require(std::isfinite(nm.sharp_change_fraction_of_feed) && nm.sharp_change_fraction_of_feed > 0.0,
          "numerical.sharp_change_fraction_of_feed", nm.sharp_change_fraction_of_feed,
          "must be finite and > 0");
}

double SimulationGrid::depth_at_step(std::int64_t k) const {
  const double b = depth_start_m + static_cast<double>(k) * depth_per_step_m;
  return depth_per_step_m >= 0.0 ? std::min(b, depth_end_m) : std::max(b, depth_end_m);
}

SimulationGrid simulation_grid(const SimulationOptions& o) {
  validate(o);
  SimulationGrid g;
  g.teeth = o.teeth;
  g.steps_per_tooth = o.steps_per_tooth;
  g.steps_per_revolution = o.teeth * o.steps_per_tooth;
  g.time_step_s = 60.0 / (o.spindle_rpm * g.steps_per_revolution);
  g.angle_step_rad = kTwoPi / g.steps_per_revolution;
  g.depth_start_m = o.depth.start_m;
  if (o.depth.kind == DepthProfile::Kind::kRamp) {
    g.revolutions = ramp_revolutions(o.depth);
    g.depth_end_m = o.depth.end_m;
    const double per_rev_m = 1e-3 / o.depth.revolutions_per_mm;
    g.depth_per_step_m =
        (o.depth.end_m > o.depth.start_m ? per_rev_m : -per_rev_m) / g.steps_per_revolution;
  } else {
    g.revolutions = o.depth.revolutions;
    g.depth_end_m = o.depth.start_m;
    g.depth_per_step_m = 0.0;
  }
  g.steps = static_cast<std::int64_t>(g.revolutions) * g.steps_per_revolution;
  return g;
}

int revolution_at_depth(const SimulationOptions& o, double depth_m) {
  const SimulationGrid g = simulation_grid(o);
  if (g.depth_per_step_m == 0.0) return g.revolutions - 1;
  const double per_rev = g.depth_per_step_m * g.steps_per_revolution;
  const double j = std::floor((depth_m - g.depth_start_m) / per_rev);
  return static_cast<int>(std::clamp(j, 0.0, static_cast<double>(g.revolutions - 1)));
}

}  // namespace milling
}  // namespace chatterlab
