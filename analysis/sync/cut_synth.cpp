#include "analysis/sync/cut_synth.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"
#include "analysis/milling/simulation.h"

namespace chatterlab {
namespace sync {

double ToolContour::x_m(double theta1) const {
  double c = eccentricity_m * std::sin(theta1 + eccentricity_angle_rad);
  for (std::size_t h = 0; h < harmonic_m.size(); ++h) {
    const double kh = static_cast<double>(h + 2);
    c += harmonic_m[h] * std::cos(kh * (kPi / 2 - theta1) + harmonic_phase_rad[h]);
  }
  return c;
}

double ToolContour::y_m(double theta1) const {
  double c = eccentricity_m * std::cos(theta1 + eccentricity_angle_rad);
  for (std::size_t h = 0; h < harmonic_m.size(); ++h) {
    const double kh = static_cast<double>(h + 2);
    c += harmonic_m[h] * std::cos(kh * (-theta1) + harmonic_phase_rad[h]);
  }
  return c;
}

double tach_volts(double theta1, double offset_rad, double samples_per_rad, double width,
                  double high_V) {
  double u = std::fmod(theta1 - offset_rad, 2 * kPi);
  if (u < 0) u += 2 * kPi;
  u *= samples_per_rad;  // samples since the edge, in [0, P)
  const double period = 2 * kPi * samples_per_rad;
  if (u > period / 2) u -= period;  // just before the edge: negative
  const double rise = std::clamp(0.5 * (u + 1.0), 0.0, 1.0);
  const double fall = std::clamp(0.5 * (width - u + 1.0), 0.0, 1.0);
  return high_V * std::min(rise, fall);
}

int sampled_steps_per_tooth(int P, int teeth, int min_steps_per_tooth) {
  require_rule(P >= 1, "cut_record.samples_per_revolution", P, "must be >= 1");
  require_rule(teeth >= 1, "cut_record.cut.teeth", teeth, "must be >= 1");
  require_rule(min_steps_per_tooth >= 1, "cut_record.min_steps_per_tooth", min_steps_per_tooth,
               "must be >= 1");
  int S = P;
  while (S < min_steps_per_tooth * teeth || S % teeth != 0) S += P;
  return S / teeth;
}

CutRecord synthesize_cut_record(const CutRecordSpec& s) {
  const double per_rev = s.fs_hz * kSecondsPerMinute / s.cut.spindle_rpm;
  const auto P = static_cast<int>(std::lround(per_rev));
  require_rule(std::isfinite(per_rev) && std::abs(per_rev - P) <= 1e-9 * per_rev && P >= 16,
               "cut_record.fs_hz * 60 / spindle_rpm", per_rev,
               "must be a whole number of samples per revolution (>= 16)");
  const int S = s.cut.teeth * s.cut.steps_per_tooth;
  require_rule(S % P == 0, "cut_record.cut.steps_per_tooth", s.cut.steps_per_tooth,
               "teeth * steps_per_tooth must be a multiple of the " + std::to_string(P) +
                   " samples per revolution");
  require_rule(s.air_revolutions >= 0, "cut_record.air_revolutions", s.air_revolutions,
               "must be >= 0");
  require_rule(s.tail_revolutions >= 0, "cut_record.tail_revolutions", s.tail_revolutions,
               "must be >= 0");
  require_rule(s.noise_tip_m >= 0, "cut_record.noise_tip_m", s.noise_tip_m, "must be >= 0");
  require_rule(s.sensor_to_tip > 0, "cut_record.sensor_to_tip", s.sensor_to_tip, "must be > 0");
  require_rule(s.tach_width_revolutions > 0 && s.tach_width_revolutions < 1,
               "cut_record.tach_width_revolutions", s.tach_width_revolutions, "must be in (0, 1)");
  require_rule(s.contour.harmonic_phase_rad.empty() ||
                   s.contour.harmonic_phase_rad.size() == s.contour.harmonic_m.size(),
               "cut_record.contour.harmonic_phase_rad size", s.contour.harmonic_phase_rad.size(),
               "must be 0 (drawn) or the number of harmonics, " +
                   std::to_string(s.contour.harmonic_m.size()));
  const int decimation = S / P;

  const milling::SimulationGrid grid = milling::simulation_grid(s.cut);
  milling::RecordingRequest rec;
  rec.trace_revolutions = grid.revolutions;
  const milling::SimulationResult sim = milling::simulate(s.cut, rec);
  CutRecord r;
  if (!sim.summary.ok()) {
    r.summary.fail("simulation failed: " + sim.summary.message);
    return r;
  }
  r.samples_per_revolution = P;
  r.cut_revolutions = grid.revolutions;
  r.depth_start_m = grid.depth_at_step(0);
  r.depth_end_m = grid.depth_at_step(grid.steps);

  std::mt19937_64 rng(s.seed);
  ToolContour contour = s.contour;
  if (contour.harmonic_phase_rad.empty()) {
    std::uniform_real_distribution<double> phase(0.0, 2 * kPi);
    for (std::size_t h = 0; h < contour.harmonic_m.size(); ++h) {
      contour.harmonic_phase_rad.push_back(phase(rng));
    }
  }
  r.harmonic_phase_rad = contour.harmonic_phase_rad;
  std::normal_distribution<double> noise(0.0, s.noise_tip_m);
  const auto draw = [&]() { return s.noise_tip_m > 0 ? noise(rng) : 0.0; };

  const Eigen::Index n_air = static_cast<Eigen::Index>(s.air_revolutions) * P;
  const Eigen::Index n_cut = static_cast<Eigen::Index>(grid.revolutions) * P;
  const Eigen::Index n = n_air + n_cut + static_cast<Eigen::Index>(s.tail_revolutions) * P;
  r.x_sensor_m.resize(n);
  r.y_sensor_m.resize(n);
  r.tach_V.resize(n);
  r.x_tip_m = Eigen::VectorXd::Zero(n);
  r.y_tip_m = Eigen::VectorXd::Zero(n);
  r.theta1_rad.resize(n);
  const double offset_rad = s.offset_angle_deg * kDegToRad;
  const double samples_per_rad = P / (2 * kPi);
  const double width = s.tach_width_revolutions * P;
  const std::size_t last_trace = sim.trace.x_m.size() - 1;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double theta1 = 2 * kPi * static_cast<double>(i % P) / P;
    r.theta1_rad[i] = 2 * kPi * static_cast<double>(i) / P;
    if (i >= n_air && i < n_air + n_cut) {
      const auto k = std::min(static_cast<std::size_t>((i - n_air) * decimation), last_trace);
      r.x_tip_m[i] = sim.trace.x_m[k];
      r.y_tip_m[i] = sim.trace.y_m[k];
    }
    r.x_sensor_m[i] = (r.x_tip_m[i] + draw()) / s.sensor_to_tip + contour.x_m(theta1);
    r.y_sensor_m[i] = (r.y_tip_m[i] + draw()) / s.sensor_to_tip + contour.y_m(theta1);
    r.tach_V[i] = tach_volts(theta1, offset_rad, samples_per_rad, width, s.tach_high_V);
  }
  const double T = kSecondsPerMinute / s.cut.spindle_rpm;
  r.air_end_s = (s.air_revolutions - 1) * T;
  r.cut_start_s = s.air_revolutions * T;
  r.cut_end_s = (s.air_revolutions + grid.revolutions) * T;
  r.summary.succeed();
  return r;
}

}  // namespace sync
}  // namespace chatterlab
