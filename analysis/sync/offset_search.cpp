#include "analysis/sync/offset_search.h"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/common/angles.h"
#include "analysis/common/constants.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace sync {

namespace {

void check_pair(const Eigen::Ref<const Eigen::VectorXd>& x,
                const Eigen::Ref<const Eigen::VectorXd>& y, const char* name) {
  if (x.size() != y.size() || x.size() < 8) {
    std::ostringstream m;
    m << "RevolutionMatcher: " << name << " x has " << x.size() << " points, y " << y.size()
      << ": must be equal and >= 8";
    throw InputError(m.str());
  }
  if (!x.allFinite() || !y.allFinite()) {
    throw InputError(std::string("RevolutionMatcher: ") + name +
                     " revolution has non-finite values");
  }
}

// Minimum of f on [a, b] by golden-section search until the bracket is narrower than tol.
template <typename F>
double golden_section(const F& f, double a, double b, double tol) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - g * (b - a);
  double d = a + g * (b - a);
  double fc = f(c);
  double fd = f(d);
  while (b - a > tol) {
    if (fc <= fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = f(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = f(d);
    }
  }
  return 0.5 * (a + b);
}

}  // namespace

RevolutionMatcher::RevolutionMatcher(const Eigen::Ref<const Eigen::VectorXd>& measured_x_m,
                                     const Eigen::Ref<const Eigen::VectorXd>& measured_y_m,
                                     const Eigen::Ref<const Eigen::VectorXd>& simulated_x_m,
                                     const Eigen::Ref<const Eigen::VectorXd>& simulated_y_m)
    : mx_(measured_x_m), my_(measured_y_m), sx_(simulated_x_m), sy_(simulated_y_m) {
  check_pair(measured_x_m, measured_y_m, "measured");
  check_pair(simulated_x_m, simulated_y_m, "simulated");
}

double RevolutionMatcher::rms_error_m(double offset_rad) const {
  const Eigen::Index N = mx_.size();
  const Eigen::Index S = sx_.size();
  const double s = static_cast<double>(S);
  // Position of measured point j on the simulated grid: (phi_j + delta) S / (2 pi), phi_j =
  // 2 pi j / N. u0 in [0, S) and the step S / N keep every position below 2 S.
  double u0 = std::fmod(offset_rad / kTwoPi, 1.0) * s;
  if (u0 < 0.0) u0 += s;
  if (u0 >= s) u0 -= s;
  const double step = s / static_cast<double>(N);
  double sum = 0.0;
  for (Eigen::Index j = 0; j < N; ++j) {
    double u = u0 + step * static_cast<double>(j);
    if (u >= s) u -= s;
    auto a = static_cast<Eigen::Index>(u);
    if (a >= S) a = S - 1;
    const double f = u - static_cast<double>(a);
    const Eigen::Index a1 = a + 1 == S ? 0 : a + 1;
    const double ex = mx_[j] - ((1.0 - f) * sx_[a] + f * sx_[a1]);
    const double ey = my_[j] - ((1.0 - f) * sy_[a] + f * sy_[a1]);
    sum += ex * ex + ey * ey;
  }
  return std::sqrt(sum / (2.0 * static_cast<double>(N)));
}

double RevolutionMatcher::measured_rms_m() const {
  return std::sqrt((mx_.squaredNorm() + my_.squaredNorm()) /
                   (2.0 * static_cast<double>(mx_.size())));
}

OffsetSearch search_offset(const RevolutionMatcher& matcher, int teeth,
                           const OffsetSearchOptions& options) {
  validate(options);
  if (teeth < 1) {
    throw InputError("search_offset: teeth = " + std::to_string(teeth) + ": must be >= 1");
  }
  const double step = options.coarse_step_deg;
  const auto K = static_cast<Eigen::Index>(std::ceil(360.0 / step - 1e-9));
  OffsetSearch r;
  r.candidate_deg.resize(K);
  r.error_m.resize(K);
  for (Eigen::Index k = 0; k < K; ++k) {
    r.candidate_deg[k] = static_cast<double>(k) * step;
    r.error_m[k] = matcher.rms_error_m(r.candidate_deg[k] * kDegToRad);
  }
  const auto E = [&](double deg) { return matcher.rms_error_m(deg * kDegToRad); };
  const auto refine = [&](double deg) {
    return wrap_deg(golden_section(E, deg - step, deg + step, options.resolution_deg));
  };

  Eigen::Index best = 0;
  r.error_m.minCoeff(&best);
  r.offset_angle_deg = refine(r.candidate_deg[best]);
  r.rms_error_m = E(r.offset_angle_deg);

  // The other teeth's alignments: the lowest coarse point within +-90 / n deg of
  // offset + k 360 / n, k = 1..n-1, refined; the best of them is the runner-up.
  for (int k = 1; k < teeth; ++k) {
    const double centre = r.offset_angle_deg + 360.0 * k / teeth;
    const double half_width = 90.0 / teeth;
    Eigen::Index at = -1;
    for (Eigen::Index c = 0; c < K; ++c) {
      if (circular_distance_deg(r.candidate_deg[c], centre) > half_width) continue;
      if (at < 0 || r.error_m[c] < r.error_m[at]) at = c;
    }
    if (at < 0) continue;
    const double deg = refine(r.candidate_deg[at]);
    const double e = E(deg);
    if (std::isnan(r.runner_up_error_m) || e < r.runner_up_error_m) {
      r.runner_up_deg = deg;
      r.runner_up_error_m = e;
    }
  }
  if (!std::isnan(r.runner_up_error_m)) {
    // Both zero (a noise-free match of alike teeth) is a tie, ratio 1.
    r.runner_up_ratio = r.rms_error_m > 0.0         ? r.runner_up_error_m / r.rms_error_m
                        : r.runner_up_error_m > 0.0 ? std::numeric_limits<double>::infinity()
                                                    : 1.0;
    r.ambiguous = r.runner_up_ratio <= 1.0 + options.ambiguity_ratio;
  }
  return r;
}

}  // namespace sync
}  // namespace chatterlab
