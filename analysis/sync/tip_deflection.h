// Tool-tip deflection from the capacitive sensors (000 sec. 3.1, steps 3 and 4).
//
// Input is the deflection at the sensor in metres (step 2, volts times the channel calibration,
// is the app's). Then
//   3. tip = sensor_to_tip * sensor (000 sec. 3.1: 2.78 for the dissertation's tool);
//   4. the mean non-cutting contour c(phi) -- unbalance, runout and out-of-roundness, fixed in
//      the tool and so periodic in the tach phase -- is the mean of the whole tachometer
//      revolutions inside the air window (revolution_mean.h), and it is subtracted from every
//      sample by its phase: d(i) = tip(i) - c(wrap(phi(i))), c linearly interpolated on its
//      grid.
// The contour includes its mean, the gap of the sensor to the rotation centre, so d is the
// deflection from the rotation centre ("the voltage baseline for the center of tool rotation").
//
// "Rescaled as necessary" (000 sec. 3.1): the dissertation averaged a waveform in volts and
// rescaled it to tip metres before subtracting; here the contour is averaged from the same
// tip-metre samples it is subtracted from (the conversion is linear, so that is the same
// thing), and it is stretched in time to every revolution's own length by the phase. It is
// never rescaled in amplitude: a gain fitted during the cut would absorb the tooth-pass
// response itself. docs/cut-processing.md.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "analysis/common/summary.h"
#include "analysis/sync/revolution_mean.h"
#include "analysis/sync/sync_options.h"
#include "analysis/sync/tach_angle.h"

namespace chatterlab {
namespace sync {

struct TipDeflection {
  StepSummary summary;
  Eigen::VectorXd x_m, y_m;  // tip deflection from the rotation centre, contour removed
  // The mean non-cutting contour at the tip against the tach phase (phase_rad, x_m, y_m), its
  // spread, and the air revolutions it averages (revolutions.count, N_air).
  RevolutionMean contour;
  // RMS of d over the air revolutions after the contour is removed, m: the noise level at the
  // tip, sqrt(1 - 1/N_air) times the noise standard deviation for white noise.
  double air_residual_rms_x_m = std::numeric_limits<double>::quiet_NaN();
  double air_residual_rms_y_m = std::numeric_limits<double>::quiet_NaN();
};

// Steps 3 and 4 above. Fails the summary (ok = false) if the tachometer step failed, if the
// air window holds fewer than options.min_air_revolutions whole tachometer revolutions (the
// message gives the window and the count) or if the air revolutions hold non-finite samples.
// Non-finite samples elsewhere stay non-finite in x_m, y_m.
//
// @param x_sensor_m, y_sensor_m  deflection at the sensors, m, one value per sample of the
//                                tachometer record
// @param sensor_to_tip           tip / sensor conversion factor, finite, > 0
// @param air_start_s, air_end_s  air window (test.yaml air_window_s), s from the first sample
// @throws InputError for sizes that differ from the tachometer record, a bad sensor_to_tip or
//         air window, or options that break their rules
TipDeflection tip_deflection(const Eigen::Ref<const Eigen::VectorXd>& x_sensor_m,
                             const Eigen::Ref<const Eigen::VectorXd>& y_sensor_m,
                             const TachAngle& tach, double sensor_to_tip, double air_start_s,
                             double air_end_s, const ContourOptions& options = {});

// options.phase_points, or the nominal samples per revolution 60 fs / expected_rpm rounded
// when it is 0 (at least 8).
int contour_phase_points(const TachAngle& tach, const ContourOptions& options);

}  // namespace sync
}  // namespace chatterlab
