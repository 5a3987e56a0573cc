// Per-record analysis of a rotating-dynamometer slot test (000 sec. 3.2, eqs 3.1-3.2):
// whole revolutions from the zero-count pulses, channel offsets, the dynamometer angle
// theta_dyn, and the mean magnitudes of the tangential and radial forces.
//
// theta_dyn by synchronous demodulation (docs/dyno-coefficients.md). Each sample gets its
// revolution phase phi in [0, 2 pi) from the zero-count edges around it. For a trial
// switching phase psi let s_psi(phi) = +1 on [psi, psi + pi) and -1 elsewhere, and
//   D(psi) = mean over samples of s_psi(phi) [Fx; Fy].
// In a two-tooth slot the dynamometer-frame force is s_true(phi) g(phi), where g keeps one
// direction quadrant (F_t, F_r >= 0) and s_true flips at the tooth changes, so |D(psi)| is
// largest when psi is a tooth change. Unlike the "Fx and Fy cross zero" reading of 000
// sec. 3.2, this also holds with edge forces, where the force jumps sign at the change instead
// of passing through zero, and it uses every sample rather than two crossings.
// theta_dyn = psi (000 sign convention: positive when the zero-count leads the tooth change),
// defined modulo pi and reported in (-pi/2, pi/2]: the tooth change nearest the zero-count.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/cutting/dyno_options.h"

namespace chatterlab {
namespace cutting {

struct SlotRecordResult {
  StepSummary summary;
  double theta_dyn_rad = std::numeric_limits<double>::quiet_NaN();  // in (-pi/2, pi/2]
  double mean_Ft_N = std::numeric_limits<double>::quiet_NaN();      // mean |F_t| (eq 3.1), N
  double mean_Fr_N = std::numeric_limits<double>::quiet_NaN();      // mean |F_r| (eq 3.2), N
  int revolutions = 0;                                              // whole revolutions used
  double measured_rpm = std::numeric_limits<double>::quiet_NaN();   // from the edge spacing
  double offset_x_N = std::numeric_limits<double>::quiet_NaN();     // removed from Fx
  double offset_y_N = std::numeric_limits<double>::quiet_NaN();     // removed from Fy
  // |D(theta_dyn)| / mean|F| in [0, 1]: ~1 for a clean slot, ~0 for an air cut (DynoOptions).
  double switching_contrast = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> per_revolution_Ft_N;  // mean |F_t| of each whole revolution
  std::vector<double> per_revolution_Fr_N;
  double spread_Ft_N = std::numeric_limits<double>::quiet_NaN();  // sample std of the above
  double spread_Fr_N = std::numeric_limits<double>::quiet_NaN();
};

// Analyses one record. Fx_N, Fy_N: forces along the rotating dynamometer axes (N, already
// scaled by the sensitivities; offsets still in); zero_V: zero-count channel (V); all the same
// length, sampled at fs_hz. spindle_rpm: nominal speed, checked against the pulse spacing.
//
// Data problems are reported in summary (ok = false): NaN samples, no zero-count edges, fewer
// than options.min_revolutions whole revolutions, an edge interval off 60/spindle_rpm by more
// than options.rpm_tolerance. Bad arguments (lengths, fs_hz, spindle_rpm, options) throw
// InputError.
SlotRecordResult analyse_slot_record(const Eigen::Ref<const Eigen::VectorXd>& Fx_N,
                                     const Eigen::Ref<const Eigen::VectorXd>& Fy_N,
                                     const Eigen::Ref<const Eigen::VectorXd>& zero_V, double fs_hz,
                                     double spindle_rpm, const DynoOptions& options = {});

// Switching phase psi in [0, pi) maximising |D(psi)| (see above), for samples with revolution
// phases phi_rad (any real values, wrapped to [0, 2 pi)) and forces F (2 x N, offsets
// removed). Grid of coarse_step_rad, then a grid of resolution_rad over +-1 coarse step; on a
// plateau of equal maxima the centre is returned. contrast (optional) receives
// |D(psi)| / mean|F|, which is at most 1 (triangle inequality) and reaches 1 when s_psi F
// keeps one direction.
double switching_phase_rad(const std::vector<double>& phi_rad,
                           const Eigen::Ref<const Eigen::Matrix2Xd>& F, double coarse_step_rad,
                           double resolution_rad, double* contrast = nullptr);

}  // namespace cutting
}  // namespace chatterlab
