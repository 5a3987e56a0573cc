// Group fit of the cutting-force coefficients from the mean force magnitudes of slot records
// at several feeds (000 eqs 3.7-3.12; docs/dyno-coefficients.md).
//
// For each record i, y_i = mean|F|_i / b_i (force per unit depth, N/m) is fitted by ordinary
// least squares as a straight line in the feed per tooth h_i (000 eqs 3.7-3.8 divided by b):
//   y = slope h + intercept.
// With mean|F| = c b Kc h + b Ke (c from DynoOptions::mean_force_model: 2/pi by default,
// 4/pi for 000 eq 3.5) the coefficients are
//   Kc = slope / c   (default pi slope / 2;  000 eqs 3.9, 3.11: pi slope / 4),
//   Ke = intercept   (000 eqs 3.10, 3.12).
#pragma once

#include <Eigen/Core>
#include <limits>

#include "analysis/common/cutting_coefficients.h"
#include "analysis/common/summary.h"
#include "analysis/cutting/dyno_options.h"
#include "analysis/milling/force_model.h"

namespace chatterlab {
namespace cutting {

// y = slope h + intercept, y the mean force magnitude per unit depth.
struct FittedLine {
  double slope_N_per_m2 = std::numeric_limits<double>::quiet_NaN();     // d(mean|F|/b)/dh
  double intercept_N_per_m = std::numeric_limits<double>::quiet_NaN();  // mean|F|/b at h = 0
  double rms_residual_N = std::numeric_limits<double>::quiet_NaN();     // RMS of mean|F| - b y(h)
  double r_squared = std::numeric_limits<double>::quiet_NaN();          // of the fit in y

  // Mean force magnitude (N) predicted at feed h (m) and depth b (m), for plotting.
  double force_N(double feed_per_tooth_m, double depth_m) const {
    return depth_m * (slope_N_per_m2 * feed_per_tooth_m + intercept_N_per_m);
  }
};

struct SlotCoefficients {
  StepSummary summary;
  // Ktc, Kte, Krc, Kre of 000 eqs 3.9-3.12 as Kt_N_m2, Kte_N_m, Kr_N_m2, Kre_N_m; NaN (edge
  // terms too) unless summary.ok().
  CuttingCoefficients coefficients;
  FittedLine tangential;  // mean|F_t| / b against h
  FittedLine radial;      // mean|F_r| / b against h
  SlotMeanForceModel mean_force_model = SlotMeanForceModel::kSingleToothChip;  // as used
  int records = 0;                                                             // records in the fit
  int distinct_feeds = 0;  // distinct feed values among them
};

// c of mean|F| = c b Kc h + b Ke for the chosen model: 2/pi or 4/pi.
double mean_force_slope_factor(SlotMeanForceModel model);

// feeds_m: feed per tooth of each record (m, > 0); mean_Ft_N, mean_Fr_N: mean force magnitudes
// of each record (N, SlotRecordResult); depth_m: axial depth of each record (m, > 0). All the
// same length. Fewer than 2 distinct feeds is reported in summary; mismatched lengths,
// non-finite or non-positive inputs and bad options throw InputError.
SlotCoefficients fit_slot_coefficients(const Eigen::Ref<const Eigen::VectorXd>& feeds_m,
                                       const Eigen::Ref<const Eigen::VectorXd>& mean_Ft_N,
                                       const Eigen::Ref<const Eigen::VectorXd>& mean_Fr_N,
                                       const Eigen::Ref<const Eigen::VectorXd>& depth_m,
                                       const DynoOptions& options = {});

}  // namespace cutting
}  // namespace chatterlab
