// Steady-state Kalman filter of a linear model (kalman_filter.h): the stabilizing solution P of
// the filter's discrete algebraic Riccati equation (DARE; 001 eq. 4.10 with its P_s typo read as
// P, notes/001.md)
//
//   P = A P A^T - A P C^T (C P C^T + R)^-1 C P A^T + Q          (P: the prior covariance P-)
//
// and the gains
//   K = P C^T (C P C^T + R)^-1     measurement-update gain, x+ = x- + K (z - C x-)
//   L = A K                        predictor gain, x-[k+1] = A x-[k] + B u[k] + L (z[k] - C x-[k])
//   P+ = P - K (C P C^T + R) K^T   posterior covariance.
//
// Method: the structure-preserving doubling algorithm (SDA; Chu, Fan, Lin, Wang, Int. J. Control
// 77, 2004; convergence: Lin, Xu, SIAM J. Matrix Anal. Appl. 28, 2006), on the filter DARE as the
// dual of the control DARE (A -> A^T, B -> C^T):
//   A_0 = A^T,  G_0 = C^T R^-1 C,  H_0 = Q
//   W_k = I + G_k H_k
//   A_k+1 = A_k W_k^-1 A_k,  G_k+1 = G_k + A_k W_k^-1 G_k A_k^T,  H_k+1 = H_k + A_k^T H_k W_k^-1
//   A_k
// H_k -> P quadratically (error ~ rho^(2^k), rho the spectral radius of the closed loop
// A - L C) when (A, C) is detectable and (A, Q^1/2) stabilizable, the usual conditions of a
// steady-state filter; no inverse of A is needed, so singular A is fine. W_k is solved by LU.
//
// The result is checked, not trusted: the DARE residual relative to |P| + |Q| and the spectral
// radius of A - L C (< 1: the solution is the stabilizing one). When the conditions fail (a
// mode with no process noise and no damping, an unobservable unstable mode) the iteration can
// converge to a non-stabilizing solution or not at all; both give a failed summary.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace kalman {

struct DareOptions {
  // Stop when |H_k+1 - H_k|_F <= relative_tolerance |H_k+1|_F (quadratic convergence: the next
  // step is then at rounding level).
  double relative_tolerance = 1e-13;
  // Iterations allowed, >= 1. 60 doublings cover rho^(2^60): any rho < 1 - 1e-16.
  int max_iterations = 60;
  // Largest accepted residual |P - (A P A^T - A P C^T S^-1 C P A^T + Q)|_F / (|P|_F + |Q|_F).
  double residual_tolerance = 1e-9;
};

struct SteadyStateKalman {
  StepSummary summary;          // not run; failed with the reason if unconverged or not stabilizing
  Eigen::MatrixXd P;            // prior covariance, the DARE solution (N x N)
  Eigen::MatrixXd P_posterior;  // P+ (N x N)
  Eigen::MatrixXd K;            // measurement-update gain (N x M)
  Eigen::MatrixXd L;            // predictor gain A K (N x M)
  double residual = std::numeric_limits<double>::quiet_NaN();         // relative, see options
  double spectral_radius = std::numeric_limits<double>::quiet_NaN();  // of A - L C
  int iterations = 0;
};

// @param A state transition (N x N).
// @param C measurement matrix (M x N).
// @param Q process noise covariance (N x N), symmetric positive semi-definite.
// @param R measurement noise covariance (M x M), symmetric positive definite.
// Throws InputError for mismatched sizes, non-finite entries, asymmetric Q or R, R not positive
// definite or Q not positive semi-definite (the message names the matrix and the rule).
SteadyStateKalman steady_state_gain(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                    const Eigen::Ref<const Eigen::MatrixXd>& C,
                                    const Eigen::Ref<const Eigen::MatrixXd>& Q,
                                    const Eigen::Ref<const Eigen::MatrixXd>& R,
                                    const DareOptions& options = {});

}  // namespace kalman
}  // namespace chatterlab
