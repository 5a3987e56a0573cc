// The tip-to-sensor dynamics of one lateral axis of the spindle-integrated force sensor, from
// hammer taps on the tool tip with the calibrated sensor force as response (003 ch. 4,
// format section 6 "sifs-tap"):
//   - the FRF H1 = sum conj(F_a) F_m / sum |F_a|^2 over the hit windows (FFT of each whole
//     window, no taper, pre-impact means removed), with coherence;
//   - the modal model of 003 eq. 4-27, G(s) = sum_i alpha_i w_i^2 / (s^2 + 2 zeta_i w_i s + w_i^2)
//     (the format's alpha_i is the thesis's alpha_i^-1), fitted to H1 in the band by weighted
//     nonlinear least squares with sum alpha_i = 1 enforced (the sensor is statically
//     calibrated: G(0) = 1);
//   - its scaled modal realization (blocks A_i = [[0, w_i], [-w_i, -2 zeta_i w_i]],
//     B_i = [0, w_i]^T, C_i = [alpha_i, 0]): the companion form of 003 eqs 4-28..4-36 has
//     kappa_inf(A) near 1e22 and fails 003 eq. 4-37 (notes/003.md section 3);
//   - FRF confidence bounds (003 eqs 6-3 and 6-4, the phase sigma in radians without the
//     thesis's angle factor: Bendat & Piersol).
#pragma once

#include <Eigen/Core>
#include <complex>
#include <vector>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace sifs {

// A hit window in samples [begin, end) of the record; all windows of a test have one length.
struct TapWindow {
  Eigen::Index begin = 0;
  Eigen::Index end = 0;
};

struct TapOptions {
  double impact_fraction = 0.10;     // the impact starts where the hammer first exceeds this x peak
  double pre_impact_guard_s = 1e-3;  // the pre-impact part ends this long before it
  double min_pre_impact_s = 0.020;   // a window must start at least this long before its impact
  // `auto` windows: a hit is a hammer excursion above auto_threshold_fraction x the record's
  // largest |hammer| (baseline = median), bounces within auto_bounce_s kept with their hit;
  // each window starts auto_pretrigger_s before its impact and all have the length of the
  // shortest spacing (capped by auto_max_window_s).
  double auto_threshold_fraction = 0.2;
  double auto_bounce_s = 0.05;
  double auto_pretrigger_s = 0.030;
  double auto_max_window_s = 0.5;
};

// `hits: auto`. @throws InputError when the hammer shows no hit, naming the threshold
std::vector<TapWindow> auto_tap_windows(const Eigen::Ref<const Eigen::VectorXd>& hammer_n,
                                        double fs_hz, const TapOptions& options = {});

struct TapFrf {
  StepSummary summary;
  Eigen::VectorXd f_hz;  // bins k = 1 .. L/2, f = k fs / L (DC left out)
  Eigen::VectorXcd h1;   // sensor N per hammer N
  Eigen::VectorXd coherence;
  int hits = 0;  // n_d
  double df_hz = 0.0;
  // Per window: the impact sample (first |hammer - pre-impact mean| >= impact_fraction x peak)
  std::vector<Eigen::Index> impact;
  // R_tap: RMS (N) of the pooled pre-impact responses, each with its own mean removed.
  double r_tap_n = 0.0;
};

// @param hammer_n, response_n  the hammer force and the calibrated sensor force of the axis (N)
// @param windows               equal lengths, inside the record, each starting >= min_pre_impact_s
//                              before its impact
// @throws InputError naming the window ("hits[1]: ...") for a window that breaks a rule
TapFrf tap_frf(const Eigen::Ref<const Eigen::VectorXd>& hammer_n,
               const Eigen::Ref<const Eigen::VectorXd>& response_n, double fs_hz,
               const std::vector<TapWindow>& windows, const TapOptions& options = {});

struct SensorMode {
  double fn_hz = 0.0;
  double zeta = 0.0;
  double alpha = 0.0;  // modal gain (the format's alpha_i; sum = G(0))
};

// G(j 2 pi f) of 003 eq. 4-27.
std::complex<double> sensor_response(const std::vector<SensorMode>& modes, double f_hz);

struct SensorFitOptions {
  int modes = 3;            // k of eq. 4-27
  double band_lo_hz = 0.0;  // fit band (inclusive)
  double band_hi_hz = 0.0;
  bool coherence_weights = true;  // residual i weighted by sqrt(coherence_i)
  bool unit_static_gain = true;   // sum alpha = 1 (alpha_k = 1 - sum of the others)
  double max_zeta = 0.5;
};

struct SensorModel {
  StepSummary summary;
  std::vector<SensorMode> modes;  // by fn_hz
  double static_gain = 0.0;       // sum alpha
  // 100 ||G_fit - H1|| / ||H1|| over the band (unweighted 2-norms of the complex vectors).
  double fit_nrmse_pct = 0.0;
  int iterations = 0;
};

// Start: peak picking of |H1| in the band (the `modes` highest separated peaks) with
// half-power damping and alpha from the peak height; then Ceres Levenberg-Marquardt on the
// real and imaginary parts with log-parametrised fn, zeta (stable by construction).
SensorModel fit_sensor_model(const TapFrf& frf, const SensorFitOptions& options);

// The scaled modal realization (dense matrices of size 2k, block diagonal).
struct ScaledModal {
  Eigen::MatrixXd A;     // 2k x 2k
  Eigen::VectorXd B;     // 2k
  Eigen::RowVectorXd C;  // 2k
  double cond_A = 0.0;   // 003 eq. 4-38: ||A||_inf ||A^-1||_inf
};
ScaledModal realize_scaled_modal(const std::vector<SensorMode>& modes);
// C (j w I - A)^-1 B, for the realization-equals-model test.
std::complex<double> realization_response(const ScaledModal& r, double f_hz);

// Observability judged on the discrete pair (e^{A T}, C) (notes/003.md: powers of the
// continuous A are numerically rank deficient): the reciprocal 2-norm condition number
// sigma_min / sigma_max of the observability matrix [C; C F; ...; C F^{n-1}].
double discrete_observability_rcond(const Eigen::MatrixXd& A, const Eigen::RowVectorXd& C,
                                    double T_s);

// 003 eqs 6-3, 6-4 (B&P): per bin, sigma_|H| = sqrt(1 - g2) / (|g| sqrt(2 n_d)) |H|,
// sigma_phase_rad = sqrt(1 - g2) / (|g| sqrt(2 n_d)); g2 the coherence. With n_d = 1 the
// coherence is 1 and the bounds are zero (reported as such, not as certainty: the caller says
// so).
struct FrfConfidence {
  Eigen::VectorXd magnitude_sigma;
  Eigen::VectorXd phase_sigma_rad;
};
FrfConfidence frf_confidence(const TapFrf& frf);

}  // namespace sifs
}  // namespace chatterlab
