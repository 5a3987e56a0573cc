// The discrete spindle drive with its speed and current loops (analysis/sysid/spindle_drive.h):
// the synthetic truth of 001 sec. 3.1 (notes/001.md sec. 7.1 A).
#include "analysis/sysid/spindle_drive.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace sysid {
namespace {

using cd = std::complex<double>;

// 1 Hz grid 1 .. f_max.
Eigen::VectorXd grid_to(double f_max) {
  const auto n = static_cast<Eigen::Index>(f_max);
  return Eigen::VectorXd::LinSpaced(n, 1.0, f_max);
}

// 001 eq. 3.9 from the three sweep FRFs: G_s (G_o / G_loop) / (Kt (1 + G_o)).
Eigen::VectorXcd combined_eq_3_9(const SpindleDrive& drive, const Eigen::VectorXd& f) {
  const Eigen::VectorXcd Go = drive.open_loop_gain(f);
  const Eigen::VectorXcd Gloop = drive.velocity_plant(f);
  const Eigen::VectorXcd Gs = drive.mechanical(f);
  Eigen::VectorXcd G(f.size());
  for (Eigen::Index i = 0; i < f.size(); ++i) {
    G[i] = Gs[i] * (Go[i] / Gloop[i]) / (drive.params().kt_nm_per_a * (1.0 + Go[i]));
  }
  return G;
}

// max |a - b| / |b|.
double max_relative_error(const Eigen::VectorXcd& a, const Eigen::VectorXcd& b) {
  return ((a - b).cwiseAbs().array() / b.cwiseAbs().array()).maxCoeff();
}

// The complex amplitude of the f_hz component of y over its last `periods` whole periods
// (a single-bin DFT; the mean and the other harmonics of f_hz drop out).
cd phasor(const Eigen::VectorXd& y, double f_hz, double rate, int periods) {
  const auto n = static_cast<Eigen::Index>(std::lround(periods * rate / f_hz));
  cd acc = 0.0;
  for (Eigen::Index k = y.size() - n; k < y.size(); ++k) {
    acc += y[k] * std::polar(1.0, -kTwoPi * f_hz * static_cast<double>(k) / rate);
  }
  return 2.0 * acc / static_cast<double>(n);
}

SpindleDriveParams at_tool() {
  SpindleDriveParams p;
  p.disturbance_at_tool = true;
  return p;
}

SpindleDriveParams continuous_filter() {
  SpindleDriveParams p;
  p.current_loop = CurrentLoopForm::kContinuousFilter;
  return p;
}

TEST(SpindleDrive, DefaultsOfNotes001) {
  const SpindleDrive drive;
  const SpindleDriveParams& p = drive.params();
  EXPECT_NEAR(p.kp_a_s_per_rad, 7.853981634, 1e-8);
  EXPECT_NEAR(p.ti_s, 6.366197724e-3, 1e-12);
  EXPECT_EQ(drive.delay_samples(), 1);
  // sqrt(k (J1 + J2) / (J1 J2)) / (2 pi) and sqrt(k / J2) / (2 pi).
  EXPECT_NEAR(drive.torsional_frequency_hz(), 889.7, 0.05);
  EXPECT_NEAR(drive.antiresonance_frequency_hz(), 795.8, 0.05);
  EXPECT_EQ(drive.closed_loop().A.rows(), 6);
  EXPECT_EQ(drive.closed_loop().B.cols(), 2);
  EXPECT_EQ(drive.closed_loop().C.rows(), 3);
}

TEST(SpindleDrive, InvalidParamsNameTheirField) {
  const auto message = [](const SpindleDriveParams& p) -> std::string {
    try {
      SpindleDrive drive(p);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  SpindleDriveParams p;
  p.j1_kg_m2 = 0.0;
  EXPECT_NE(message(p).find("j1_kg_m2"), std::string::npos);
  p = {};
  p.j2_kg_m2 = -1.0;
  EXPECT_NE(message(p).find("j2_kg_m2"), std::string::npos);
  p = {};
  p.k_nm_per_rad = std::nan("");
  EXPECT_NE(message(p).find("k_nm_per_rad"), std::string::npos);
  p = {};
  p.c_nm_s_per_rad = -0.1;
  EXPECT_NE(message(p).find("c_nm_s_per_rad"), std::string::npos);
  p = {};
  p.b_nm_s_per_rad = -0.1;
  EXPECT_NE(message(p).find("b_nm_s_per_rad"), std::string::npos);
  p = {};
  p.kt_nm_per_a = 0.0;
  EXPECT_NE(message(p).find("kt_nm_per_a"), std::string::npos);
  p = {};
  p.current_bandwidth_rad_s = 0.0;
  EXPECT_NE(message(p).find("current_bandwidth_rad_s"), std::string::npos);
  p = {};
  p.kp_a_s_per_rad = 0.0;
  EXPECT_NE(message(p).find("kp_a_s_per_rad"), std::string::npos);
  p = {};
  p.ti_s = 0.0;
  EXPECT_NE(message(p).find("ti_s"), std::string::npos);
  p = {};
  p.sample_rate_hz = 0.0;
  EXPECT_NE(message(p).find("sample_rate_hz"), std::string::npos);
  p = {};
  p.current_delay_s = 150e-6;  // 1.5 samples
  EXPECT_NE(message(p).find("current_delay_s"), std::string::npos);
  p = {};
  p.current_delay_s = -100e-6;
  EXPECT_NE(message(p).find("current_delay_s"), std::string::npos);
  p = {};
  p.kp_a_s_per_rad *= 40.0;  // far beyond the gain margin
  EXPECT_NE(message(p).find("spectral radius"), std::string::npos);
  p = {};
  p.current_delay_s = 200e-6 + 5e-10;  // within 1e-9 s of 2 samples
  EXPECT_EQ(message(p), "");
  EXPECT_EQ(SpindleDrive(p).delay_samples(), 2);
  p.current_delay_s = 0.0;
  EXPECT_EQ(SpindleDrive(p).delay_samples(), 0);
}

TEST(SpindleDrive, ClosedLoopPolesInsideTheUnitCircle) {
  for (const SpindleDriveParams& p : {SpindleDriveParams{}, at_tool(), continuous_filter()}) {
    const SpindleDrive drive(p);
    const Eigen::VectorXcd z = drive.closed_loop_poles();
    EXPECT_EQ(z.size(), drive.closed_loop().A.rows());
    EXPECT_LT(z.cwiseAbs().maxCoeff(), 1.0);
  }
}

TEST(SpindleDrive, DcGainOfTorqueToCurrentIsOneOverKt) {
  for (const SpindleDriveParams& p : {SpindleDriveParams{}, at_tool(), continuous_filter()}) {
    const SpindleDrive drive(p);
    EXPECT_NEAR(drive.dc_gain_torque_to_current(), 1.0 / p.kt_nm_per_a, 1e-9 / p.kt_nm_per_a);
    const Eigen::VectorXd f0 = Eigen::VectorXd::Zero(1);
    EXPECT_NEAR(std::abs(drive.speed_tracking(f0)[0] - 1.0), 0.0, 1e-9);
    // 1 Hz: 1.250 A per N m (notes/001.md sec. 7.1 A).
    const Eigen::VectorXd f1 = Eigen::VectorXd::Constant(1, 1.0);
    EXPECT_NEAR(std::abs(drive.torque_to_current(f1)[0]), 1.25, 2e-3);
  }
}

TEST(SpindleDrive, SweepFrfsAreTheRatiosASpeedReferenceSweepMeasures) {
  // G_o = T / (1 - T) (speed / error), G_loop = speed / I_nom, G_s = speed / I_act, with the
  // closed-loop responses to speed_ref; G_m = G_loop / G_s and G_Omega = G_o / G_loop.
  for (const SpindleDriveParams& p : {SpindleDriveParams{}, at_tool(), continuous_filter()}) {
    const SpindleDrive drive(p);
    const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(500, 1.0, 4990.0);
    const Eigen::VectorXcd Go = drive.open_loop_gain(f);
    const Eigen::VectorXcd Gloop = drive.velocity_plant(f);
    const Eigen::VectorXcd Gs = drive.mechanical(f);
    const Eigen::VectorXcd Gm = drive.current_loop(f);
    const Eigen::VectorXcd Gc = drive.speed_controller(f);
    Eigen::VectorXcd T(f.size()), loop(f.size()), s(f.size());
    for (Eigen::Index i = 0; i < f.size(); ++i) {
      const Eigen::MatrixXcd H = frequency_response(drive.closed_loop(), f[i]);
      T[i] = H(0, 0) / (1.0 - H(0, 0));
      loop[i] = H(0, 0) / H(1, 0);
      s[i] = H(0, 0) / H(2, 0);
    }
    EXPECT_LT(max_relative_error(Go, T), 1e-9);
    EXPECT_LT(max_relative_error(Gloop, loop), 1e-9);
    EXPECT_LT(max_relative_error(Gs, s), 1e-9);
    EXPECT_LT(max_relative_error(Gm, Eigen::VectorXcd(Gloop.array() / Gs.array())), 1e-12);
    EXPECT_LT(max_relative_error(Gc, Eigen::VectorXcd(Go.array() / Gloop.array())), 1e-12);
  }
}

TEST(SpindleDrive, Eq39IsExactWhenTheTorqueEntersAtTheMotor) {
  const SpindleDrive drive;
  const Eigen::VectorXd f = grid_to(5000.0);
  const Eigen::VectorXcd truth = drive.torque_to_current(f);
  EXPECT_LT(max_relative_error(combined_eq_3_9(drive, f), truth), 1e-9);
  // The same through the single-input single-output model of the truth.
  EXPECT_LT(max_relative_error(frequency_response(drive.torque_to_current_model(), f), truth),
            1e-12);
  // Other delays.
  for (double delay : {0.0, 300e-6}) {
    SpindleDriveParams p;
    p.current_delay_s = delay;
    const SpindleDrive other(p);
    EXPECT_LT(max_relative_error(combined_eq_3_9(other, f), other.torque_to_current(f)), 1e-9)
        << delay;
  }
}

TEST(SpindleDrive, Eq39FailsWhenTheTorqueEntersAtTheTool) {
  const SpindleDrive drive(at_tool());
  const Eigen::VectorXd f = grid_to(2000.0);
  const double err = max_relative_error(combined_eq_3_9(drive, f), drive.torque_to_current(f));
  EXPECT_GT(err, 0.01);
  // Below the antiresonance the shaft is stiff and the error small.
  const Eigen::VectorXd low = grid_to(100.0);
  EXPECT_LT(max_relative_error(combined_eq_3_9(drive, low), drive.torque_to_current(low)), 0.02);
}

TEST(SpindleDrive, Eq39IsApproximateWithTheContinuousCurrentFilter) {
  // The sampled I_act is not the current that acted over the sample: G_s carries the phase of
  // a skew of about 58 us (about half a sample) and eq. 3.9 is off by about 2 pi f 58 us
  // relative, 3.6 % at 100 Hz and 68 % at 2 kHz at the defaults.
  const SpindleDrive drive(continuous_filter());
  const Eigen::VectorXd f100 = Eigen::VectorXd::Constant(1, 100.0);
  const double err100 =
      max_relative_error(combined_eq_3_9(drive, f100), drive.torque_to_current(f100));
  EXPECT_NEAR(err100, 0.036, 0.003);
  const Eigen::VectorXd f = grid_to(2000.0);
  const double err = max_relative_error(combined_eq_3_9(drive, f), drive.torque_to_current(f));
  EXPECT_NEAR(err, 0.68, 0.05);
}

TEST(SpindleDrive, TorsionalModeNear890Hz) {
  // The free torsional mode sqrt(k (J1 + J2) / (J1 J2)) / (2 pi) = 889.7 Hz has damping ratio
  // c (J1 + J2) / (J1 J2) / (2 w_n) = 0.112. The loop gain is small there (|G_o| ~ 0.15), so
  // the closed loop keeps it: a pole pair within 2 % of 889.7 Hz (903.7 Hz, zeta 0.108). On
  // |G_dtau| it shows as an antiresonance dip (near the motor-side antiresonance
  // sqrt(k / J2) / (2 pi) = 795.8 Hz, pulled lower by the 1/f roll-off: 769 Hz) followed by a
  // resonance peak (pulled higher by the same roll-off: 945 Hz), both interior extrema of
  // their windows, the peak more than twice the dip.
  const SpindleDrive drive;
  const std::vector<DiscreteMode> modes =
      modes_of(drive.closed_loop_poles(), drive.params().sample_rate_hz);
  const DiscreteMode* torsion = nullptr;
  for (const DiscreteMode& m : modes) {
    if (torsion == nullptr || std::abs(m.fn_hz - 889.7) < std::abs(torsion->fn_hz - 889.7)) {
      torsion = &m;
    }
  }
  ASSERT_NE(torsion, nullptr);
  EXPECT_NEAR(torsion->fn_hz, 889.7, 0.02 * 889.7);
  EXPECT_NEAR(torsion->zeta, 0.112, 0.01);
  const auto interior_extremum = [&drive](double lo, double hi, bool maximum) {
    const Eigen::VectorXd f =
        Eigen::VectorXd::LinSpaced(static_cast<Eigen::Index>(hi - lo) + 1, lo, hi);
    const Eigen::VectorXd mag = drive.torque_to_current(f).cwiseAbs();
    Eigen::Index i = 0;
    if (maximum) {
      mag.maxCoeff(&i);
    } else {
      mag.minCoeff(&i);
    }
    EXPECT_GT(i, 0) << lo;
    EXPECT_LT(i, f.size() - 1) << lo;
    return std::make_pair(f[i], mag[i]);
  };
  const auto dip = interior_extremum(600.0, 880.0, false);
  const auto peak = interior_extremum(880.0, 1200.0, true);
  std::printf("|G_dtau|: dip %.0f Hz (%.4g A/Nm), peak %.0f Hz (%.4g A/Nm)\n", dip.first,
              dip.second, peak.first, peak.second);
  EXPECT_NEAR(dip.first, 795.8, 0.05 * 795.8);
  EXPECT_NEAR(peak.first, 889.7, 0.08 * 889.7);
  EXPECT_GT(peak.second, 2.0 * dip.second);
}

TEST(SpindleDrive, SpeedLoopMargins) {
  const SpeedLoopMargins m = SpindleDrive().speed_loop_margins();
  std::printf("crossover %.2f Hz, phase margin %.2f deg, min |1 + G_o| %.4f at %.1f Hz\n",
              m.crossover_hz, m.phase_margin_deg, m.min_return_difference,
              m.min_return_difference_hz);
  EXPECT_NEAR(m.crossover_hz, 102.0, 5.0);
  EXPECT_GT(m.phase_margin_deg, 55.0);
  EXPECT_LT(m.phase_margin_deg, 75.0);
  EXPECT_GT(m.min_return_difference, 0.5);
}

TEST(SpindleDrive, ConstantReferenceGivesNoTransient) {
  const SpindleDrive drive;
  const Eigen::Index n = 2000;
  const SpindleDriveRecord r =
      drive.simulate(Eigen::VectorXd::Constant(n, 3000.0), Eigen::VectorXd::Zero(n));
  ASSERT_EQ(r.speed_rpm.size(), n);
  ASSERT_EQ(r.current_nom_a.size(), n);
  ASSERT_EQ(r.current_act_a.size(), n);
  // Friction current B w / Kt.
  const double i0 = 0.002 * 3000.0 * kRpmToRadPerS / 0.8;
  EXPECT_LT((r.speed_rpm.array() - 3000.0).abs().maxCoeff(), 1e-9);
  EXPECT_LT((r.current_nom_a.array() - i0).abs().maxCoeff(), 1e-9);
  EXPECT_LT((r.current_act_a.array() - i0).abs().maxCoeff(), 1e-9);
  const SpindleDriveRecord empty = drive.simulate(Eigen::VectorXd(), Eigen::VectorXd());
  EXPECT_EQ(empty.speed_rpm.size(), 0);
}

TEST(SpindleDrive, SimulateRejectsBadInput) {
  const SpindleDrive drive;
  EXPECT_THROW(drive.simulate(Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(4)), InputError);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(3);
  r[1] = std::nan("");
  EXPECT_THROW(drive.simulate(r, Eigen::VectorXd::Zero(3)), InputError);
}

TEST(SpindleDrive, SineReferenceMatchesTheTrackingFrf) {
  for (double delay : {100e-6, 0.0}) {
    SpindleDriveParams p;
    p.current_delay_s = delay;
    const SpindleDrive drive(p);
    const double rate = drive.params().sample_rate_hz;
    const double f0 = 50.0;
    const Eigen::Index n = 20000;  // 2 s; the last 50 periods are analysed
    Eigen::VectorXd ref(n);
    for (Eigen::Index k = 0; k < n; ++k) {
      ref[k] = 3000.0 + 10.0 * std::sin(kTwoPi * f0 * static_cast<double>(k) / rate);
    }
    const SpindleDriveRecord r = drive.simulate(ref, Eigen::VectorXd::Zero(n));
    const cd measured = phasor(r.speed_rpm, f0, rate, 50) / phasor(ref, f0, rate, 50);
    const cd truth = drive.speed_tracking(Eigen::VectorXd::Constant(1, f0))[0];
    EXPECT_LT(std::abs(measured - truth) / std::abs(truth), 1e-6) << delay;
    EXPECT_NEAR(std::abs(measured), std::abs(truth), 1e-6 * std::abs(truth));
    EXPECT_NEAR(std::arg(measured), std::arg(truth), 1e-6);
  }
}

TEST(SpindleDrive, SineTorqueMatchesTheTorqueToCurrentFrf) {
  for (const SpindleDriveParams& p : {SpindleDriveParams{}, at_tool(), continuous_filter()}) {
    const SpindleDrive drive(p);
    const double rate = p.sample_rate_hz;
    const double f0 = 800.0;
    const Eigen::Index n = 20000;
    Eigen::VectorXd tau(n);
    for (Eigen::Index k = 0; k < n; ++k) {
      tau[k] = 1.5 + std::cos(kTwoPi * f0 * static_cast<double>(k) / rate);
    }
    const SpindleDriveRecord r = drive.simulate(Eigen::VectorXd::Constant(n, 3000.0), tau);
    const cd measured = phasor(r.current_nom_a, f0, rate, 400) / phasor(tau, f0, rate, 400);
    const cd truth = drive.torque_to_current(Eigen::VectorXd::Constant(1, f0))[0];
    EXPECT_LT(std::abs(measured - truth) / std::abs(truth), 1e-6);
  }
}

TEST(SpindleDrive, TorqueStepSettlesToTauOverKt) {
  for (const SpindleDriveParams& p : {SpindleDriveParams{}, at_tool()}) {
    const SpindleDrive drive(p);
    const Eigen::Index n = 20000;
    const Eigen::Index step = 1000;
    const double tau = 2.0;
    Eigen::VectorXd torque = Eigen::VectorXd::Zero(n);
    torque.tail(n - step).setConstant(tau);
    for (double rpm : {0.0, 3000.0}) {
      const SpindleDriveRecord r = drive.simulate(Eigen::VectorXd::Constant(n, rpm), torque);
      const double i_before = r.current_nom_a[step - 1];
      EXPECT_NEAR(r.current_nom_a[n - 1] - i_before, tau / p.kt_nm_per_a, 1e-9) << rpm;
      EXPECT_NEAR(r.current_act_a[n - 1] - i_before, tau / p.kt_nm_per_a, 1e-9) << rpm;
      EXPECT_NEAR(r.speed_rpm[n - 1], rpm, 1e-9) << rpm;
      if (rpm == 0.0) {
        EXPECT_NEAR(r.current_nom_a[n - 1], tau / p.kt_nm_per_a, 1e-9);
      }
      // The loop rejects the torque: the speed dips and recovers.
      EXPECT_LT(r.speed_rpm.segment(step, 200).minCoeff(), rpm - 1.0) << rpm;
    }
  }
}

}  // namespace
}  // namespace sysid
}  // namespace chatterlab
