// Synthetic SIFS records (analysis/sifs/sifs_synth.h): the signals are what notes/003.md
// section 7 and format section 6 ask for, each checked against a closed form or a second method.
#include "analysis/sifs/sifs_synth.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <vector>

#include "analysis/common/constants.h"
#include "analysis/sifs/calibration.h"
#include "analysis/signal/harmonic_fit.h"

namespace chatterlab {
namespace sifs {
namespace {

// Calibrated sensor force f_m = C s from washers (format section 6, eq. 3-1 pairs).
Eigen::Matrix<double, Eigen::Dynamic, 3> calibrated(const Eigen::Matrix3d& C, const Washers& w) {
  return pair_signals(w) * C.transpose();
}

TEST(SifsSynth, WashersFromPairsFollowThePairConvention) {
  Pairs s(3, 3);
  s << 1.0, 2.0, 3.0, -0.5, 0.25, 4.0, 7.0, -3.0, -2.0;
  const Washers w = washers_from_pairs(s);
  // s_x = 0.5 (x1 - x2), s_y = -0.5 (y1 - y2), s_z = 0.5 (z1 + z2): exact up to rounding.
  EXPECT_LT((pair_signals(w) - s).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_DOUBLE_EQ(w(0, 2), 3.0 - 2.0);  // y1 = b - s_y with b = s_z
}

TEST(SifsSynth, StaticWindowsGiveSensitivityTimesLoad) {
  StaticSynthOptions o;
  o.steps = 3;
  o.unloaded_s = 2.0;
  o.hold_s = 1.5;
  o.transition_s = 0.5;
  o.load_sign = -1.0;
  o.seed = 11;
  const StaticSynth st = synthesize_static(Axis::kY, o);
  ASSERT_EQ(st.windows.size(), 7u);  // 0, 1, 2, 3, 2, 1, 0 weights
  EXPECT_DOUBLE_EQ(st.windows[3].load_n, -3 * 44.482);
  EXPECT_DOUBLE_EQ(st.windows.back().load_n, 0.0);
  // Drift of each channel within +-(0.5..1) x 5 N/min, and different per channel.
  for (int c = 0; c < 6; ++c) {
    EXPECT_GE(std::abs(st.drift_n_per_min[c]), 2.5);
    EXPECT_LE(std::abs(st.drift_n_per_min[c]), 5.0);
  }
  // Offsets and drift are known here: removed exactly, each window's mean pair signal is S f to
  // the noise of its mean (0.05 N / sqrt(1000 samples) ~ 2e-3 N; 1e-2 N is 5 sigma).
  Washers w = st.washers_n;
  for (Eigen::Index k = 0; k < w.rows(); ++k) {
    const double t_min = static_cast<double>(k) / o.fs_hz / 60.0;
    w.row(k) -= (st.offset_n + st.drift_n_per_min * t_min).transpose();
  }
  const Pairs s = pair_signals(w);
  const Eigen::Matrix3d S = o.C.inverse();
  for (const auto& win : st.windows) {
    const auto b = static_cast<Eigen::Index>(std::ceil(win.start_s * o.fs_hz));
    const auto e = static_cast<Eigen::Index>(std::floor(win.end_s * o.fs_hz));
    const Eigen::Vector3d mean = s.middleRows(b, e - b).colwise().mean().transpose();
    const Eigen::Vector3d expected = S * Eigen::Vector3d(0.0, win.load_n, 0.0);
    EXPECT_LT((mean - expected).cwiseAbs().maxCoeff(), 1e-2) << "window at " << win.start_s;
    // The windows exclude the transitions: the load is constant inside.
    EXPECT_EQ(st.load_n.segment(b, e - b).maxCoeff(), st.load_n.segment(b, e - b).minCoeff());
  }
}

TEST(SifsSynth, StaticGroupRecoversTheCalibrationMatrix) {
  // The project's static reduction (drift fitted on the unloaded windows) over three axes.
  StaticSynthOptions o;
  o.steps = 3;
  o.unloaded_s = 3.0;
  o.hold_s = 2.0;
  std::vector<StaticReduction> red;
  for (int a = 0; a < 3; ++a) {
    o.seed = 100 + static_cast<std::uint64_t>(a);
    const StaticSynth st = synthesize_static(static_cast<Axis>(a), o);
    red.push_back(reduce_static_test(st.washers_n, o.fs_hz, static_cast<Axis>(a), st.windows));
  }
  const CalibrationFit fit = fit_calibration(red);
  ASSERT_TRUE(fit.summary.ok()) << fit.summary.message;
  // Noise 0.05 N per washer over ~2000-sample windows: C to 0.5 % of its largest entry.
  EXPECT_LT((fit.C - o.C).cwiseAbs().maxCoeff(), 5e-3 * o.C.cwiseAbs().maxCoeff()) << fit.C;
}

// H = sum conj(F_a) F_m / sum |F_a|^2 over the windows, DFT of each whole window at f_hz.
std::complex<double> tap_frf_at(const TapSynth& tap, const Eigen::VectorXd& response, double fs_hz,
                                double window_s, double f_hz) {
  std::complex<double> num = 0.0, den = 0.0;
  const auto len = static_cast<Eigen::Index>(std::llround(window_s * fs_hz));
  for (double t0 : tap.window_start_s) {
    const auto b = static_cast<Eigen::Index>(std::llround(t0 * fs_hz));
    const double fa0 = tap.hammer_n.segment(b, 100).mean();
    const double fm0 = response.segment(b, 100).mean();
    std::complex<double> Fa = 0.0, Fm = 0.0;
    for (Eigen::Index k = 0; k < len; ++k) {
      const std::complex<double> e =
          std::polar(1.0, -kTwoPi * f_hz * static_cast<double>(k) / fs_hz);
      Fa += (tap.hammer_n[b + k] - fa0) * e;
      Fm += (response[b + k] - fm0) * e;
    }
    num += std::conj(Fa) * Fm;
    den += std::norm(Fa);
  }
  return num / den;
}

TEST(SifsSynth, TapResponseHasThePlantFrf) {
  TapSynthOptions o;
  o.modes = default_plant_x();
  o.hits = 3;
  o.noise_n = 0.0;
  o.hammer_noise_n = 0.0;
  o.seed = 5;
  const TapSynth tap = synthesize_tap(Axis::kX, o);
  ASSERT_EQ(tap.window_start_s.size(), 3u);
  for (std::size_t i = 0; i < tap.impact_s.size(); ++i) {
    EXPECT_NEAR(tap.impact_s[i] - tap.window_start_s[i], 0.04, 0.5 / o.fs_hz);  // 40 ms before
  }
  EXPECT_GE(tap.hammer_n.maxCoeff(), 0.95 * 100.0);
  EXPECT_LE(tap.hammer_n.maxCoeff(), 300.0);
  const Eigen::VectorXd fx = calibrated(o.C, tap.washers_n).col(0);
  // Whole transients in each window (from rest, decayed by e^-13 at its end): the DFT ratio is
  // G at any frequency, up to the fine-rate hold (~(pi f / 102400)^2 / 6) and the anti-alias
  // filter's pass-band ripple. 3e-3 of max(|G|, 1) covers both to 4 kHz.
  for (double f : {50.0, 300.0, 420.0, 570.0, 980.0, 1500.0, 2400.0, 4000.0}) {
    const std::complex<double> h = tap_frf_at(tap, fx, o.fs_hz, o.window_s, f);
    const std::complex<double> g = sensor_response(o.modes, f);
    EXPECT_LT(std::abs(h - g), 3e-3 * std::max(1.0, std::abs(g)))
        << f << " Hz: " << h << " vs " << g;
  }
  // The cross axis sees cross_fraction of it.
  const Eigen::VectorXd fy = calibrated(o.C, tap.washers_n).col(1);
  const std::complex<double> hy = tap_frf_at(tap, fy, o.fs_hz, o.window_s, 420.0);
  EXPECT_NEAR(std::abs(hy), 0.02 * std::abs(sensor_response(o.modes, 420.0)), 1e-3);
}

TEST(SifsSynth, TapNoiseHasTheTruthVariance) {
  TapSynthOptions o;
  o.modes = default_plant_y();
  o.hits = 2;
  o.seed = 9;
  const TapSynth tap = synthesize_tap(Axis::kY, o);
  EXPECT_NEAR(tap.noise_var_n2, 0.15 * 0.15, 1e-15);  // 003: R_tap = 0.15 N
  // The calibrated y force minus the noise-free response: white noise of that variance
  // (~20000 samples: the sample variance is within 3 % at 3 sigma).
  const Eigen::VectorXd fy = calibrated(o.C, tap.washers_n).col(1);
  const Eigen::VectorXd e = fy - tap.sensor_n;
  const double var = (e.array() - e.mean()).square().mean();
  EXPECT_NEAR(var / tap.noise_var_n2, 1.0, 0.03);
}

// Mean tip force of a straight end mill over a revolution: 003 eq. 2-7 with the edge terms of
// notes/003.md item 25 (phi from +y, h = fz sin phi, F_x = -F_t cos - F_r sin,
// F_y = F_t sin - F_r cos), plus the axial force F_a = Kac b h + Kae b.
Eigen::Vector3d averaged_force(const CutForceModel& m, double phi_st, double phi_ex) {
  const double N = m.teeth, a = m.depth_m, c = m.feed_per_tooth_m;
  const auto fx = [&](double p) {
    return N * a * c / (8 * kPi) *
               (m.Ktc_N_m2 * std::cos(2 * p) - m.Krc_N_m2 * (2 * p - std::sin(2 * p))) +
           N * a / (2 * kPi) * (-m.Kte_N_m * std::sin(p) + m.Kre_N_m * std::cos(p));
  };
  const auto fy = [&](double p) {
    return N * a * c / (8 * kPi) *
               (m.Ktc_N_m2 * (2 * p - std::sin(2 * p)) + m.Krc_N_m2 * std::cos(2 * p)) -
           N * a / (2 * kPi) * (m.Kte_N_m * std::cos(p) + m.Kre_N_m * std::sin(p));
  };
  const auto fz = [&](double p) {
    return N * a / (2 * kPi) * (-m.Kac_N_m2 * c * std::cos(p) + m.Kae_N_m * p);
  };
  return {fx(phi_ex) - fx(phi_st), fy(phi_ex) - fy(phi_st), fz(phi_ex) - fz(phi_st)};
}

CutSynthOptions short_cut() {
  CutSynthOptions o;
  o.plant_x = default_plant_x();
  o.plant_y = default_plant_y();
  o.duration_s = 1.2;
  o.air_s = 0.4;
  o.entry_s = 0.05;
  o.exit_s = 0.05;
  o.tail_s = 0.05;
  o.seed = 3;
  return o;
}

TEST(SifsSynth, CutMeanForceIsTheAveragedFormula) {
  for (const bool up : {true, false}) {
    CutSynthOptions o = short_cut();
    o.force.runout_m = 0.0;  // the formula has no runout
    o.force.up_milling = up;
    o.force.radial_immersion_m = 0.5 * o.force.radius_m;
    const CutSynth cut = synthesize_cut(o);
    const double fs = o.fs_hz;
    const auto b = static_cast<Eigen::Index>(std::ceil(cut.harmonic_window_s[0] * fs - 1e-6));
    const auto e = static_cast<Eigen::Index>(std::ceil(cut.harmonic_window_s[1] * fs - 1e-6));
    const Eigen::Vector3d mean = cut.tip_force_n.middleRows(b, e - b).colwise().mean().transpose();
    const double arc = std::acos(1.0 - 0.5);
    const Eigen::Vector3d want =
        up ? averaged_force(o.force, 0.0, arc) : averaged_force(o.force, kPi - arc, kPi);
    // Straight teeth: edge-force steps at entry and exit, sampled at 102.4 kHz midpoints over
    // ~100 revolutions: 0.3 % of the largest component.
    EXPECT_LT((mean - want).cwiseAbs().maxCoeff(), 3e-3 * want.cwiseAbs().maxCoeff())
        << (up ? "up" : "down") << ": " << mean.transpose() << " vs " << want.transpose();
    // No force in the air.
    EXPECT_EQ(cut.tip_force_n.topRows(static_cast<Eigen::Index>(0.39 * fs)).cwiseAbs().maxCoeff(),
              0.0);
  }
}

TEST(SifsSynth, CutWindowsAndHelixKeepTheMean) {
  // The helix spreads each tooth's force over angle; the mean over whole revolutions stays.
  CutSynthOptions o = short_cut();
  o.force.runout_m = 0.0;
  CutSynthOptions h = o;
  h.force.helix_deg = 30.0;
  const CutSynth a = synthesize_cut(o), b = synthesize_cut(h);
  const double fs = o.fs_hz;
  EXPECT_DOUBLE_EQ(a.air_window_s[0], 0.05);
  EXPECT_DOUBLE_EQ(a.air_window_s[1], 0.35);
  EXPECT_DOUBLE_EQ(a.cut_window_s[0], 0.5);
  EXPECT_DOUBLE_EQ(a.cut_window_s[1], 1.05);
  const double revs = (a.harmonic_window_s[1] - a.harmonic_window_s[0]) * o.spindle_rpm / 60;
  EXPECT_NEAR(revs, std::round(revs), 1e-9);
  EXPECT_GE(a.harmonic_window_s[0], a.cut_window_s[0]);
  EXPECT_LE(a.harmonic_window_s[1], a.cut_window_s[1]);
  const auto i0 = static_cast<Eigen::Index>(std::ceil(a.harmonic_window_s[0] * fs - 1e-6));
  const auto i1 = static_cast<Eigen::Index>(std::ceil(a.harmonic_window_s[1] * fs - 1e-6));
  const Eigen::Vector3d ma = a.tip_force_n.middleRows(i0, i1 - i0).colwise().mean();
  const Eigen::Vector3d mb = b.tip_force_n.middleRows(i0, i1 - i0).colwise().mean();
  EXPECT_LT((ma - mb).cwiseAbs().maxCoeff(), 3e-3 * ma.cwiseAbs().maxCoeff());
}

TEST(SifsSynth, UnbalanceAppearsInTheAirWindow) {
  CutSynthOptions o = short_cut();
  const CutSynth cut = synthesize_cut(o);
  const double omega = o.spindle_rpm * kRpmToRadPerS;
  ASSERT_EQ(cut.unbalance_x.size(), 2u);
  EXPECT_DOUBLE_EQ(cut.unbalance_x[0].amp_n, o.m0e_kg_m * omega * omega);  // 003 eq. 3-6
  const auto f = calibrated(o.C, cut.washers_n);
  const auto b = static_cast<Eigen::Index>(cut.air_window_s[0] * o.fs_hz);
  const auto e = static_cast<Eigen::Index>(cut.air_window_s[1] * o.fs_hz);
  for (int a = 0; a < 2; ++a) {
    const Eigen::VectorXd x = f.col(a);
    const signal::HarmonicFit fit =
        signal::fit_harmonics(x, o.fs_hz, b, e, o.spindle_rpm / 60.0, {1, 2});
    const auto& truth = a == 0 ? cut.unbalance_x : cut.unbalance_y;
    // 3840 samples of ~3.5 N noise: amplitude sigma ~0.08 N, plus the drift's leak (< 0.1 N).
    for (std::size_t i = 0; i < 2; ++i) {
      const std::complex<double> c = fit.c(static_cast<Eigen::Index>(i));
      EXPECT_NEAR(std::abs(c), truth[i].amp_n, 0.4) << "axis " << a << " h " << truth[i].h;
    }
    const double phase_deg = std::arg(fit.c(0)) * kRadToDeg;
    EXPECT_NEAR(std::remainder(phase_deg - truth[0].phase_deg, 360.0), 0.0, 3.0);
  }
  // Calibrated noise: x at noise_n, y and z by C's rows.
  EXPECT_NEAR(cut.noise_var_n2[0], 3.5 * 3.5, 1e-12);
  EXPECT_NEAR(cut.noise_var_n2[1] / cut.noise_var_n2[0],
              o.C.row(1).squaredNorm() / o.C.row(0).squaredNorm(), 1e-12);
}

TEST(SifsSynth, CutSensorAndDynamometerSeeTheTipForce) {
  CutSynthOptions o = short_cut();
  const CutSynth cut = synthesize_cut(o);
  const double fs = o.fs_hz, sf = o.spindle_rpm / 60.0;
  const auto b = static_cast<Eigen::Index>(std::ceil(cut.harmonic_window_s[0] * fs - 1e-6));
  const auto e = static_cast<Eigen::Index>(std::ceil(cut.harmonic_window_s[1] * fs - 1e-6));
  // The noise-free sensor force's harmonics are G(j h Omega) times the tip force's (steady
  // state: the entry transient has decayed); the tooth-passing harmonic h = 4 and its double.
  // The truth rows are means over one sample interval: their harmonics are the continuous
  // force's times sinc(h SF / fs) (a centred boxcar), while the sensor record is anti-aliased
  // (flat pass band).
  for (int a = 0; a < 2; ++a) {
    const Eigen::VectorXd tip = cut.tip_force_n.col(a), sen = cut.sensor_n.col(a);
    const auto ft = signal::fit_harmonics(tip, fs, b, e, sf, {4, 8});
    const auto fm = signal::fit_harmonics(sen, fs, b, e, sf, {4, 8});
    const auto& plant = a == 0 ? o.plant_x : o.plant_y;
    for (Eigen::Index i = 0; i < 2; ++i) {
      const double f = (4.0 * static_cast<double>(i + 1)) * sf, x = kPi * f / fs;
      const std::complex<double> want = sensor_response(plant, f) * ft.c(i) / (std::sin(x) / x);
      EXPECT_LT(std::abs(fm.c(i) - want), 5e-3 * std::abs(ft.c(i))) << "axis " << a;
    }
  }
  // Dynamometer: f_x = dx cos a - dy sin a, f_y = dx sin a + dy cos a (format step 6), air mean
  // removed, against the truth in the cut window (noise 0.3 N over ~7000 samples).
  const double ca = std::cos(o.dyno_angle_deg * kDegToRad),
               sa = std::sin(o.dyno_angle_deg * kDegToRad);
  const auto ab = static_cast<Eigen::Index>(cut.air_window_s[0] * fs);
  const auto ae = static_cast<Eigen::Index>(cut.air_window_s[1] * fs);
  const Eigen::Vector3d air = cut.dyno_n.middleRows(ab, ae - ab).colwise().mean();
  const Eigen::Vector3d d = cut.dyno_n.middleRows(b, e - b).colwise().mean().transpose() - air;
  const Eigen::Vector3d t = cut.tip_force_n.middleRows(b, e - b).colwise().mean();
  EXPECT_NEAR(d[0] * ca - d[1] * sa, t[0], 0.05);
  EXPECT_NEAR(d[0] * sa + d[1] * ca, t[1], 0.05);
  EXPECT_NEAR(d[2], t[2], 0.05);
}

TEST(SifsSynth, TruthOfTheDefaultPlant) {
  // notes/003.md section 7: antiresonances at ~572 Hz and ~1970 Hz (rounded there).
  const auto ar = antiresonances_hz(default_plant_x());
  ASSERT_EQ(ar.size(), 2u);
  EXPECT_NEAR(ar[0], 572.0, 2.0);
  EXPECT_NEAR(ar[1], 1970.0, 2.0);
  for (double f : ar) {  // local minima of |G|
    const double g = std::abs(sensor_response(default_plant_x(), f));
    EXPECT_LE(g, std::abs(sensor_response(default_plant_x(), f - 0.01)));
    EXPECT_LE(g, std::abs(sensor_response(default_plant_x(), f + 0.01)));
  }
  const double bw = bandwidth_before_hz(default_plant_x(), 5000.0);
  EXPECT_GE(std::abs(std::abs(sensor_response(default_plant_x(), bw)) - 1.0), 0.1);
  EXPECT_LT(std::abs(std::abs(sensor_response(default_plant_x(), bw - 1.0)) - 1.0), 0.1);
  // Without a resonance the limit is returned.
  EXPECT_DOUBLE_EQ(bandwidth_before_hz({{4000.0, 0.5, 1.0}}, 50.0), 50.0);
}

TEST(SifsSynth, SimulatedPlantReachesTheStaticGain) {
  // Step response of eq. 4-27: settles at sum alpha = G(0).
  const auto plant = default_plant_y();
  const Eigen::VectorXd u = Eigen::VectorXd::Ones(20000);
  const Eigen::VectorXd y = simulate_plant(plant, u, 51200.0);
  EXPECT_EQ(y[0], 0.0);  // from rest
  EXPECT_NEAR(y[y.size() - 1], 1.0, 1e-9);
}

TEST(SifsSynth, BadOptionsAreNamed) {
  CutSynthOptions o = short_cut();
  o.oversample = 3;
  try {
    synthesize_cut(o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "cut.oversample = 3: must be even and >= 2");
  }
  TapSynthOptions t;
  t.modes = default_plant_x();
  try {
    synthesize_tap(Axis::kZ, t);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "tap axis = z: must be x or y");
  }
}

}  // namespace
}  // namespace sifs
}  // namespace chatterlab
