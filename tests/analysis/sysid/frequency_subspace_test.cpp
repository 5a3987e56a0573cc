// The frequency-domain subspace method of McKelvey, Akcay and Ljung (1996)
// (analysis/sysid/frequency_subspace.h).
#include "analysis/sysid/frequency_subspace.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>

#include "analysis/sysid/era.h"
#include "analysis/sysid/random_system.h"

namespace chatterlab {
namespace sysid {
namespace {

constexpr double kRate = 10000.0;

// Each pole of `a` to its nearest in `b`, the largest distance.
double pole_set_distance(const Eigen::VectorXcd& a, const Eigen::VectorXcd& b) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index j = 0; j < b.size(); ++j) best = std::min(best, std::abs(a[i] - b[j]));
    worst = std::max(worst, best);
  }
  return worst;
}

// Noise-free: the median rule with its floor finds the order, and the poles, D and the FRF
// come back to rounding. Tolerance 1e-8 in z for the poles (the closest pairs of a random
// system are the ill-conditioned ones; measured: see the stream output), fit > 99.99 %.
TEST(FrequencySubspace, RecoversATenStateSystemWithoutNoise) {
  RandomSystemOptions o;
  o.order = 10;
  const DiscreteStateSpace truth = random_stable_system(o, kRate, 110);
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(1025, 0.0, 0.5 * kRate);
  const Eigen::VectorXcd G = frequency_response(truth, f);
  const FrequencySubspaceResult r = frequency_subspace_identify(f, G, kRate);
  ASSERT_TRUE(r.summary.ok()) << r.summary.full_report();
  EXPECT_EQ(r.block_rows, 80);
  EXPECT_EQ(r.real_columns, 2048);
  EXPECT_NEAR(r.aspect_ratio, 80.0 / 1968.0, 1e-15);
  EXPECT_EQ(r.order_by_threshold, 10);
  EXPECT_EQ(r.model.order(), 10);
  EXPECT_EQ(r.unstable_removed, 0);
  const double d_poles =
      std::max(pole_set_distance(poles(truth), r.poles), pole_set_distance(r.poles, poles(truth)));
  EXPECT_LT(d_poles, 1e-8);
  EXPECT_NEAR(r.model.D, truth.D, 1e-8);
  EXPECT_NEAR(r.dc_gain, dc_gain(truth), 1e-7 * std::max(1.0, std::abs(dc_gain(truth))));
  EXPECT_GT(r.fit_pct, 99.99);
  // The fit points exclude DC (as ERA's) and the model's values are its frequency response.
  EXPECT_EQ(r.fit_f_hz.size(), 1024);
  const Eigen::VectorXcd G_model = frequency_response(r.model, r.fit_f_hz);
  EXPECT_LT((G_model - r.fit_G_model).cwiseAbs().maxCoeff(), 1e-9 * G.cwiseAbs().maxCoeff());
  std::cout << "pole distance " << d_poles << ", fit " << r.fit_pct << " %, s_10/s_11 "
            << r.singular_values[9] / r.singular_values[10] << "\n";
}

// A given order is used as it is; q and the frequency grid need not be the defaults (any
// spacing: a log grid here).
TEST(FrequencySubspace, GivenOrderOnALogGrid) {
  RandomSystemOptions o;
  o.order = 6;
  const DiscreteStateSpace truth = random_stable_system(o, kRate, 3);
  const Eigen::VectorXd f =
      Eigen::VectorXd::LinSpaced(400, std::log(1.0), std::log(4999.0)).array().exp().matrix();
  const Eigen::VectorXcd G = frequency_response(truth, f);
  FrequencySubspaceOptions opt;
  opt.order = 6;
  opt.block_rows = 12;
  const FrequencySubspaceResult r = frequency_subspace_identify(f, G, kRate, opt);
  ASSERT_TRUE(r.summary.ok()) << r.summary.full_report();
  EXPECT_EQ(r.model.order(), 6);
  EXPECT_TRUE(std::isnan(r.threshold));
  EXPECT_LT(pole_set_distance(poles(truth), r.poles), 1e-8);
  EXPECT_GT(r.fit_pct, 99.999);
}

// An unstable pair in the data (|z| = 1.02; on the unit circle its FRF is finite) is removed
// by the Schur split, and B and D are fitted for the stable rest.
TEST(FrequencySubspace, UnstablePolesAreRemoved) {
  RandomSystemOptions o;
  o.order = 8;
  const DiscreteStateSpace stable = random_stable_system(o, kRate, 21);
  DiscreteStateSpace both = stable;
  both.A = Eigen::MatrixXd::Zero(10, 10);
  both.A.topLeftCorner(8, 8) = stable.A;
  const double rad = 1.02, th = 0.7;
  both.A.bottomRightCorner(2, 2) << rad * std::cos(th), -rad * std::sin(th), rad * std::sin(th),
      rad * std::cos(th);
  both.B.resize(10);
  both.B << stable.B, 0.3, -0.8;
  both.C.resize(10);
  both.C << stable.C, 1.1, 0.4;
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(513, 0.0, 0.5 * kRate);
  const FrequencySubspaceResult r =
      frequency_subspace_identify(f, frequency_response(both, f), kRate);
  ASSERT_TRUE(r.summary.ok()) << r.summary.full_report();
  EXPECT_EQ(r.order_by_threshold, 10);
  EXPECT_EQ(r.unstable_removed, 2);
  EXPECT_EQ(r.model.order(), 8);
  EXPECT_LT(r.poles.cwiseAbs().maxCoeff(), 1.0);
  EXPECT_LT(pole_set_distance(r.poles, poles(stable)), 1e-7);
  ASSERT_FALSE(r.summary.warnings.empty());
  EXPECT_NE(r.summary.warnings.back().find("2 unstable states removed"), std::string::npos);
}

// Bad data and options fail the summary with a message naming the field; nothing throws.
TEST(FrequencySubspace, BadInputNamesTheField) {
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(101, 0.0, 5000.0);
  const Eigen::VectorXcd G = Eigen::VectorXcd::Constant(101, {1.0, 0.5});
  const auto fails_with = [&](const Eigen::VectorXd& ff, const Eigen::VectorXcd& gg, double rate,
                              const FrequencySubspaceOptions& opt, const std::string& key) {
    const FrequencySubspaceResult r = frequency_subspace_identify(ff, gg, rate, opt);
    EXPECT_TRUE(r.summary.failed()) << key;
    EXPECT_NE(r.summary.message.find(key), std::string::npos) << r.summary.message;
  };
  FrequencySubspaceOptions small;
  small.max_order = 10;  // q = 20 <= 101 points
  fails_with(f, G, 0.0, small, "sample_rate_hz");
  fails_with(f, G, std::nan(""), small, "sample_rate_hz");
  fails_with(f, G.head(100), kRate, small, "FRF values");
  Eigen::VectorXd f_bad = f;
  f_bad[50] = f_bad[49];
  fails_with(f_bad, G, kRate, small, "rise strictly");
  f_bad = f;
  f_bad[100] = 6000.0;
  fails_with(f_bad, G, kRate, small, "sample_rate_hz / 2");
  f_bad = f;
  f_bad[0] = -1.0;
  fails_with(f_bad, G, kRate, small, "freq_hz = -1");
  Eigen::VectorXcd G_bad = G;
  G_bad[7] = {std::numeric_limits<double>::infinity(), 0.0};
  fails_with(f, G_bad, kRate, small, "FRF at 350");
  fails_with(f, Eigen::VectorXcd::Zero(101), kRate, small, "no dynamics");
  // 101 points give L = 200 real columns: q = 2 max_order = 80 is fine, q = 101 is not.
  FrequencySubspaceOptions o = small;
  o.block_rows = 101;
  fails_with(f, G, kRate, o, "block_rows = 101");
  o = small;
  o.order = 11;
  fails_with(f, G, kRate, o, "order = 11");
  o = small;
  o.order = 5;
  o.block_rows = 5;
  fails_with(f, G, kRate, o, "block_rows = 5");
  o = small;
  o.max_order = 0;
  fails_with(f, G, kRate, o, "max_order = 0");
  // A real constant FRF is a pure D: no state above the floor.
  const FrequencySubspaceResult r =
      frequency_subspace_identify(f, Eigen::VectorXcd::Constant(101, 1.3), kRate, small);
  EXPECT_TRUE(r.summary.failed());
  EXPECT_NE(r.summary.message.find("kept no state"), std::string::npos) << r.summary.message;
}

}  // namespace
}  // namespace sysid
}  // namespace chatterlab
