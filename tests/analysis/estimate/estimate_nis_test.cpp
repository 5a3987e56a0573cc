// The NIS diagnostics of the EKF variants (EkfResult::nis, ekf_variants.h): recomputed
// independently for ekf-coeff-xy, and their bookkeeping for every variant.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <string>

#include "analysis/estimate/ekf.h"
#include "analysis/estimate/ekf_variants.h"
#include "tests/support/estimators_run.h"
#include "tests/support/record_property.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab {
namespace estimate {
namespace {

using chatterlab::testing::estimators_short_cut;

TEST(EkfNis, CoeffXyMatchesAnIndependentRecomputation) {
  // The filter of ekf-coeff-xy rebuilt from its documented tuning (ekf_options.h defaults) and
  // stepped here; before each update nu = z - H x-, S = H P- H^T + R (H selects x, y) and
  // NIS = nu^T S^-1 nu with S inverted explicitly. Reference bands in closed form: a
  // chi-square(2) variable has F^-1(p) = -2 ln(1 - p); the mean of K of them has the band of
  // chi-square(2K) / K, here against Wilson-Hilferty (relative error < 1e-8 at 2K ~ 4e4:
  // 4.3e-11 at 1e6, mpmath, growing as dof^-1.5). Tolerances: the mean to 1e-9 relative (the
  // same numbers summed in the same order; LDL^T vs an explicit inverse differ in the last
  // bits), the band to 1e-7.
  const MeasuredCut& cut = estimators_short_cut();
  const CutSetup setup;
  const CoeffEkfOptions o;
  const ModalParameters modal = chatterlab::testing::table52_modal();
  const EkfResult r = ekf_coeff(EstimatorId::kCoeffXy, cut, setup, {modal, {{2e9, 1e9}}}, o);
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;

  const CoeffXyModel model(cut.time_step_s, o.discretization, modal);
  CoeffXyModel::State x0 = CoeffXyModel::State::Zero();
  x0.tail<2>() << 2e9, 1e9;
  CoeffXyModel::StateMatrix P0 = CoeffXyModel::StateMatrix::Zero();
  P0.diagonal() << o.p0_deflection_m2, o.p0_velocity_m2_s2, o.p0_deflection_m2, o.p0_velocity_m2_s2,
      o.p0_Kt, o.p0_Kr;
  CoeffXyModel::Noise q;
  q << o.q_force_N2, o.q_force_N2, o.q_Kt, o.q_Kr;
  ToolEkf<CoeffXyModel> f =
      make_tool_ekf(model, x0, P0, q, CoeffXyModel::Measurement::Constant(o.r_m2));
  const CutChips chips(cut, setup);
  const double lower = -2.0 * std::log(1.0 - 0.025), upper = -2.0 * std::log(1.0 - 0.975);
  double sum = 0.0;
  long count = 0, inside = 0;
  for (Eigen::Index k = chips.first_step(); k + 1 < chips.samples(); ++k) {
    const StepChips c = chips.chips(k);
    ForceInput u;
    for (int p = 0; p < c.teeth; ++p) {
      u.regressor_m2 += tooth_regressor_m2(c.tooth[static_cast<std::size_t>(p)]);
    }
    f.predict(u);
    const Eigen::Vector2d z(cut.x_m[k + 1], cut.y_m[k + 1]);
    const Eigen::Vector2d nu(z[0] - f.state()[0], z[1] - f.state()[2]);
    Eigen::Matrix2d S;
    S << f.covariance()(0, 0) + o.r_m2, f.covariance()(0, 2), f.covariance()(2, 0),
        f.covariance()(2, 2) + o.r_m2;
    const double nis = nu.dot(S.inverse() * nu);
    sum += nis;
    ++count;
    if (nis >= lower && nis <= upper) ++inside;
    f.update(z);
  }
  ASSERT_EQ(r.nis.updates, count);
  EXPECT_EQ(r.nis.dof, 2 * count);
  EXPECT_NEAR(r.nis.mean, sum / count, 1e-9 * sum / count);
  EXPECT_DOUBLE_EQ(r.nis.fraction_inside, static_cast<double>(inside) / count);
  const double k = 2.0 * count, z975 = 1.959963984540054;  // normal 0.975 quantile
  const auto wilson_hilferty = [k](double zp) {
    return k * std::pow(1.0 - 2.0 / (9.0 * k) + zp * std::sqrt(2.0 / (9.0 * k)), 3) / (k / 2.0);
  };
  EXPECT_NEAR(r.nis.mean_band.upper, wilson_hilferty(z975), 1e-7 * r.nis.mean_band.upper);
  EXPECT_NEAR(r.nis.mean_band.lower, wilson_hilferty(-z975), 1e-7 * r.nis.mean_band.lower);
  EXPECT_EQ(r.nis.confidence, 0.95);
  ASSERT_EQ(r.nis_per_filter.size(), 1u);
  EXPECT_EQ(r.nis_per_filter[0].mean, r.nis.mean);
  // The default tuning's R (sd 10 um) is far above the record's noise (0.5 um): the NIS says so.
  EXPECT_LT(r.nis.mean, r.nis.mean_band.lower);
}

TEST(EkfNis, EveryVariantCountsItsUpdates) {
  // One update per step and filter, of as many rows as measured axes; per tooth the pooled
  // summary adds the filters' (each of which has its own).
  const MeasuredCut& cut = estimators_short_cut();
  const CutSetup setup;
  for (EstimatorId id : all_estimators()) {
    const EkfResult r = chatterlab::testing::run_estimator(id, cut, setup);
    ASSERT_TRUE(r.summary.ok()) << estimator_name(id) << ": " << r.summary.message;
    chatterlab::testing::record_and_print(std::string(estimator_name(id)) + "_mean_nis",
                                          r.nis.mean);
    const int axes = estimator_info(id).measured_axes;
    EXPECT_EQ(r.nis.updates, r.steps * r.filters) << estimator_name(id);
    EXPECT_EQ(r.nis.dof, r.nis.updates * axes) << estimator_name(id);
    EXPECT_TRUE(std::isfinite(r.nis.mean) && r.nis.mean > 0.0) << estimator_name(id);
    EXPECT_LT(r.nis.mean_band.lower, r.nis.mean_band.upper);
    EXPECT_GE(r.nis.fraction_inside, 0.0);
    EXPECT_LE(r.nis.fraction_inside, 1.0);
    ASSERT_EQ(r.nis_per_filter.size(), static_cast<std::size_t>(r.filters)) << estimator_name(id);
    double pooled = 0.0;
    for (const kalman::NisSummary& s : r.nis_per_filter) {
      EXPECT_EQ(s.updates, r.steps);
      pooled += s.mean * static_cast<double>(s.updates);
    }
    EXPECT_NEAR(r.nis.mean, pooled / static_cast<double>(r.nis.updates), 1e-12 * r.nis.mean);
  }
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
