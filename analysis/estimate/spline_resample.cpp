#include "analysis/estimate/spline_resample.h"

#include <cmath>
#include <sstream>

#include "analysis/common/require.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace estimate {

namespace {

template <typename T>
void require(bool rule_holds, const char* field, T value, const char* rule) {
  require_rule(rule_holds, std::string("resample.") + field, value, rule);
}

// Second derivatives M_0 .. M_n-1 at the knots (header), by the Thomas algorithm on the
// tridiagonal system for M_1 .. M_n-2 (diagonally dominant: no pivoting needed).
Eigen::VectorXd knot_curvatures(const Eigen::Ref<const Eigen::VectorXd>& y, double h,
                                SplineEnd end) {
  const Eigen::Index n = y.size();
  const Eigen::Index m = n - 2;  // unknowns M_1 .. M_n-2
  Eigen::VectorXd M = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd diag(m), upper(m), rhs(m);
  const double scale = 6.0 / (h * h);
  for (Eigen::Index i = 0; i < m; ++i) {
    diag[i] = 4.0;
    upper[i] = 1.0;  // the sub-diagonal equals the super-diagonal of the row above
    rhs[i] = scale * (y[i] - 2.0 * y[i + 1] + y[i + 2]);
  }
  // Row r has sub-diagonal lower(r) and super-diagonal upper[r]. Not-a-knot: rows 0 and m-1
  // become 6 M = rhs (header), so upper[0] = 0 and lower(m-1) = 0.
  const bool not_a_knot = end == SplineEnd::kNotAKnot;
  if (not_a_knot) {
    diag[0] = 6.0;
    upper[0] = 0.0;
    diag[m - 1] = 6.0;
  }
  const auto lower = [&](Eigen::Index r) { return (not_a_knot && r == m - 1) ? 0.0 : 1.0; };
  for (Eigen::Index r = 1; r < m; ++r) {
    const double w = lower(r) / diag[r - 1];
    diag[r] -= w * upper[r - 1];
    rhs[r] -= w * rhs[r - 1];
  }
  M[m] = rhs[m - 1] / diag[m - 1];
  for (Eigen::Index r = m - 2; r >= 0; --r) M[r + 1] = (rhs[r] - upper[r] * M[r + 2]) / diag[r];
  if (not_a_knot) {
    M[0] = 2.0 * M[1] - M[2];
    M[n - 1] = 2.0 * M[n - 2] - M[n - 3];
  }
  return M;
}

}  // namespace

Eigen::Index resampled_count(Eigen::Index n, double step_in_s, double step_out_s) {
  if (n < 1) return 0;
  const double span_steps = static_cast<double>(n - 1) * step_in_s / step_out_s;
  return static_cast<Eigen::Index>(std::floor(span_steps + 1e-9)) + 1;
}

Eigen::VectorXd resample_cubic_spline(const Eigen::Ref<const Eigen::VectorXd>& samples,
                                      double step_in_s, double step_out_s, SplineEnd end) {
  require(samples.size() >= 4, "samples.size()", samples.size(),
          "must be >= 4 (a cubic spline needs four knots)");
  require(std::isfinite(step_in_s) && step_in_s > 0.0, "step_in_s", step_in_s,
          "must be finite and > 0");
  require(std::isfinite(step_out_s) && step_out_s > 0.0, "step_out_s", step_out_s,
          "must be finite and > 0");
  for (Eigen::Index i = 0; i < samples.size(); ++i) {
    if (!std::isfinite(samples[i])) {
      std::ostringstream f;
      f << "samples[" << i << "]";
      require(false, f.str().c_str(), samples[i], "must be finite");
    }
  }
  const Eigen::Index n = samples.size();
  const Eigen::VectorXd M = knot_curvatures(samples, step_in_s, end);
  const Eigen::Index count = resampled_count(n, step_in_s, step_out_s);
  Eigen::VectorXd out(count);
  const double h2_6 = step_in_s * step_in_s / 6.0;
  const double ratio = step_out_s / step_in_s;
  for (Eigen::Index j = 0; j < count; ++j) {
    const double s = static_cast<double>(j) * ratio;  // position in input steps
    Eigen::Index i = static_cast<Eigen::Index>(std::floor(s));
    if (i > n - 2) i = n - 2;  // the last point (s = n - 1) lies on the last segment
    const double u = s - static_cast<double>(i);
    const double v = 1.0 - u;
    out[j] = v * samples[i] + u * samples[i + 1] +
             h2_6 * ((v * v * v - v) * M[i] + (u * u * u - u) * M[i + 1]);
  }
  return out;
}

}  // namespace estimate
}  // namespace chatterlab
