// Cutting torque from the spindle's commanded current (001 ch. 4): the drive model realized by
// ERA (era.h), augmented with a random-walk torque state, and a steady-state Kalman observer
// whose covariances come from the current's quantization (R) and from a simulated cut (Q).
//
// 001's equations, as the format fixes them (notes/001.md sec. 5 reconstructs the printed ones):
//   augmentation (4.1-4.4): x_e = [x; tau], A_e = [[A, B], [0, 1]], C_e = [C, D] (001 drops D;
//     our models have D = y_0 of ERA, so it is kept), Q_e = diag(0, .., 0, Q);
//   gain (4.10-4.11 corrected): P the a-priori solution of the filter DARE,
//     K = P C_e^T / (C_e P C_e^T + R) (001 pairs the prior P with R^-1: printed 4.11 is wrong);
//   observer (4.12 corrected): x_k = A_e x_{k-1} + K (y_k - C_e A_e x_{k-1}), torque_k = the last
//     element of x_k (4.9), with y_k, not y_{k-1}; x_0 = 0, so torque_0 = 0 and the recursion
//     starts with y_1;
//   R (4.13) = resolution^2 / 12: a variance (001's 0.0029 is its square root);
//   Q (4.14-4.19): the sample variance of T_{k+1} - T_k of the nominal cut's torque.
//
// Speed: the recursion is x_k = F x_{k-1} + K y_k with F = (I - K C_e) A_e. It runs in F's real
// block-diagonal modal form (2 x 2 rotation-scaling blocks and scalars: about 6 flops per state
// and sample instead of 2 (n+1)), with the dense form kept as the fallback when F's eigenvectors
// are ill-conditioned (docs/sysid.md).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/sysid/state_space.h"

namespace chatterlab {
namespace sysid {

// The nominal cut of the format's step 3 (kind spindle-current).
struct NominalCut {
  double spindle_rpm = 0.0;         // > 0
  int teeth = 0;                    // >= 1
  double tool_radius_m = 0.0;       // > 0
  double helix_deg = 0.0;           // [0, 60]
  double axial_depth_m = 0.0;       // > 0
  double radial_immersion_m = 0.0;  // > 0; >= 2 radius: slot
  bool up_milling = true;
  double feed_per_tooth_m = 0.0;  // > 0
  double Ktc_N_m2 = 0.0;          // >= 0
  double Kte_N_m = 0.0;           // >= 0
};

// T(t) = sum over teeth j and 100 equal axial slices (centres z) of
// R (Ktc c sin(phi) + Kte) dz where engaged, phi = 2 pi rpm t / 60 + 2 pi j / teeth
// - 2 z tan(helix) / D; engaged when phi mod 2 pi lies in [0, acos(1 - ri/R)] (up milling),
// [pi - acos(1 - ri/R), pi] (down milling) or [0, pi] (ri >= 2R). 001 eqs 4.15-4.18.
// @return T_k at t = k / rate, k = 0 .. samples - 1. @throws InputError naming a bad field.
Eigen::VectorXd nominal_cutting_torque(const NominalCut& cut, double sample_rate_hz,
                                       Eigen::Index samples);

// Q of the format's step 3: the sample variance (n - 1) of T_{k+1} - T_k over
// k = 0 .. round(20 * 60 / rpm * rate) (twenty revolutions). 001 eqs 4.14, 4.19.
double torque_increment_variance(const NominalCut& cut, double sample_rate_hz);

struct TorqueObserver {
  StepSummary summary;       // failed: torque unobservable, or the DARE failed
  DiscreteStateSpace model;  // the drive model
  Eigen::MatrixXd A_e;       // (n+1) x (n+1)
  Eigen::RowVectorXd C_e;    // n+1
  Eigen::VectorXd K;         // n+1, measurement-update gain; K(n) is the torque gain
  double Q_Nm2 = 0.0, R_A2 = 0.0;
  double dare_residual = std::numeric_limits<double>::quiet_NaN();
  double spectral_radius = std::numeric_limits<double>::quiet_NaN();  // of F
  // The modal form of F: blocks of size 1 or 2 along the diagonal of Lambda.
  bool modal = false;
  std::vector<int> block_size;
  Eigen::MatrixXd Lambda;      // (n+1) x (n+1), block diagonal
  Eigen::VectorXd b_modal;     // T^-1 K
  Eigen::RowVectorXd c_modal;  // e_last^T T
  double modal_residual = std::numeric_limits<double>::quiet_NaN();  // |T Lambda T^-1 - F| / |F|
};

// @param model the drive model (torque N*m in, current A out), stable
// @param Q_Nm2 > 0, R_A2 > 0
// Never throws for a model whose torque is unobservable: the summary says so
// (|G_model(1)| < 1e-9). @throws InputError for Q or R <= 0 or non-finite.
TorqueObserver design_torque_observer(const DiscreteStateSpace& model, double Q_Nm2, double R_A2);

// Runs the observer over y (current minus the friction current, A): torque (N*m), same length.
// Modal form when the design has it, else dense. No allocation per sample.
void run_torque_observer(const TorqueObserver& obs, const Eigen::Ref<const Eigen::VectorXd>& y,
                         Eigen::VectorXd* torque);
// The dense recursion of the format's step 4 (a reference for tests and the fallback).
void run_torque_observer_dense(const TorqueObserver& obs,
                               const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::VectorXd* torque);

// H(f) = z e_last^T (zI - F)^-1 K G_model(z), z = exp(j 2 pi f / rate): the response of the
// torque estimate to the true torque (1 at f = 0 when the design is unbiased).
Eigen::VectorXcd torque_estimate_response(const TorqueObserver& obs,
                                          const Eigen::Ref<const Eigen::VectorXd>& f_hz);

// The format's step 5: the first f of 1, 2, 3, .. Hz below rate/2 with |H(f)| < 1/sqrt(2);
// rate/2 if none.
double observer_bandwidth_hz(const TorqueObserver& obs);

}  // namespace sysid
}  // namespace chatterlab
