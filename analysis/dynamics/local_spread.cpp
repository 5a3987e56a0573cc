#include "analysis/dynamics/local_spread.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace dynamics {

namespace {

// The p-quantile of |N(0, sigma^2)| is sigma Phi^-1((1 + p) / 2): Phi^-1(7/8) = 1.1503.
constexpr double kQuartileToSigma = 1.0 / 1.1503493803760079;
// Points further than this many robust stds from the first fit are left out of the second:
// white noise passes 99.7 % of its points, chatter all of them (|r| <= 1.25 s for a sinusoid,
// 1.15 s for clusters), a glitch of 10 noise stds none.
constexpr double kClip = 3.0;

// The kSpreadQuantile quantile of |v| (v is overwritten), interpolated linearly between order
// statistics at position p (m - 1).
double upper_quartile_abs(std::vector<double>& v) {
  for (double& e : v) e = std::abs(e);
  const double pos = kSpreadQuantile * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const double frac = pos - static_cast<double>(lo);
  const auto it = v.begin() + static_cast<std::ptrdiff_t>(lo);
  std::nth_element(v.begin(), it, v.end());
  const double below = *it;
  if (frac == 0.0) return below;
  const double above = *std::min_element(it + 1, v.end());
  return below + frac * (above - below);
}

// Polynomial of degree kTrendDegree in t_k = (2k - (m - 1)) / (m - 1) in [-1, 1] through x_k:
// least squares, then least squares again without the points beyond kClip robust stds of the
// first fit (one trimming step, so that a single glitch cannot tilt the trend). Returns the
// residuals of the final trend in `r` and sqrt(m / (m - p)) q75|r| / 1.1503, p = degree + 1.
double robust_trend_spread(const Eigen::Ref<const Eigen::VectorXd>& x, std::vector<double>& r) {
  constexpr int p = kTrendDegree + 1;
  const Eigen::Index m = x.size();
  const double dof = std::sqrt(static_cast<double>(m) / static_cast<double>(m - p));
  Eigen::Matrix<double, Eigen::Dynamic, p> basis(m, p);
  for (Eigen::Index k = 0; k < m; ++k) {
    const double t =
        (2.0 * static_cast<double>(k) - static_cast<double>(m - 1)) / static_cast<double>(m - 1);
    double power = 1.0;
    for (int j = 0; j < p; ++j, power *= t) basis(k, j) = power;
  }
  const auto fit = [&](const Eigen::Matrix<double, Eigen::Dynamic, 1>& weight) {
    const Eigen::Matrix<double, p, p> normal = basis.transpose() * weight.asDiagonal() * basis;
    const Eigen::Matrix<double, p, 1> rhs = basis.transpose() * weight.cwiseProduct(x);
    const Eigen::Matrix<double, p, 1> coef = normal.ldlt().solve(rhs);
    r.resize(static_cast<std::size_t>(m));
    for (Eigen::Index k = 0; k < m; ++k) {
      r[static_cast<std::size_t>(k)] = x[k] - basis.row(k).dot(coef);
    }
  };
  Eigen::VectorXd weight = Eigen::VectorXd::Ones(m);
  fit(weight);
  std::vector<double> scratch = r;
  const double limit = kClip * kQuartileToSigma * dof * upper_quartile_abs(scratch);
  Eigen::Index kept = 0;
  for (Eigen::Index k = 0; k < m; ++k) {
    weight[k] = std::abs(r[static_cast<std::size_t>(k)]) > limit ? 0.0 : 1.0;
    kept += weight[k] > 0.0 ? 1 : 0;
  }
  if (kept < m && kept >= 2 * p) fit(weight);
  scratch = r;
  return kQuartileToSigma * dof * upper_quartile_abs(scratch);
}

// h_k = v_k' (V'V)^-1 v_k of the full-window trend fit, for the standardised residuals.
Eigen::VectorXd leverages(int m) {
  constexpr int p = kTrendDegree + 1;
  Eigen::Matrix<double, Eigen::Dynamic, p> basis(m, p);
  for (int k = 0; k < m; ++k) {
    const double t = (2.0 * k - (m - 1.0)) / (m - 1.0);
    double power = 1.0;
    for (int j = 0; j < p; ++j, power *= t) basis(k, j) = power;
  }
  const Eigen::Matrix<double, p, p> inverse = (basis.transpose() * basis).inverse();
  Eigen::VectorXd h(m);
  for (int k = 0; k < m; ++k) h[k] = basis.row(k) * inverse * basis.row(k).transpose();
  return h;
}

}  // namespace

LocalSpread local_spread(const Eigen::Ref<const Eigen::VectorXd>& x, int window_revolutions) {
  const int w = window_revolutions;
  if (w < 5 || w % 2 == 0) {
    std::ostringstream m;
    m << "local spread: window_revolutions = " << w << ": must be odd and >= 5";
    throw InputError(m.str());
  }
  const Eigen::Index n = x.size();
  if (n < w) {
    std::ostringstream m;
    m << "local spread: " << n << " revolutions: at least window_revolutions = " << w << " needed";
    throw InputError(m.str());
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!std::isfinite(x[i])) {
      std::ostringstream m;
      m << "local spread: x[" << i << "] = " << x[i] << ": must be finite";
      throw InputError(m.str());
    }
  }

  const Eigen::Index half = w / 2;
  const Eigen::VectorXd h = leverages(w);

  LocalSpread out;
  out.spread.resize(n);
  out.central_residual.resize(n);
  std::vector<double> r;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index c = std::clamp(i, half, n - 1 - half);  // window centre
    out.spread[i] = robust_trend_spread(x.segment(c - half, w), r);
    const Eigen::Index j = i - c + half;  // i's place in the window
    out.central_residual[i] = r[static_cast<std::size_t>(j)] / std::sqrt(1.0 - h[j]);
  }
  return out;
}

double detrended_spread(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::VectorXd* residual) {
  const Eigen::Index m = x.size();
  if (m < kTrendDegree + 2) {
    std::ostringstream msg;
    msg << "detrended spread: " << m << " values: at least " << kTrendDegree + 2 << " needed";
    throw InputError(msg.str());
  }
  std::vector<double> r;
  const double s = robust_trend_spread(x, r);
  if (residual != nullptr) *residual = Eigen::Map<const Eigen::VectorXd>(r.data(), m);
  return s;
}

double quartile_scale(const Eigen::Ref<const Eigen::VectorXd>& v) {
  if (v.size() == 0) throw InputError("quartile scale: no values");
  std::vector<double> a(v.data(), v.data() + v.size());
  return kQuartileToSigma * upper_quartile_abs(a);
}

}  // namespace dynamics
}  // namespace chatterlab
