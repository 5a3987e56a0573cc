// The dynamometer model of one axis (004 eq. 3.1) as a continuous state-space system, and its
// zero-order-hold discretization (004 eqs 2.2-2.3).
//
//   x' = A x + B F,   y = C x          (strictly proper: D = 0, 004 E2)
//
// F is the force on the workpiece (N), y the dynamometer output (N). The realization is any
// well-conditioned one (transfer_fit.h builds a scaled modal form; the controllable canonical
// form of 004 eq. 3.4 has a 2-norm condition number of 3e23-9e23 with 004 Table 3.1).
//
// Zero-order hold at fs = 1 / dt (004 eqs 2.2-2.3 with the integral written correctly, 004 E1):
//   Ad = e^(A dt),   Bd = (integral_0^dt e^(A tau) d tau) B,
// both read from one matrix exponential of the augmented [[A, B], [0, 0]] dt (Van Loan), which
// needs no inverse of A. With the force held over [k dt, (k+1) dt):
//   x(k+1) = Ad x(k) + Bd F(k),   y(k) = C x(k).
// The force of interval k first shows in y(k+1): h(0) = 0, h(1) = C Bd (004 E12).
#pragma once

#include <Eigen/Core>
#include <complex>
#include <vector>

namespace chatterlab {
namespace forcerec {

struct ContinuousModel {
  Eigen::MatrixXd A;     // n x n
  Eigen::VectorXd B;     // n
  Eigen::RowVectorXd C;  // n

  Eigen::Index order() const { return A.rows(); }
};

struct DiscreteModel {
  Eigen::MatrixXd Ad;    // n x n
  Eigen::VectorXd Bd;    // n
  Eigen::RowVectorXd C;  // n
  double sample_rate_hz = 0.0;

  Eigen::Index order() const { return Ad.rows(); }
};

// 004 eqs 2.2-2.3 (E1). Requires a square A matching B and C, and sample_rate_hz > 0 (checked:
// std::invalid_argument naming the argument).
DiscreteModel zoh(const ContinuousModel& model, double sample_rate_hz);

// G(j 2 pi f) = C (j 2 pi f I - A)^-1 B at each frequency.
Eigen::VectorXcd frequency_response(const ContinuousModel& model,
                                    const Eigen::Ref<const Eigen::VectorXd>& f_hz);

// The sampled model's response at z = exp(j 2 pi f / fs): C (z I - Ad)^-1 Bd.
Eigen::VectorXcd frequency_response(const DiscreteModel& model,
                                    const Eigen::Ref<const Eigen::VectorXd>& f_hz);

// Markov parameters h(1..count) = C Ad^(k-1) Bd (h(0) = 0 is not stored): the response of
// y(k) to a unit force held over interval 0.
Eigen::VectorXd impulse_response(const DiscreteModel& model, Eigen::Index count);

// An orthonormal basis of the vectors orthogonal to c (n x (n-1)): the last n-1 columns of the
// Householder Q of c (the SMO's null(C), 004 eq. 2.17, and the vector fit's zeros).
Eigen::MatrixXd orthogonal_complement(const Eigen::Ref<const Eigen::VectorXd>& c);

// y(k), k = 0..N-1, from rest (x(0) = 0) for the held forces F(0..N-1).
Eigen::VectorXd simulate(const DiscreteModel& model,
                         const Eigen::Ref<const Eigen::VectorXd>& force);

}  // namespace forcerec
}  // namespace chatterlab
