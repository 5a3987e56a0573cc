// The feedback coefficient filter (ekf-coeff-xy-feedback, 000 secs 4.4 and 8.2: chips from the
// filter's own delayed estimates) against the measured-chip per-tooth filter
// (ekf-coeff-xy-per-tooth) on the simulated cut of estimate_coeff_test.cpp (000 table 5.2
// incline 1 at 1 mm, 0.2 s; 000 sec. 6.1's start values), at the measurement noise of 000
// sec. 6.1 and above it.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "analysis/estimate/ekf_variants.h"
#include "tests/support/record_property.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab {
namespace estimate {
namespace {

using testing::dissertation_start_coefficients;
using testing::table52_coefficients;
using testing::table52_modal;

MeasuredCut cut_with_noise(double noise_m, unsigned seed) {
  testing::SyntheticCutSpec spec;
  spec.noise_m = noise_m;
  spec.seed = seed;
  return testing::synthetic_cut(spec);
}

struct Errors {
  double Kt1, Kr1, Kt2, Kr2;  // relative errors
};

Errors errors_of(const EkfResult& r) {
  const auto t = table52_coefficients();
  return {r.value("Kt1_N_m2") / t[0].Kt_N_m2 - 1, r.value("Kr1_N_m2") / t[0].Kr_N_m2 - 1,
          r.value("Kt2_N_m2") / t[1].Kt_N_m2 - 1, r.value("Kr2_N_m2") / t[1].Kr_N_m2 - 1};
}

void record(const std::string& name, const EkfResult& r) {
  const Errors e = errors_of(r);
  testing::record_and_print(name + "_Kt1_error_pct", 100 * e.Kt1);
  testing::record_and_print(name + "_Kr1_error_pct", 100 * e.Kr1);
  testing::record_and_print(name + "_Kt2_error_pct", 100 * e.Kt2);
  testing::record_and_print(name + "_Kr2_error_pct", 100 * e.Kr2);
  testing::record_and_print(name + "_runtime_s", r.runtime_s);
}

// Errors in variables: the measured-chip filter's chip carries the noise of x(t) - x(t - tau),
// which biases its coefficients low, most on the stronger tooth (tooth 2, 27 times tooth 1).
// The feedback filter takes the chip from its own (filtered) estimates. Measured over seeds
// 20240607, 1, 2, 3 (tooth 2, Kt2 / Kr2 error):
//   noise 0.5 um: measured -0.18..+0.32 %, feedback -0.14..+0.32 % (all four within 0.4 %)
//   noise 2 um:   measured -2.2..-5.1 %,   feedback -0.39..+1.33 %
//   noise 5 um:   measured -16.8..-23.0 %, feedback -1.3..+3.4 %
// Acceptance, over the first three seeds: at 0.5 um both within 0.5 % on all four; at 2 and 5
// um the measured-chip filter's mean tooth-2 error below -2 % and -15 %, the feedback filter's
// mean within +-1 % and +-2 %, and every seed within 2 % and 4 %.
TEST(EkfFeedback, RemovesTheErrorsInVariablesBiasOfTheMeasuredChip) {
  struct Level {
    double noise_m;
    double measured_mean_below;  // the measured-chip filter's mean tooth-2 error is below this
    double feedback_mean_within;
    double feedback_each_within;
  };
  for (const Level& l : {Level{5e-7, 0.005, 0.005, 0.005}, Level{2e-6, -0.02, 0.01, 0.02},
                         Level{5e-6, -0.15, 0.02, 0.04}}) {
    SCOPED_TRACE("noise " + std::to_string(l.noise_m) + " m");
    double measured_sum = 0.0, feedback_sum = 0.0;
    int count = 0;
    for (unsigned seed : {20240607u, 1u, 2u}) {
      const MeasuredCut cut = cut_with_noise(l.noise_m, seed);
      const CoeffEkfInputs in{table52_modal(), dissertation_start_coefficients()};
      const EkfResult measured = ekf_coeff(EstimatorId::kCoeffXyPerTooth, cut, CutSetup{}, in);
      const EkfResult feedback = ekf_coeff(EstimatorId::kCoeffXyFeedback, cut, CutSetup{}, in);
      ASSERT_TRUE(measured.summary.ok()) << measured.summary.message;
      ASSERT_TRUE(feedback.summary.ok()) << feedback.summary.message;
      EXPECT_EQ(feedback.estimator, "ekf-coeff-xy-feedback");
      EXPECT_EQ(feedback.steps, measured.steps);
      const std::string n = "seed" + std::to_string(seed) + "_noise_" +
                            std::to_string(static_cast<int>(std::lround(l.noise_m * 1e9))) + "nm_";
      record(n + "measured", measured);
      record(n + "feedback", feedback);
      const Errors m = errors_of(measured);
      const Errors f = errors_of(feedback);
      measured_sum += m.Kt2 + m.Kr2;
      feedback_sum += f.Kt2 + f.Kr2;
      count += 2;
      EXPECT_LT(std::abs(f.Kt2), l.feedback_each_within) << seed;
      EXPECT_LT(std::abs(f.Kr2), l.feedback_each_within) << seed;
      if (l.noise_m < 1e-6) {
        for (double e : {m.Kt1, m.Kr1, m.Kt2, m.Kr2, f.Kt1, f.Kr1, f.Kt2, f.Kr2}) {
          EXPECT_LT(std::abs(e), 0.005) << seed;
        }
      }
    }
    const double measured_mean = measured_sum / count;
    const double feedback_mean = feedback_sum / count;
    testing::record_and_print("measured_tooth2_mean_error_pct", 100 * measured_mean);
    testing::record_and_print("feedback_tooth2_mean_error_pct", 100 * feedback_mean);
    if (l.noise_m > 1e-6) {
      EXPECT_LT(measured_mean, l.measured_mean_below);
    }
    EXPECT_LT(std::abs(feedback_mean), l.feedback_mean_within);
  }
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
