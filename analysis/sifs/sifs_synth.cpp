#include "analysis/sifs/sifs_synth.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <unsupported/Eigen/MatrixFunctions>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"
#include "analysis/frf/modal_response.h"
#include "analysis/milling/force_model.h"
#include "analysis/signal/resample.h"

namespace chatterlab {
namespace sifs {
namespace {

using Rows3 = Eigen::Matrix<double, Eigen::Dynamic, 3>;

Eigen::Index samples_for(double seconds, double fs_hz) {
  return static_cast<Eigen::Index>(std::llround(seconds * fs_hz));
}

// Per washer: a drift rate of +-(0.5..1) x magnitude (different per channel, 003 table 1: up to
// 5 N/min) and an offset in [-offset, offset].
void draw_drift_and_offsets(std::mt19937_64& rng, double drift_n_per_min, double offset_n,
                            Eigen::Matrix<double, 6, 1>* drift, Eigen::Matrix<double, 6, 1>* off) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int c = 0; c < 6; ++c) {
    const double sign = unit(rng) < 0.5 ? -1.0 : 1.0;
    (*drift)[c] = sign * (0.5 + 0.5 * unit(rng)) * drift_n_per_min;
    (*off)[c] = (2.0 * unit(rng) - 1.0) * offset_n;
  }
}

// washers += offset + drift t / 60 + N(0, sigma^2), t = k / fs.
void add_washer_disturbances(std::mt19937_64& rng, const Eigen::Matrix<double, 6, 1>& drift_per_min,
                             const Eigen::Matrix<double, 6, 1>& offset, double sigma_n,
                             double fs_hz, Washers* w) {
  std::normal_distribution<double> normal(0.0, 1.0);
  for (Eigen::Index k = 0; k < w->rows(); ++k) {
    const double t_min = static_cast<double>(k) / fs_hz / 60.0;
    for (int c = 0; c < 6; ++c) {
      (*w)(k, c) += offset[c] + drift_per_min[c] * t_min + sigma_n * normal(rng);
    }
  }
}

// s = S f per row.
Pairs pairs_of(const Eigen::Matrix3d& C, const Rows3& f) {
  const Eigen::Matrix3d S = C.inverse();
  return f * S.transpose();
}

void check_plant(const std::vector<SensorMode>& modes, const char* what) {
  require_rule(!modes.empty(), what, "[]", "needs at least one mode");
  for (const auto& m : modes) {
    require_rule(m.fn_hz > 0.0 && std::isfinite(m.fn_hz), std::string(what) + ".fn_hz", m.fn_hz,
                 "must be > 0");
    require_rule(m.zeta > 0.0 && m.zeta < 1.0, std::string(what) + ".zeta", m.zeta,
                 "must be in (0, 1)");
  }
}

}  // namespace

Eigen::Matrix3d default_calibration_matrix() {
  Eigen::Matrix3d C;
  C << 18.9, -19.0, 2.10, 0.28, 23.3, -1.62, 1.83, -3.09, 53.9;
  return C;
}

std::vector<SensorMode> default_plant_x() {
  return {{420.0, 0.03, 0.55}, {980.0, 0.04, 0.40}, {2400.0, 0.05, 0.05}};
}

std::vector<SensorMode> default_plant_y() {
  std::vector<SensorMode> m = default_plant_x();
  for (auto& mode : m) mode.fn_hz *= 1.05;
  return m;
}

Washers washers_from_pairs(const Pairs& s) {
  Washers w(s.rows(), 6);
  // a = b = s_z: an axial load presses every washer alike; d = 0.5 s_x: the X load tilts the
  // Z pair too (cancelled by its sum).
  w.col(0) = s.col(2) + s.col(0);
  w.col(1) = s.col(2) - s.col(0);
  w.col(2) = s.col(2) - s.col(1);
  w.col(3) = s.col(2) + s.col(1);
  w.col(4) = s.col(2) + 0.5 * s.col(0);
  w.col(5) = s.col(2) - 0.5 * s.col(0);
  return w;
}

double washer_noise_for(const Eigen::Matrix3d& C, Axis axis, double calibrated_rms_n) {
  const double row = C.row(static_cast<int>(axis)).norm();
  return calibrated_rms_n * std::sqrt(2.0) / row;
}

Eigen::Vector3d calibrated_noise_var(const Eigen::Matrix3d& C, double washer_sigma_n) {
  return 0.5 * washer_sigma_n * washer_sigma_n * C.rowwise().squaredNorm();
}

Eigen::VectorXd simulate_plant(const std::vector<SensorMode>& modes,
                               const Eigen::Ref<const Eigen::VectorXd>& u_held, double fine_hz) {
  check_plant(modes, "plant");
  require_rule(fine_hz > 0.0, "fine_hz", fine_hz, "must be > 0");
  const double T = 1.0 / fine_hz;
  Eigen::VectorXd y = Eigen::VectorXd::Zero(u_held.size());
  for (const auto& m : modes) {
    // Scaled modal block (sensor_model.h): A = [[0, w], [-w, -2 zeta w]], B = [0, w]^T,
    // C = [alpha, 0]; e^{[[A, B], [0, 0]] T} = [[Phi, Gamma], [0, 1]] for a held input.
    const double w = kTwoPi * m.fn_hz;
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    M(0, 1) = w;
    M(1, 0) = -w;
    M(1, 1) = -2.0 * m.zeta * w;
    M(1, 2) = w;
    const Eigen::Matrix3d E = (M * T).exp();
    const Eigen::Matrix2d Phi = E.topLeftCorner<2, 2>();
    const Eigen::Vector2d Gamma = E.topRightCorner<2, 1>();
    Eigen::Vector2d x = Eigen::Vector2d::Zero();
    for (Eigen::Index i = 0; i < u_held.size(); ++i) {
      y[i] += m.alpha * x[0];
      x = Phi * x + Gamma * u_held[i];
    }
  }
  return y;
}

// ---- static --------------------------------------------------------------------------------

StaticSynth synthesize_static(Axis axis, const StaticSynthOptions& o) {
  require_rule(o.fs_hz > 0.0, "static.fs_hz", o.fs_hz, "must be > 0");
  require_rule(o.steps >= 1, "static.steps", o.steps, "must be >= 1");
  require_rule(o.hold_s > 2.0 * o.settle_s, "static.hold_s", o.hold_s, "must exceed 2 settle_s");
  require_rule(o.unloaded_s > 2.0 * o.settle_s, "static.unloaded_s", o.unloaded_s,
               "must exceed 2 settle_s");
  require_rule(o.transition_s >= 0.0, "static.transition_s", o.transition_s, "must be >= 0");
  std::vector<int> levels;
  for (int k = 0; k <= o.steps; ++k) levels.push_back(k);
  for (int k = o.steps - 1; k >= 0; --k) levels.push_back(k);
  // Level i holds over [start_i, end_i]; ramps of transition_s between.
  std::vector<double> start, end;
  double t = 0.0;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const double hold = (i == 0 || i + 1 == levels.size()) ? o.unloaded_s : o.hold_s;
    start.push_back(t);
    end.push_back(t + hold);
    t += hold + (i + 1 < levels.size() ? o.transition_s : 0.0);
  }
  const Eigen::Index n = samples_for(t, o.fs_hz);
  StaticSynth out;
  out.load_n.resize(n);
  std::size_t level = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double tk = static_cast<double>(k) / o.fs_hz;
    while (level + 1 < levels.size() && tk >= start[level + 1]) ++level;
    double units = levels[level];
    if (tk > end[level] && level + 1 < levels.size()) {  // ramp to the next level
      const double f = (tk - end[level]) / o.transition_s;
      units += f * (levels[level + 1] - levels[level]);
    }
    out.load_n[k] = o.load_sign * o.step_n * units;
  }
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const double load = levels[i] == 0 ? 0.0 : o.load_sign * o.step_n * levels[i];  // no -0
    out.windows.push_back({start[i] + o.settle_s, end[i] - o.settle_s, load});
  }
  Rows3 f = Rows3::Zero(n, 3);
  f.col(static_cast<int>(axis)) = out.load_n;
  out.washers_n = washers_from_pairs(pairs_of(o.C, f));
  std::mt19937_64 rng(o.seed);
  draw_drift_and_offsets(rng, o.drift_n_per_min, o.offset_n, &out.drift_n_per_min, &out.offset_n);
  add_washer_disturbances(rng, out.drift_n_per_min, out.offset_n, o.noise_n, o.fs_hz,
                          &out.washers_n);
  return out;
}

// ---- tap -----------------------------------------------------------------------------------

TapSynth synthesize_tap(Axis axis, const TapSynthOptions& o) {
  require_rule(axis == Axis::kX || axis == Axis::kY, "tap axis", to_string(axis), "must be x or y");
  check_plant(o.modes, "tap.modes");
  require_rule(o.fs_hz > 0.0, "tap.fs_hz", o.fs_hz, "must be > 0");
  require_rule(o.oversample >= 1, "tap.oversample", o.oversample, "must be >= 1");
  require_rule(o.hits >= 1, "tap.hits", o.hits, "must be >= 1");
  require_rule(o.first_hit_s >= o.pretrigger_s + 0.02, "tap.first_hit_s", o.first_hit_s,
               "must be >= pretrigger_s + 20 ms");
  require_rule(o.hit_spacing_s >= o.window_s + 0.04, "tap.hit_spacing_s", o.hit_spacing_s,
               "must be >= window_s + 40 ms (windows never overlap)");
  require_rule(o.window_s > o.pretrigger_s, "tap.window_s", o.window_s, "must exceed pretrigger_s");
  require_rule(o.peak_min_n > 0.0 && o.peak_max_n >= o.peak_min_n, "tap.peak_n", o.peak_max_n,
               "needs 0 < peak_min_n <= peak_max_n");
  require_rule(o.pulse_width_s > 0.0, "tap.pulse_width_s", o.pulse_width_s, "must be > 0");

  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  TapSynth out;
  std::vector<frf::HammerPulse> pulses, held_pulses;
  const double fine_hz = o.fs_hz * o.oversample;
  for (int i = 0; i < o.hits; ++i) {
    const double t = o.first_hit_s + i * o.hit_spacing_s + (2.0 * unit(rng) - 1.0) * 0.02;
    const double peak = o.peak_min_n + (o.peak_max_n - o.peak_min_n) * unit(rng);
    const double width = o.pulse_width_s * (0.8 + 0.4 * unit(rng));
    pulses.push_back({t, peak, width});
    // The held force of fine step i is the pulse at (i + 1/2) / fine_hz.
    held_pulses.push_back({t - 0.5 / fine_hz, peak, width});
    out.impact_s.push_back(t);
    out.window_start_s.push_back(std::round((t - o.pretrigger_s) * o.fs_hz) / o.fs_hz);
  }
  const double end_s = out.window_start_s.back() + o.window_s + 0.05;
  const Eigen::Index n = static_cast<Eigen::Index>(std::ceil(end_s * o.fs_hz));
  const Eigen::Index nf = n * o.oversample;
  const Eigen::VectorXd hammer_fine = frf::half_sine_pulses(pulses, fine_hz, nf);
  const Eigen::VectorXd held = frf::half_sine_pulses(held_pulses, fine_hz, nf);
  const Eigen::VectorXd fm_fine = simulate_plant(o.modes, held, fine_hz);
  const signal::RationalResampler down(fine_hz, o.fs_hz);
  out.hammer_n = down.apply(hammer_fine);
  out.sensor_n = down.apply(fm_fine);

  Rows3 fm = Rows3::Zero(n, 3);
  const int a = static_cast<int>(axis);
  fm.col(a) = out.sensor_n;
  fm.col(1 - a) = o.cross_fraction * out.sensor_n;  // small cross-axis leakage
  out.washers_n = washers_from_pairs(pairs_of(o.C, fm));
  out.washer_sigma_n = washer_noise_for(o.C, axis, o.noise_n);
  out.noise_var_n2 = calibrated_noise_var(o.C, out.washer_sigma_n)[a];
  Eigen::Matrix<double, 6, 1> no_drift = Eigen::Matrix<double, 6, 1>::Zero(), offset;
  Eigen::Matrix<double, 6, 1> unused;
  draw_drift_and_offsets(rng, 0.0, o.offset_n, &unused, &offset);
  add_washer_disturbances(rng, no_drift, offset, out.washer_sigma_n, o.fs_hz, &out.washers_n);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (Eigen::Index k = 0; k < n; ++k) out.hammer_n[k] += o.hammer_noise_n * normal(rng);
  return out;
}

// ---- cut -----------------------------------------------------------------------------------

namespace {

// The engaged depth at t: 0 in air, linear entry and exit ramps, full in between.
double depth_at(const CutSynthOptions& o, double t) {
  const double e0 = o.air_s, e1 = o.air_s + o.entry_s;
  const double x1 = o.duration_s - o.tail_s, x0 = x1 - o.exit_s;
  double f = 0.0;
  if (t < e0 || t >= x1) {
    f = 0.0;
  } else if (t < e1) {
    f = (t - e0) / o.entry_s;
  } else if (t < x0) {
    f = 1.0;
  } else {
    f = (x1 - t) / o.exit_s;
  }
  return f * o.force.depth_m;
}

// The tip force (on the tool, machine axes) at t: 000 eqs 2.1-2.4 per tooth and axial disc with
// the edge terms of 000 eqs 3.3-3.4 (milling/force_model.h) and the axial force
// F_a = Kac b h + Kae b; chip h = fz sin(theta) + runout difference (static chip, 003 eq. 2-7's
// model).
class TipForce {
 public:
  explicit TipForce(const CutSynthOptions& o) : o_(o) {
    const CutForceModel& m = o.force;
    const double arc = std::acos(std::clamp(1.0 - m.radial_immersion_m / m.radius_m, -1.0, 1.0));
    entry_ = m.up_milling ? 0.0 : kPi - arc;
    exit_ = m.up_milling ? arc : kPi;
    slices_ = m.helix_deg > 0.0 ? m.axial_slices : 1;
    lag_per_m_ = std::tan(m.helix_deg * kDegToRad) / m.radius_m;
    k_.Kt_N_m2 = m.Ktc_N_m2;
    k_.Kr_N_m2 = m.Krc_N_m2;
    k_.Kte_N_m = m.Kte_N_m;
    k_.Kre_N_m = m.Kre_N_m;
    for (int p = 0; p < m.teeth; ++p) {
      rho_.push_back(m.runout_m * std::cos(m.runout_angle_deg * kDegToRad + p * kTwoPi / m.teeth));
    }
    omega_ = o.spindle_rpm * kRpmToRadPerS;
  }

  Eigen::Vector3d operator()(double t) const {
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    const double depth = depth_at(o_, t);
    if (depth <= 0.0) return f;
    const CutForceModel& m = o_.force;
    const double b = depth / slices_;
    const double theta1 = o_.theta1_deg * kDegToRad + omega_ * t;
    for (int j = 0; j < slices_; ++j) {
      const double lag = (j + 0.5) * b * lag_per_m_;
      for (int p = 0; p < m.teeth; ++p) {
        double theta = std::fmod(theta1 + p * kTwoPi / m.teeth - lag, kTwoPi);
        if (theta < 0.0) theta += kTwoPi;
        if (!milling::in_cut(theta, entry_, exit_)) continue;
        const double h = m.feed_per_tooth_m * std::sin(theta) + rho_[static_cast<std::size_t>(p)] -
                         rho_[static_cast<std::size_t>((p + m.teeth - 1) % m.teeth)];
        if (h <= 0.0) continue;
        const milling::ToothForce tf = milling::tooth_force(k_, h, b, true);
        f.head<2>() += milling::tooth_force_xy_N(tf, std::sin(theta), std::cos(theta));
        f[2] += m.Kac_N_m2 * b * h + m.Kae_N_m * b;
      }
    }
    return f;
  }

 private:
  const CutSynthOptions& o_;
  double entry_ = 0, exit_ = 0, lag_per_m_ = 0, omega_ = 0;
  int slices_ = 1;
  milling::CuttingCoefficients k_;
  std::vector<double> rho_;
};

}  // namespace

CutSynth synthesize_cut(const CutSynthOptions& o) {
  check_plant(o.plant_x, "cut.plant_x");
  check_plant(o.plant_y, "cut.plant_y");
  const CutForceModel& m = o.force;
  require_rule(m.teeth >= 1, "cut.teeth", m.teeth, "must be >= 1");
  require_rule(m.radius_m > 0.0, "cut.radius_m", m.radius_m, "must be > 0");
  require_rule(m.radial_immersion_m > 0.0 && m.radial_immersion_m <= 2.0 * m.radius_m,
               "cut.radial_immersion_m", m.radial_immersion_m, "must be in (0, 2 radius]");
  require_rule(m.axial_slices >= 1, "cut.axial_slices", m.axial_slices, "must be >= 1");
  require_rule(o.spindle_rpm > 0.0, "cut.spindle_rpm", o.spindle_rpm, "must be > 0");
  require_rule(o.fs_hz > 0.0, "cut.fs_hz", o.fs_hz, "must be > 0");
  require_rule(o.oversample >= 2 && o.oversample % 2 == 0, "cut.oversample", o.oversample,
               "must be even and >= 2");
  require_rule(o.entry_s > 0.0 && o.exit_s > 0.0 && o.tail_s >= 0.0, "cut.entry_s", o.entry_s,
               "entry_s and exit_s must be > 0, tail_s >= 0");
  CutSynth out;
  out.air_window_s = {0.05, o.air_s - o.margin_s};
  out.cut_window_s = {o.air_s + o.entry_s + o.margin_s,
                      o.duration_s - o.tail_s - o.exit_s - o.margin_s};
  require_rule(out.air_window_s[1] > out.air_window_s[0] + 0.05, "cut.air_s", o.air_s,
               "leaves no air window (needs > 0.1 s + margin_s)");
  const double sf_hz = o.spindle_rpm / 60.0;
  require_rule(out.cut_window_s[1] - out.cut_window_s[0] > 2.0 / sf_hz, "cut.duration_s",
               o.duration_s, "leaves fewer than two revolutions of steady engagement");
  const double t0 = std::ceil(out.cut_window_s[0] * o.fs_hz - 1e-9) / o.fs_hz;
  const double revs = std::floor((out.cut_window_s[1] - t0) * sf_hz + 1e-9);
  out.harmonic_window_s = {t0, t0 + revs / sf_hz};

  const Eigen::Index n = samples_for(o.duration_s, o.fs_hz);
  const int os = o.oversample, half = o.oversample / 2;
  const Eigen::Index nf = n * os;
  const double fine_hz = o.fs_hz * os;
  // Held force of fine step i (index i + half), at its midpoint (i + 1/2) / fine_hz,
  // i = -half .. nf + half - 1: the truth rows need half a record step on each side.
  const TipForce tip(o);
  Rows3 held(nf + os, 3);
  for (Eigen::Index i = -half; i < nf + half; ++i) {
    held.row(i + half) = tip((static_cast<double>(i) + 0.5) / fine_hz).transpose();
  }
  out.tip_force_n.resize(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    out.tip_force_n.row(k) = held.middleRows(k * os, os).colwise().mean();
  }
  // The force at the fine sample times (mean of the neighbouring midpoints) and the sensor
  // force G * f_a; z: G = 1.
  const Rows3 fa_fine = 0.5 * (held.middleRows(half - 1, nf) + held.middleRows(half, nf));
  const Eigen::VectorXd ux = held.col(0).segment(half, nf), uy = held.col(1).segment(half, nf);
  const Eigen::VectorXd fmx = simulate_plant(o.plant_x, ux, fine_hz);
  const Eigen::VectorXd fmy = simulate_plant(o.plant_y, uy, fine_hz);
  const signal::RationalResampler down(fine_hz, o.fs_hz);
  out.sensor_n.resize(n, 3);
  out.sensor_n.col(0) = down.apply(fmx);
  out.sensor_n.col(1) = down.apply(fmy);
  out.sensor_n.col(2) = down.apply(fa_fine.col(2));
  Rows3 fa(n, 3);
  for (int c = 0; c < 3; ++c) fa.col(c) = down.apply(fa_fine.col(c));

  // Unbalance (003 eq. 3-6 corrected): a forward-rotating force, y lagging x by 90 deg.
  const double omega = o.spindle_rpm * kRpmToRadPerS;
  const double a1 = o.m0e_kg_m * omega * omega;
  out.unbalance_x = {{1, a1, o.unbalance_phase_deg}};
  out.unbalance_y = {{1, a1, o.unbalance_phase_deg - 90.0}};
  if (o.h2_fraction > 0.0) {
    out.unbalance_x.push_back({2, o.h2_fraction * a1, o.h2_phase_deg});
    out.unbalance_y.push_back({2, o.h2_fraction * a1, o.h2_phase_deg - 90.0});
  }
  Rows3 fm = out.sensor_n;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / o.fs_hz;
    for (const auto& u : out.unbalance_x) {
      fm(k, 0) += u.amp_n * std::cos(u.h * omega * t + u.phase_deg * kDegToRad);
    }
    for (const auto& u : out.unbalance_y) {
      fm(k, 1) += u.amp_n * std::cos(u.h * omega * t + u.phase_deg * kDegToRad);
    }
  }
  out.washers_n = washers_from_pairs(pairs_of(o.C, fm));
  out.washer_sigma_n = washer_noise_for(o.C, Axis::kX, o.noise_n);
  out.noise_var_n2 = calibrated_noise_var(o.C, out.washer_sigma_n);
  std::mt19937_64 rng(o.seed);
  Eigen::Matrix<double, 6, 1> drift, offset;
  draw_drift_and_offsets(rng, o.drift_n_per_min, o.offset_n, &drift, &offset);
  add_washer_disturbances(rng, drift, offset, out.washer_sigma_n, o.fs_hz, &out.washers_n);

  // Dynamometer: f_x = dx cos a - dy sin a, f_y = dx sin a + dy cos a (format step 6), so
  // dx = f_x cos a + f_y sin a, dy = -f_x sin a + f_y cos a.
  const double ca = std::cos(o.dyno_angle_deg * kDegToRad);
  const double sa = std::sin(o.dyno_angle_deg * kDegToRad);
  out.dyno_n.resize(n, 3);
  out.dyno_n.col(0) = ca * fa.col(0) + sa * fa.col(1);
  out.dyno_n.col(1) = -sa * fa.col(0) + ca * fa.col(1);
  out.dyno_n.col(2) = fa.col(2);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Vector3d dyno_offset;
  for (int c = 0; c < 3; ++c) dyno_offset[c] = o.dyno_offset_n * unit(rng);
  for (Eigen::Index k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c) out.dyno_n(k, c) += dyno_offset[c] + o.dyno_noise_n * normal(rng);
  }
  return out;
}

// ---- truth ---------------------------------------------------------------------------------

std::vector<double> antiresonances_hz(const std::vector<SensorMode>& modes) {
  std::vector<double> f;
  for (const auto& m : modes) f.push_back(m.fn_hz);
  std::sort(f.begin(), f.end());
  const auto mag = [&](double x) { return std::abs(sensor_response(modes, x)); };
  std::vector<double> out;
  for (std::size_t i = 0; i + 1 < f.size(); ++i) {
    // Grid of 0.1 Hz, then golden section around the grid minimum.
    constexpr double kStep = 0.1;
    double best = f[i] + kStep, best_mag = mag(best);
    for (double x = f[i] + kStep; x < f[i + 1]; x += kStep) {
      const double v = mag(x);
      if (v < best_mag) best = x, best_mag = v;
    }
    if (best - f[i] < 2 * kStep || f[i + 1] - best < 2 * kStep) continue;  // no interior minimum
    double lo = best - kStep, hi = best + kStep;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    while (hi - lo > 1e-4) {
      const double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
      if (mag(a) < mag(b)) {
        hi = b;
      } else {
        lo = a;
      }
    }
    out.push_back(0.5 * (lo + hi));
  }
  return out;
}

double bandwidth_before_hz(const std::vector<SensorMode>& modes, double limit_hz) {
  for (double f = 1.0; f <= limit_hz; f += 1.0) {
    if (std::abs(std::abs(sensor_response(modes, f)) - 1.0) >= 0.1) return f;
  }
  return limit_hz;
}

}  // namespace sifs
}  // namespace chatterlab
