#include "analysis/cutting/slot_fit.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace cutting {

namespace {

// Two feeds closer than this fraction of the largest feed count as one (a 0.025 mm step is
// 1/6 of 0.150 mm; 1e-6 only merges values that differ by rounding).
constexpr double kDistinctFeedRelTol = 1e-6;

void check_positive(const Eigen::Ref<const Eigen::VectorXd>& v, const char* name, bool allow_zero) {
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    const bool ok = std::isfinite(v[i]) && (allow_zero ? v[i] >= 0.0 : v[i] > 0.0);
    if (!ok) {
      std::ostringstream m;
      m << "fit_slot_coefficients: " << name << "[" << i << "] = " << v[i] << ": must be "
        << (allow_zero ? ">= 0" : "> 0");
      throw InputError(m.str());
    }
  }
}

// OLS of y = slope h + intercept; residuals are reported in N (times the record depth).
FittedLine fit_line(const Eigen::VectorXd& h, const Eigen::VectorXd& force_N,
                    const Eigen::VectorXd& b) {
  const Eigen::VectorXd y = force_N.cwiseQuotient(b);
  const double hm = h.mean();
  const double ym = y.mean();
  const Eigen::VectorXd dh = h.array() - hm;
  const Eigen::VectorXd dy = y.array() - ym;
  FittedLine line;
  line.slope_N_per_m2 = dh.dot(dy) / dh.squaredNorm();
  line.intercept_N_per_m = ym - line.slope_N_per_m2 * hm;
  const Eigen::VectorXd res_y = dy - line.slope_N_per_m2 * dh;
  const double ss_res = res_y.squaredNorm();
  const double ss_tot = dy.squaredNorm();
  line.r_squared = ss_tot > 0.0 ? 1.0 - ss_res / ss_tot : (ss_res == 0.0 ? 1.0 : 0.0);
  line.rms_residual_N =
      std::sqrt(res_y.cwiseProduct(b).squaredNorm() / static_cast<double>(h.size()));
  return line;
}

}  // namespace

double mean_force_slope_factor(SlotMeanForceModel model) {
  switch (model) {
    case SlotMeanForceModel::kSingleToothChip:
      return 2.0 / kPi;
    case SlotMeanForceModel::kDissertationEq3_5:
      return 4.0 / kPi;
  }
  throw InputError("mean_force_slope_factor: unknown SlotMeanForceModel " +
                   std::to_string(static_cast<int>(model)));
}

SlotCoefficients fit_slot_coefficients(const Eigen::Ref<const Eigen::VectorXd>& feeds_m,
                                       const Eigen::Ref<const Eigen::VectorXd>& mean_Ft_N,
                                       const Eigen::Ref<const Eigen::VectorXd>& mean_Fr_N,
                                       const Eigen::Ref<const Eigen::VectorXd>& depth_m,
                                       const DynoOptions& options) {
  validate(options);
  const Eigen::Index n = feeds_m.size();
  if (mean_Ft_N.size() != n || mean_Fr_N.size() != n || depth_m.size() != n) {
    std::ostringstream m;
    m << "fit_slot_coefficients: feeds_m has " << n << " entries, mean_Ft_N " << mean_Ft_N.size()
      << ", mean_Fr_N " << mean_Fr_N.size() << ", depth_m " << depth_m.size() << ": must be equal";
    throw InputError(m.str());
  }
  check_positive(feeds_m, "feeds_m", false);
  check_positive(mean_Ft_N, "mean_Ft_N", true);
  check_positive(mean_Fr_N, "mean_Fr_N", true);
  check_positive(depth_m, "depth_m", false);

  SlotCoefficients out;
  out.coefficients.Kte_N_m = std::numeric_limits<double>::quiet_NaN();  // not measured yet
  out.coefficients.Kre_N_m = std::numeric_limits<double>::quiet_NaN();
  out.mean_force_model = options.mean_force_model;
  out.records = static_cast<int>(n);
  std::vector<double> sorted(feeds_m.data(), feeds_m.data() + n);
  std::sort(sorted.begin(), sorted.end());
  if (n > 0) {
    const double tol = kDistinctFeedRelTol * sorted.back();
    out.distinct_feeds = 1;
    for (std::size_t i = 1; i < sorted.size(); ++i) {
      if (sorted[i] - sorted[i - 1] > tol) ++out.distinct_feeds;
    }
  }
  if (out.distinct_feeds < 2) {
    out.summary.fail("fewer than 2 distinct feeds: " + std::to_string(out.distinct_feeds) +
                     " among " + std::to_string(n) +
                     " records; a line in feed needs at least 2 (000 eqs 3.7-3.8)");
    return out;
  }

  const Eigen::VectorXd h = feeds_m;
  const Eigen::VectorXd b = depth_m;
  out.tangential = fit_line(h, mean_Ft_N, b);
  out.radial = fit_line(h, mean_Fr_N, b);

  // mean|F| = c b Kc h + b Ke (000 eqs 3.5-3.6 as corrected, or as printed) -> eqs 3.9-3.12.
  const double c = mean_force_slope_factor(options.mean_force_model);
  CuttingCoefficients& k = out.coefficients;
  k.Kt_N_m2 = out.tangential.slope_N_per_m2 / c;
  k.Kte_N_m = out.tangential.intercept_N_per_m;
  k.Kr_N_m2 = out.radial.slope_N_per_m2 / c;
  k.Kre_N_m = out.radial.intercept_N_per_m;

  const auto warn_line = [&](const FittedLine& line, const char* name) {
    if (line.r_squared < options.fit_r_squared_warning) {
      std::ostringstream m;
      m << name << " line: R^2 = " << line.r_squared << " < " << options.fit_r_squared_warning
        << ": mean force is not linear in feed";
      out.summary.warnings.push_back(m.str());
    }
    if (line.intercept_N_per_m < 0.0) {
      std::ostringstream m;
      m << name << " line: negative edge coefficient " << line.intercept_N_per_m
        << " N/m (the intercept should be >= 0)";
      out.summary.warnings.push_back(m.str());
    }
  };
  warn_line(out.tangential, "tangential");
  warn_line(out.radial, "radial");
  out.summary.succeed();
  return out;
}

}  // namespace cutting
}  // namespace chatterlab
