#include "analysis/kalman/dare.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <sstream>
#include <string>

#include "analysis/common/require.h"

namespace chatterlab {
namespace kalman {

namespace {

using Eigen::MatrixXd;

std::string size_text(const Eigen::Ref<const MatrixXd>& X) {
  return std::to_string(X.rows()) + " x " + std::to_string(X.cols());
}

// Symmetric to rounding: |X - X^T| <= 1e-12 max|X| entrywise (1e-12: a matrix assembled from
// products of symmetric ones is symmetric to ~1e-15 relative).
bool symmetric(const Eigen::Ref<const MatrixXd>& X) {
  return (X - X.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * X.cwiseAbs().maxCoeff();
}

void validate(const Eigen::Ref<const MatrixXd>& A, const Eigen::Ref<const MatrixXd>& C,
              const Eigen::Ref<const MatrixXd>& Q, const Eigen::Ref<const MatrixXd>& R) {
  const Eigen::Index n = A.rows(), m = C.rows();
  const std::string sq = std::to_string(n) + " x " + std::to_string(n);
  require_rule(n >= 1 && A.cols() == n, "dare: A size", size_text(A), "must be square, N >= 1");
  require_rule(m >= 1 && C.cols() == n, "dare: C size", size_text(C),
               "must be M x " + std::to_string(n) + ", M >= 1");
  require_rule(Q.rows() == n && Q.cols() == n, "dare: Q size", size_text(Q), "must be " + sq);
  require_rule(R.rows() == m && R.cols() == m, "dare: R size", size_text(R),
               "must be " + std::to_string(m) + " x " + std::to_string(m));
  require_rule(A.allFinite(), "dare: A", "non-finite", "must be finite");
  require_rule(C.allFinite(), "dare: C", "non-finite", "must be finite");
  require_rule(Q.allFinite() && symmetric(Q), "dare: Q", "asymmetric or non-finite",
               "must be finite and symmetric");
  require_rule(R.allFinite() && symmetric(R), "dare: R", "asymmetric or non-finite",
               "must be finite and symmetric");
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eq(Q, Eigen::EigenvaluesOnly);
  const double q_scale = eq.eigenvalues().cwiseAbs().maxCoeff();
  require_rule(eq.eigenvalues().minCoeff() >= -1e-12 * q_scale, "dare: Q smallest eigenvalue",
               eq.eigenvalues().minCoeff(), "must be >= 0 (Q positive semi-definite)");
  const Eigen::SelfAdjointEigenSolver<MatrixXd> er(R, Eigen::EigenvaluesOnly);
  require_rule(er.eigenvalues().minCoeff() > 0.0, "dare: R smallest eigenvalue",
               er.eigenvalues().minCoeff(), "must be > 0 (R positive definite)");
}

}  // namespace

SteadyStateKalman steady_state_gain(const Eigen::Ref<const MatrixXd>& A,
                                    const Eigen::Ref<const MatrixXd>& C,
                                    const Eigen::Ref<const MatrixXd>& Q,
                                    const Eigen::Ref<const MatrixXd>& R,
                                    const DareOptions& options) {
  validate(A, C, Q, R);
  require_rule(options.max_iterations >= 1, "dare.max_iterations", options.max_iterations,
               "must be >= 1");
  require_rule(options.relative_tolerance > 0.0, "dare.relative_tolerance",
               options.relative_tolerance, "must be > 0");
  require_rule(options.residual_tolerance > 0.0, "dare.residual_tolerance",
               options.residual_tolerance, "must be > 0");
  const Eigen::Index n = A.rows();
  const MatrixXd I = MatrixXd::Identity(n, n);
  SteadyStateKalman out;

  // SDA on the dual (control-form) DARE.
  MatrixXd Ak = A.transpose();
  MatrixXd G = C.transpose() * R.ldlt().solve(C);
  G = 0.5 * (G + G.transpose()).eval();
  MatrixXd H = Q;
  bool converged = false;
  double change = std::numeric_limits<double>::quiet_NaN();
  for (int it = 1; it <= options.max_iterations; ++it) {
    const Eigen::PartialPivLU<MatrixXd> W(I + G * H);
    const MatrixXd WA = W.solve(Ak);
    const MatrixXd WG = W.solve(G);
    MatrixXd H_next = H + Ak.transpose() * H * WA;
    MatrixXd G_next = G + Ak * WG * Ak.transpose();
    Ak = Ak * WA;
    H_next = 0.5 * (H_next + H_next.transpose()).eval();
    G = 0.5 * (G_next + G_next.transpose()).eval();
    out.iterations = it;
    if (!H_next.allFinite() || !G.allFinite() || !Ak.allFinite()) {
      out.summary.fail("dare: the doubling iteration left the finite numbers at iteration " +
                       std::to_string(it) +
                       " ((A, C) not detectable or (A, Q^1/2) not stabilizable?)");
      return out;
    }
    change = (H_next - H).norm();
    const double size = H_next.norm();
    if (!std::isfinite(change) || !std::isfinite(size)) {  // entries beyond ~1e154 overflow |.|
      out.summary.fail("dare: the doubling iteration diverged at iteration " + std::to_string(it) +
                       " ((A, C) not detectable or (A, Q^1/2) not stabilizable?)");
      return out;
    }
    H = std::move(H_next);
    if (change <= options.relative_tolerance * size) {
      converged = true;
      break;
    }
  }
  if (!converged) {
    std::ostringstream m;
    m << "dare: no convergence in " << options.max_iterations << " doubling steps (last change "
      << change / H.norm() << " of |P|): (A, C) not detectable or (A, Q^1/2) not stabilizable?";
    out.summary.fail(m.str());
    return out;
  }

  out.P = H;
  const MatrixXd PCt = out.P * C.transpose();
  const MatrixXd S = C * PCt + R;
  const Eigen::LDLT<MatrixXd> S_ldlt(S);
  out.K = S_ldlt.solve(PCt.transpose()).transpose();
  out.L = A * out.K;
  out.P_posterior = out.P - out.K * S * out.K.transpose();
  out.P_posterior = 0.5 * (out.P_posterior + out.P_posterior.transpose()).eval();
  const MatrixXd APCt = A * PCt;
  const MatrixXd rhs = A * out.P * A.transpose() - APCt * S_ldlt.solve(APCt.transpose()) + Q;
  const double scale = out.P.norm() + Q.norm();  // 0 only when P = Q = 0
  out.residual = (out.P - rhs).norm() / (scale > 0.0 ? scale : 1.0);
  const Eigen::EigenSolver<MatrixXd> closed(A - out.L * C, false);
  out.spectral_radius = closed.eigenvalues().cwiseAbs().maxCoeff();
  std::ostringstream m;
  if (!(out.residual <= options.residual_tolerance)) {
    m << "dare: residual " << out.residual << " above dare.residual_tolerance "
      << options.residual_tolerance;
    out.summary.fail(m.str());
  } else if (!(out.spectral_radius < 1.0)) {
    m << "dare: the solution is not stabilizing (spectral radius of A - L C = "
      << out.spectral_radius
      << " >= 1): (A, Q^1/2) not stabilizable, e.g. an unstable mode without process noise";
    out.summary.fail(m.str());
  } else {
    out.summary.succeed();
  }
  return out;
}

}  // namespace kalman
}  // namespace chatterlab
