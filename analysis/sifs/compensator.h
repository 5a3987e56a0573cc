// The expanded-disturbance Kalman filter that compensates the spindle-integrated force sensor's
// dynamics (003 sec. 4.5 and ch. 5, corrected as in notes/003.md section 4 and format section 6
// "sifs-cut" steps 3-7), its tuning sweep on tap tests (003 sec. 6.1, eq. 6-2) and its
// estimator response (the usable bandwidth).
//
// Model (003 eqs 4-43..4-51 corrected): the axis's scaled modal plant (sensor_model.h) driven
// by f_a = f_c + x_1f, with f_c a random walk and (x_1f, x_2f) an undamped resonator at the
// tooth-passing frequency omega_t = 2 pi TPF (rad/s):
//
//   d/dt [x_n; f_c; x_1f; x_2f] = [[A_n, B_n, B_n, 0], [0, 0, 0, 0], [0, 0, 0, -omega_t^2],
//                                  [0, 0, 1, 0]] x_e + Gamma [w_dc; w_ac],
//   Gamma = [0 0; 1 0; 0 1; 0 0],   f_m = [C_n 0 0 0] x_e + v,   f_a_hat = C_o x_e,
//   C_o = [0_(1 x 2k) 1 1 0],
//
// 2k + 3 states, Q_c = q I_2 (N^2/s). Discretised at T = 1 / filter rate by Van Loan's method:
// F = e^{A_e T}, Q_d = int_0^T e^{A_e s} Gamma Q_c Gamma^T e^{A_e^T s} ds (from the exponential
// of [[-A_e, Gamma Q_c Gamma^T], [0, A_e^T]] T).
//
// R: the format's R is an RMS in N used where a variance belongs (003 tables 8-15 and format
// step 5): the filter takes R_filter = r as given. Scaling (q, r) by one factor scales P and
// leaves every gain unchanged (from P0 = 0 and for the DARE alike), so the estimate depends on
// q / r only.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/sifs/sensor_model.h"

namespace chatterlab {
namespace sifs {

enum class GainMode {
  // From x0 = 0, P0 = 0 (003 table 5, eqs 5-48..5-50). The gain sequence depends on q / r and
  // the model only, not on the data; once |K_k - K_k-1| <= 1e-13 |K_k| it is held (exact to
  // rounding) so a long record costs a steady-state step per sample.
  kTimeVarying,
  // K_inf from the DARE (003 eq. 5-55 corrected, analysis/kalman/dare.h) from the first sample.
  kSteadyState,
};
const char* to_string(GainMode g);  // "time-varying", "steady-state"

// The discrete augmented model of one axis at one tooth-passing frequency and filter rate.
struct CompensatorModel {
  int modes = 0;   // k
  int states = 0;  // 2k + 3
  double tpf_hz = 0.0;
  double filter_rate_hz = 0.0;
  Eigen::MatrixXd F;        // e^{A_e T}
  Eigen::MatrixXd Qd_unit;  // Van Loan Q_d for q = 1 (scales linearly with q)
  Eigen::RowVectorXd H;     // C_e
  Eigen::RowVectorXd Co;    // C_o
  double cond_F = 0.0;      // ||F||_inf ||F^-1||_inf (003 eq. 4-37 applied to F, not A_e)
  double obsv_rcond = 0.0;  // of (F, H), see discrete_observability_rcond
};

// @param modes          the fitted plant (sum alpha need not be 1)
// @param tpf_hz         > 0 and below the filter Nyquist
// @param filter_rate_hz > 0
// @throws InputError for modes with fn >= the filter Nyquist, non-positive zeta, or bad rates
CompensatorModel make_compensator(const std::vector<SensorMode>& modes, double tpf_hz,
                                  double filter_rate_hz);

// Runs the filter over z (the measured force at the filter rate) and writes f_a_hat = C_o x+ at
// each step into *estimate (resized to z.size()). Fixed-size filter steps for k <= 6 modes
// (dispatch on 2k + 3 states), dynamic above. q > 0, r > 0.
// *gain_steps (optional): the samples until the time-varying gain converged by the rule of
// kTimeVarying (the gain is then held), -1 when it had not by the end of z, 0 for the
// steady-state gain.
// @return the summary: fails when the DARE does not converge (steady-state mode)
StepSummary compensate(const CompensatorModel& m, double q, double r, GainMode gain,
                       const Eigen::Ref<const Eigen::VectorXd>& z, Eigen::VectorXd* estimate,
                       Eigen::Index* gain_steps = nullptr);

// K_inf (states x 1) of the DARE with Q = (q/r) Qd_unit, R = 1. Throws InputError for
// q_over_r <= 0; an unconverged DARE returns an empty vector.
Eigen::VectorXd steady_gain(const CompensatorModel& m, double q_over_r);

// The estimator's response to the measured force, T(e^{j w T}) =
// C_o [I - (I - K H) F e^{-j w T}]^-1 K, at f_hz (format step 7).
std::complex<double> estimator_response(const CompensatorModel& m, const Eigen::VectorXd& K,
                                        double f_hz);

// Usable bandwidth (format step 7): the lowest f > 0 on a 1 Hz grid up to the filter Nyquist
// with | |T_tot(f)| - 1 | >= 0.1, T_tot = G(j 2 pi f) (K empty: before compensation) or
// T(e^{j 2 pi f T}) G(j 2 pi f) (after); the filter Nyquist when there is none.
double usable_bandwidth_hz(const std::vector<SensorMode>& modes, const CompensatorModel& m,
                           const Eigen::VectorXd& K);

// The harmonics analysed (format steps 4 and 6): every integer h >= 1 with h sf_hz inside
// [band_lo_hz, band_hi_hz] and h sf_hz <= 0.45 filter_rate_hz.
std::vector<int> analysed_harmonics(double sf_hz, double band_lo_hz, double band_hi_hz,
                                    double filter_rate_hz);

// The tap-test tuning sweep of one axis at one spindle speed (format step 4, 003 eq. 6-2):
// for q = 2^n, n = n_first .. n_last, filter the whole tap record (response_n, at the filter
// rate) with r = r_tap; in each hit window, the single-sided amplitude spectra
// (2/N) |sum_k x_k e^{-j 2 pi f k T}| of the estimate and of the hammer (each with its
// pre-impact mean removed, the pre-impact part ending `pre_end` samples into the window) at
// f = h sf_hz for every analysed harmonic; RMSE_tap(q) = mean over the windows of the RMS of
// the differences. q_opt = the smallest q whose RMSE is within `flat_tolerance` (0.5 %) of the
// minimum.
struct TapSweepInput {
  const std::vector<SensorMode>* modes = nullptr;
  Eigen::VectorXd hammer_n;           // at the filter rate
  Eigen::VectorXd response_n;         // at the filter rate
  std::vector<TapWindow> windows;     // at the filter rate
  std::vector<Eigen::Index> pre_end;  // per window: samples from the window start to the end
                                      // of its pre-impact part
  double filter_rate_hz = 0.0;
  double r_tap_n = 0.0;
  double band_lo_hz = 0.0, band_hi_hz = 0.0;
  GainMode gain = GainMode::kTimeVarying;
};
struct SweepCurve {
  StepSummary summary;         // fails when no harmonic lies in the band
  std::vector<int> exponents;  // n
  Eigen::VectorXd rmse_n;      // per n
  int best_exponent = 0;       // n of q_opt
  double q_opt = 0.0;          // 2^best
  std::vector<int> harmonics;
};
struct SweepOptions {
  int n_first = 1;
  int n_last = 30;
  double flat_tolerance = 0.005;
};
SweepCurve tap_sweep(const TapSweepInput& in, double spindle_rpm, int teeth,
                     const SweepOptions& options = {});

// The tap-test map RMSE(speed, n) over a speed grid (003 sec. 6.1 step 2): one tap_sweep per
// speed, run in parallel over `jobs` threads.
struct TapMap {
  std::vector<double> rpm;
  std::vector<int> exponents;
  Eigen::MatrixXd rmse_n;          // rpm.size() x exponents.size()
  std::vector<int> best_exponent;  // per speed; a speed whose sweep fails (no harmonic in
                                   // the band) has a NaN row and best_exponent -1
};
TapMap tap_map(const TapSweepInput& in, const std::vector<double>& rpm, int teeth, int jobs,
               const SweepOptions& options = {});

// Harmonic analysis of a cut (format step 6): c_h of c0 + sum_h Re(c_h e^{j h Omega t}) fitted
// over [begin, end) of x at fs (signal/harmonic_fit.h), Omega = 2 pi sf_hz.
Eigen::VectorXcd cut_harmonics(const Eigen::Ref<const Eigen::VectorXd>& x, double fs_hz,
                               Eigen::Index begin, Eigen::Index end, double sf_hz,
                               const std::vector<int>& harmonics);
// Spectral RMSE (003 sec. 6.1, squared form): RMS over h of |c_h| - |c_h,ref|.
double spectral_rmse(const Eigen::VectorXcd& c, const Eigen::VectorXcd& c_ref);

// The same q sweep on a cut against its reference (003 tables 8-15: the cutting optimum), for
// validation: filter z with q = 2^n and r, fit the harmonics over [begin, end) and take the
// spectral RMSE against c_ref.
SweepCurve cut_sweep(const CompensatorModel& m, double r, GainMode gain,
                     const Eigen::Ref<const Eigen::VectorXd>& z, Eigen::Index begin,
                     Eigen::Index end, double sf_hz, const std::vector<int>& harmonics,
                     const Eigen::VectorXcd& c_ref, const SweepOptions& options = {});

}  // namespace sifs
}  // namespace chatterlab
