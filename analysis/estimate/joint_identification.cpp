#include "analysis/estimate/joint_identification.h"

#include <ceres/ceres.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

#include "analysis/common/ceres_lm.h"
#include "analysis/common/constants.h"
#include "analysis/common/number_text.h"
#include "analysis/common/stopwatch.h"
#include "analysis/milling/simulation.h"

namespace chatterlab {
namespace estimate {

namespace {

constexpr double kZ95 = 1.959963984540054;  // two-sided 95 % normal quantile

// Periodic Catmull-Rom interpolation of values on the grid 2 pi a / S at phase t (rad): C1 and
// exact for quadratics, so the residuals are smooth in the offset.
double periodic_cubic(const Eigen::VectorXd& v, double t) {
  const Eigen::Index S = v.size();
  double u = t / kTwoPi * static_cast<double>(S);
  u -= std::floor(u / static_cast<double>(S)) * static_cast<double>(S);
  Eigen::Index i = static_cast<Eigen::Index>(std::floor(u));
  const double f = u - static_cast<double>(i);
  auto at = [&](Eigen::Index k) { return v[((k % S) + S) % S]; };
  const double p0 = at(i - 1), p1 = at(i), p2 = at(i + 1), p3 = at(i + 2);
  return p1 + 0.5 * f *
                  (p2 - p0 +
                   f * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + f * (3.0 * (p1 - p2) + p3 - p0)));
}

// Parameter layout: 0 delta (rad), 1 ln fn, 2 ln zeta, 3 .. 3+n-1 ln(Kt_p / k),
// 3+n .. 3+2n-1 ln(Kr_p / k).
struct Layout {
  int teeth = 0;
  int size() const { return 3 + 2 * teeth; }
  static constexpr int kOffset = 0, kLnFn = 1, kLnZeta = 2;
  int kt(int p) const { return 3 + p; }
  int kr(int p) const { return 3 + teeth + p; }
};

std::string parameter_name(const Layout& l, int i) {
  if (i == Layout::kOffset) return "offset";
  if (i == Layout::kLnFn) return "ln fn";
  if (i == Layout::kLnZeta) return "ln zeta";
  if (i < 3 + l.teeth) return "ln(Kt" + std::to_string(i - 2) + "/k)";
  return "ln(Kr" + std::to_string(i - 2 - l.teeth) + "/k)";
}

// m, c and the coefficients of theta with k held.
void apply(const Layout& l, const double* theta, double k, milling::SimulationOptions* o) {
  const double wn = kTwoPi * std::exp(theta[Layout::kLnFn]);
  const double zeta = std::exp(theta[Layout::kLnZeta]);
  const double m = k / (wn * wn);
  o->modal_x = {m, 2.0 * zeta * std::sqrt(k * m), k};
  o->modal_y.reset();
  for (int p = 0; p < l.teeth; ++p) {
    o->coefficients[p] =
        milling::cutting_coefficients(k * std::exp(theta[l.kt(p)]), k * std::exp(theta[l.kr(p)]));
  }
}

class RevolutionResidual {
 public:
  RevolutionResidual(const sync::RevolutionMean& measured, milling::SimulationOptions model,
                     Layout layout, double k, double settle_tolerance, int* simulations)
      : measured_(measured),
        model_(std::move(model)),
        layout_(layout),
        k_(k),
        settle_tolerance_(settle_tolerance),
        simulations_(simulations) {
    const int R = model_.depth.revolutions;
    request_.full_revolutions = {R - 2, R - 1};
  }

  bool operator()(double const* const* parameters, double* residuals) const {
    const double* theta = parameters[0];
    milling::SimulationOptions o = model_;
    apply(layout_, theta, k_, &o);
    ++*simulations_;
    milling::SimulationResult sim;
    try {
      // A trial step far out (exp overflow: m = 0, K infinite) is invalid simulator input: the
      // step is refused, as one whose cut chatters.
      sim = milling::simulate(o, request_);
    } catch (const std::exception&) {
      return false;
    }
    if (!sim.summary.ok() || sim.records.size() != 2) return false;
    const milling::RevolutionRecord& prev = sim.records[0];
    const milling::RevolutionRecord& last = sim.records[1];
    const double last_ss = last.x_m.squaredNorm() + last.y_m.squaredNorm();
    const double change_ss =
        (last.x_m - prev.x_m).squaredNorm() + (last.y_m - prev.y_m).squaredNorm();
    if (!(change_ss <= settle_tolerance_ * settle_tolerance_ * last_ss)) return false;
    const Eigen::Index N = measured_.x_m.size();
    const double delta = theta[Layout::kOffset];
    for (Eigen::Index j = 0; j < N; ++j) {
      const double t = measured_.phase_rad[j] + delta;
      residuals[j] = measured_.x_m[j] - periodic_cubic(last.x_m, t);
      residuals[N + j] = measured_.y_m[j] - periodic_cubic(last.y_m, t);
    }
    return true;
  }

 private:
  const sync::RevolutionMean& measured_;
  milling::SimulationOptions model_;
  Layout layout_;
  double k_;
  double settle_tolerance_;
  milling::RecordingRequest request_;
  int* simulations_;
};

// The delta-method interval of v with gradient grad: its variance under cov, never below its
// variance under white residuals (white).
IntervalValue interval(double value, const Eigen::VectorXd& grad, const Eigen::MatrixXd& cov,
                       const Eigen::MatrixXd& white, bool singular) {
  IntervalValue v;
  v.value = value;
  if (singular) {
    v.sd = std::numeric_limits<double>::infinity();
    v.lo = -v.sd;
    v.hi = v.sd;
    v.identifiable = false;
    return v;
  }
  v.sd = std::sqrt(std::max({0.0, grad.dot(cov * grad), grad.dot(white * grad)}));
  v.lo = value - kZ95 * v.sd;
  v.hi = value + kZ95 * v.sd;
  v.identifiable = std::isfinite(v.sd) && 2.0 * kZ95 * v.sd < std::abs(value);
  return v;
}

void check_options(const JointIdentificationOptions& o) {
  if (o.simulated_revolutions < 3) {
    throw InputError("joint identification: simulated_revolutions = " +
                     std::to_string(o.simulated_revolutions) + ": must be >= 3");
  }
  if (o.max_iterations < 1) {
    throw InputError("joint identification: max_iterations = " + std::to_string(o.max_iterations) +
                     ": must be >= 1");
  }
  if (!(o.singular_ratio > 0.0 && o.singular_ratio < 1.0)) {
    throw InputError("joint identification: singular_ratio = " +
                     significant_text(o.singular_ratio) + ": must lie in (0, 1)");
  }
  if (o.correlation_lags < 0) {
    throw InputError("joint identification: correlation_lags = " +
                     std::to_string(o.correlation_lags) + ": must be >= 0");
  }
  if (!(o.settle_tolerance > 0.0) || !std::isfinite(o.settle_tolerance)) {
    throw InputError("joint identification: settle_tolerance = " +
                     significant_text(o.settle_tolerance) + ": must be finite and > 0");
  }
}

void check_positive(const std::string& name, double v) {
  if (!(v > 0.0) || !std::isfinite(v)) {
    throw InputError("joint identification: start " + name + " = " + significant_text(v) +
                     ": must be finite and > 0");
  }
}

}  // namespace

std::vector<CuttingCoefficients> JointIdentificationResult::coefficients() const {
  std::vector<CuttingCoefficients> k(Kt_N_m2.size());
  for (std::size_t p = 0; p < k.size(); ++p) k[p] = {Kt_N_m2[p].value, Kr_N_m2[p].value};
  return k;
}

std::vector<std::string> JointIdentificationResult::not_identifiable() const {
  std::vector<std::string> names;
  auto add = [&](const std::string& n, const IntervalValue& v) {
    if (!v.identifiable) names.push_back(n);
  };
  add("offset_deg", offset_deg);
  add("m_kg", m_kg);
  add("c_kg_s", c_kg_s);
  for (std::size_t p = 0; p < Kt_N_m2.size(); ++p) {
    add("Kt" + std::to_string(p + 1) + "_N_m2", Kt_N_m2[p]);
    add("Kr" + std::to_string(p + 1) + "_N_m2", Kr_N_m2[p]);
  }
  return names;
}

JointIdentificationResult identify_joint(const sync::RevolutionMean& measured,
                                         const milling::SimulationOptions& cut_model,
                                         double depth_m, double start_offset_deg,
                                         const ModalParameters& start_modal,
                                         const std::vector<CuttingCoefficients>& start_coefficients,
                                         const JointIdentificationOptions& options) {
  check_options(options);
  const Eigen::Index N = measured.x_m.size();
  if (N < 8 || measured.y_m.size() != N || measured.phase_rad.size() != N ||
      !measured.x_m.allFinite() || !measured.y_m.allFinite()) {
    throw InputError(
        "joint identification: the measured revolution needs >= 8 finite phase "
        "points on x and y");
  }
  if (2 * N <= 3 + 2 * cut_model.teeth) {
    throw InputError("joint identification: " + std::to_string(2 * N) + " residuals for " +
                     std::to_string(3 + 2 * cut_model.teeth) +
                     " parameters: the measured revolution needs more phase points");
  }
  check_positive("depth_m", depth_m);
  check_positive("m_kg", start_modal.m_kg);
  check_positive("c_kg_s", start_modal.c_kg_s);
  check_positive("k_N_m", start_modal.k_N_m);
  if (!std::isfinite(start_offset_deg)) {
    throw InputError("joint identification: start offset_deg = " +
                     significant_text(start_offset_deg) + ": must be finite");
  }
  if (static_cast<int>(start_coefficients.size()) != cut_model.teeth) {
    throw InputError("joint identification: " + std::to_string(start_coefficients.size()) +
                     " coefficient pairs for " + std::to_string(cut_model.teeth) + " teeth");
  }
  for (std::size_t p = 0; p < start_coefficients.size(); ++p) {
    check_positive("Kt" + std::to_string(p + 1) + "_N_m2", start_coefficients[p].Kt_N_m2);
    check_positive("Kr" + std::to_string(p + 1) + "_N_m2", start_coefficients[p].Kr_N_m2);
  }

  const auto t0 = SteadyClock::now();
  JointIdentificationResult r;
  const Layout layout{cut_model.teeth};
  const int P = layout.size();
  r.parameters = P;
  r.residuals = static_cast<int>(2 * N);
  const double k = start_modal.k_N_m;
  r.k_N_m = k;

  milling::SimulationOptions model = cut_model;
  model.depth = milling::DepthProfile::constant(depth_m, options.simulated_revolutions);
  model.coefficients.assign(cut_model.teeth, CuttingCoefficients{});
  Eigen::VectorXd theta(P);
  theta[Layout::kOffset] = start_offset_deg * kDegToRad;
  theta[Layout::kLnFn] = std::log(natural_frequency_hz(start_modal));
  theta[Layout::kLnZeta] = std::log(damping_ratio(start_modal));
  for (int p = 0; p < layout.teeth; ++p) {
    theta[layout.kt(p)] = std::log(start_coefficients[p].Kt_N_m2 / k);
    theta[layout.kr(p)] = std::log(start_coefficients[p].Kr_N_m2 / k);
  }
  apply(layout, theta.data(), k, &model);
  milling::validate(model);

  auto* functor =
      new RevolutionResidual(measured, model, layout, k, options.settle_tolerance, &r.simulations);
  auto* cost = new ceres::DynamicNumericDiffCostFunction<RevolutionResidual, ceres::CENTRAL>(
      functor, ceres::TAKE_OWNERSHIP);
  cost->AddParameterBlock(P);
  cost->SetNumResiduals(r.residuals);

  // The start's residual (also: the start must simulate a steady revolution).
  Eigen::VectorXd res(r.residuals);
  {
    const double* blocks[] = {theta.data()};
    if (!cost->Evaluate(blocks, res.data(), nullptr)) {
      delete cost;
      r.summary.fail("the start's simulated revolution at " + significant_text(depth_m * 1e3) +
                     " mm is not steady or diverged (chatter at the start's values)");
      r.runtime_s = seconds_since(t0);
      return r;
    }
    r.start_rms_error_m = std::sqrt(res.squaredNorm() / static_cast<double>(res.size()));
  }

  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, theta.data());
  const ceres::Solver::Options so = dense_lm_options(options.max_iterations, 1e-10, 1e-10, 1e-14);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  r.iterations = lm_iterations(summary);
  r.termination = summary.message;
  r.converged = summary.termination_type == ceres::CONVERGENCE;

  // Residual and Jacobian at the optimum.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(r.residuals, P);
  {
    const double* blocks[] = {theta.data()};
    double* jacobians[] = {J.data()};
    if (!cost->Evaluate(blocks, res.data(), jacobians)) {
      r.summary.fail("the simulated revolution at the solver's last point is not steady");
      r.runtime_s = seconds_since(t0);
      return r;
    }
  }
  const double ss = res.squaredNorm();
  r.rms_error_m = std::sqrt(ss / static_cast<double>(res.size()));
  const double measured_rms = std::sqrt((measured.x_m.squaredNorm() + measured.y_m.squaredNorm()) /
                                        static_cast<double>(2 * N));
  r.relative_error =
      measured_rms > 0.0 ? r.rms_error_m / measured_rms : std::numeric_limits<double>::quiet_NaN();
  const int dof = r.residuals - P;
  r.residual_sd_m = dof > 0 ? std::sqrt(ss / dof) : std::numeric_limits<double>::quiet_NaN();

  // cov = A S A^T with A = V S^-1 U^T the pseudo-inverse of J over its well-conditioned
  // directions and S the residuals' long-run covariance (see the header); parameters with a large
  // share of a near-singular direction are flagged.
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Eigen::MatrixXd(J),
                                              Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  const Eigen::MatrixXd& V = svd.matrixV();
  r.condition = sv[0] > 0.0 ? sv[P - 1] / sv[0] : 0.0;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(P, r.residuals);  // pseudo-inverse of J
  std::vector<bool> singular(P, false);
  for (int i = 0; i < P; ++i) {
    if (sv[i] > options.singular_ratio * sv[0]) {
      A += (1.0 / sv[i]) * V.col(i) * svd.matrixU().col(i).transpose();
      continue;
    }
    // Any parameter with a share of the direction has an unbounded variance along it; the text
    // names the main ones.
    std::string direction;
    for (int j = 0; j < P; ++j) {
      if (std::abs(V(j, i)) < 1e-3) continue;
      singular[j] = true;
      if (std::abs(V(j, i)) < 0.2) continue;
      direction += (direction.empty() ? "" : " + ") + significant_text(V(j, i), 2) + " " +
                   parameter_name(layout, j);
    }
    r.singular_directions.push_back(direction);
  }
  // Residual autocovariance along the phase grid, pooled over x and y (each periodic), with the
  // degrees of freedom 2N - P, up to the lag L where it stops being significant (see the header).
  // Below N / 2: lag N / 2 of a periodic sequence is its own mirror and would count twice.
  const int max_lag =
      static_cast<int>(std::min<Eigen::Index>(options.correlation_lags, (N - 1) / 2));
  std::vector<double> gamma(max_lag + 1, 0.0);
  for (int lag = 0; lag <= max_lag; ++lag) {
    double sum = 0.0;
    for (int axis = 0; axis < 2; ++axis) {
      for (Eigen::Index j = 0; j < N; ++j) sum += res[axis * N + j] * res[axis * N + (j + lag) % N];
    }
    gamma[lag] = dof > 0 ? sum / dof : std::numeric_limits<double>::quiet_NaN();
  }
  r.residual_correlation_lag1 = gamma[0] > 0.0 && max_lag >= 1 ? gamma[1] / gamma[0] : 0.0;
  const double significant = 2.0 / std::sqrt(static_cast<double>(r.residuals));
  int L = 0;
  while (L < max_lag && gamma[0] > 0.0 && std::abs(gamma[L + 1] / gamma[0]) > significant) ++L;
  r.correlation_lags = L;
  // A Sigma A^T = gamma_0 A A^T + sum over lags 1..L of gamma_l (A_j A_(j+l)^T + transposed), A_j
  // the columns of A (truncated kernel).
  Eigen::MatrixXd cov = gamma[0] * A * A.transpose();
  Eigen::MatrixXd shifted(P, r.residuals);  // column j: A_(j + lag), within its axis
  for (int lag = 1; lag <= L; ++lag) {
    for (int axis = 0; axis < 2; ++axis) {
      for (Eigen::Index j = 0; j < N; ++j) {
        shifted.col(axis * N + j) = A.col(axis * N + (j + lag) % N);
      }
    }
    const Eigen::MatrixXd term = A * shifted.transpose();
    cov += gamma[lag] * (term + term.transpose());
  }
  double long_run = gamma[0];
  for (int lag = 1; lag <= L; ++lag) long_run += 2.0 * gamma[lag];
  r.variance_inflation = gamma[0] > 0.0 ? long_run / gamma[0] : 1.0;
  // A truncated sum can lose positive definiteness when negative correlations dominate: no
  // value's interval is taken narrower than with white residuals (interval()).
  const Eigen::MatrixXd white = gamma[0] * A * A.transpose();

  // Values and their gradients in theta (delta method).
  auto any_singular = [&](const Eigen::VectorXd& g) {
    for (int j = 0; j < P; ++j) {
      if (g[j] != 0.0 && singular[j]) return true;
    }
    return false;
  };
  auto value = [&](double v, const Eigen::VectorXd& g) {
    return interval(v, g, cov, white, any_singular(g));
  };
  Eigen::VectorXd g = Eigen::VectorXd::Zero(P);
  g[Layout::kOffset] = kRadToDeg;
  r.offset_deg = value(theta[Layout::kOffset] * kRadToDeg, g);
  // Reported in [0, 360), the interval shifted with it.
  const double turns = std::floor(r.offset_deg.value / 360.0);
  r.offset_deg.value -= 360.0 * turns;
  r.offset_deg.lo -= 360.0 * turns;
  r.offset_deg.hi -= 360.0 * turns;
  // An angle has no magnitude to compare with: identifiable when narrower than half a tooth pitch.
  r.offset_deg.identifiable =
      std::isfinite(r.offset_deg.sd) && 2.0 * kZ95 * r.offset_deg.sd < 180.0 / layout.teeth;
  const double fn = std::exp(theta[Layout::kLnFn]);
  const double zeta = std::exp(theta[Layout::kLnZeta]);
  g.setZero();
  g[Layout::kLnFn] = fn;
  r.fn_hz = value(fn, g);
  g.setZero();
  g[Layout::kLnZeta] = zeta;
  r.zeta = value(zeta, g);
  const double wn = kTwoPi * fn;
  const double m = k / (wn * wn);
  g.setZero();
  g[Layout::kLnFn] = -2.0 * m;  // m = k / (2 pi fn)^2
  r.m_kg = value(m, g);
  const double c = 2.0 * zeta * std::sqrt(k * m);  // = 2 zeta k / wn
  g.setZero();
  g[Layout::kLnFn] = -c;
  g[Layout::kLnZeta] = c;
  r.c_kg_s = value(c, g);
  for (int p = 0; p < layout.teeth; ++p) {
    for (int radial = 0; radial < 2; ++radial) {
      const int i = radial ? layout.kr(p) : layout.kt(p);
      const double ratio = std::exp(theta[i]);
      g.setZero();
      g[i] = ratio;
      (radial ? r.Kr_over_k_per_m : r.Kt_over_k_per_m).push_back(value(ratio, g));
      g[i] = k * ratio;
      (radial ? r.Kr_N_m2 : r.Kt_N_m2).push_back(value(k * ratio, g));
    }
  }
  r.runtime_s = seconds_since(t0);

  if (!r.converged) {
    r.summary.fail(
        "the joint fit did not converge after " + std::to_string(r.iterations) + " iterations" +
        (summary.termination_type == ceres::FAILURE
             ? ": it reached values whose simulated cut does not settle (too close to the "
               "stability limit to fit)"
             : "") +
        " (" + r.termination + ")");
    return r;
  }
  r.summary.succeed();
  if (!r.singular_directions.empty()) {
    std::string all;
    for (const std::string& d : r.singular_directions) all += (all.empty() ? "" : "; ") + d;
    r.summary.warnings.push_back("near-singular direction(s) of the fit (" + all +
                                 "): these values are not identifiable from this cut");
  }
  const std::vector<std::string> weak = r.not_identifiable();
  if (!weak.empty()) {
    std::string names;
    for (const std::string& n : weak) names += (names.empty() ? "" : ", ") + n;
    r.summary.warnings.push_back(
        "not identifiable from this cut (95 % interval wider than the "
        "value): " +
        names);
  }
  return r;
}

}  // namespace estimate
}  // namespace chatterlab
