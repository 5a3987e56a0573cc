// The identification sequence of 000 sec. 5.1 iterated to a fixed point (identification.h), on a
// simulated cut with known truth (tests/support/synthetic_cuts.h: 000 table 5.2 incline 1 at 1 mm,
// 0.2 s, 5e-7 m noise, resampled to 5e-7 s) seen through a tachometer whose edge falls at an offset
// angle of 146.7 deg, starting from the hammer-test and dynamometer values of 000 sec. 5.1 and
// an offset 0.6 deg off.
//
// Acceptance (as the end-to-end test tests/app/cut_identification_test.cpp): offset within
// 0.5 deg, per-tooth coefficients within 2 %, m and k within 2 %, c within 10 %.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/estimate/identification.h"
#include "analysis/milling/simulation.h"
#include "tests/support/record_property.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab {
namespace estimate {
namespace {

using testing::hammer_modal;
using testing::table52_coefficients;
using testing::table52_modal;

constexpr double kOffsetToleranceDeg = 0.5;
constexpr double kCoefficientTolerance = 0.02;
constexpr double kMassStiffnessTolerance = 0.02;
constexpr double kDampingTolerance = 0.10;

// The offset on the measured mean revolution's grid (400 points, 0.9 deg) and on the simulated
// revolution's steps (1,600, 0.225 deg): 163 grid points.
constexpr int kOffsetGridPoints = 163;
constexpr double kTrueOffsetDeg = 0.9 * kOffsetGridPoints;

// The window as the tachometer sees it: theta_1 - offset (identification.h takes the
// tachometer phase and adds each pass's offset).
const MeasuredCut& window() {
  static const MeasuredCut c = [] {
    MeasuredCut w = testing::synthetic_cut(testing::SyntheticCutSpec{});
    w.theta1_rad.array() -= kTrueOffsetDeg * kDegToRad;
    return w;
  }();
  return c;
}

// The measured mean revolution at 1 mm without noise: the truth's steady revolution (the last
// of 60 simulated ones) at phase phi_j = 2 pi j / 400, i.e. at theta_1 = phi_j + offset.
const sync::RevolutionMean& measured_mean() {
  static const sync::RevolutionMean m = [] {
    milling::SimulationOptions o = testing::table52_incline1();
    o.depth = milling::DepthProfile::constant(1e-3, 60);
    milling::RecordingRequest rq;
    rq.full_revolutions = {59};
    const milling::SimulationResult sim = milling::simulate(o, rq);
    EXPECT_TRUE(sim.summary.ok());
    const milling::RevolutionRecord& r = sim.records.front();
    sync::RevolutionMean mean;
    const int N = 400;
    const int per_point = static_cast<int>(r.x_m.size()) / N;  // 4 steps per grid point
    mean.phase_rad.resize(N);
    mean.x_m.resize(N);
    mean.y_m.resize(N);
    for (int j = 0; j < N; ++j) {
      const Eigen::Index step = (per_point * (j + kOffsetGridPoints)) % r.x_m.size();
      mean.phase_rad[j] = kTwoPi * j / N;
      mean.x_m[j] = r.x_m[step];
      mean.y_m[j] = r.y_m[step];
    }
    return mean;
  }();
  return m;
}

IdentificationInputs inputs() {
  IdentificationInputs in;
  in.setup = CutSetup{};                        // 000 sec. 5.2, as the synthetic cut
  in.cut_model = milling::SimulationOptions{};  // same tool and conditions
  in.initial_offset_deg = kTrueOffsetDeg + 0.6;
  in.offset_depth_m = 1e-3;
  in.hammer = hammer_modal();
  in.dynamometer = testing::dynamometer_coefficients();
  return in;
}

double error(double value, double truth) { return std::abs(value / truth - 1.0); }

TEST(Identification, SettlesOnTheTruthFromTheHammerAndDynamometerValues) {
  const IdentificationResult r = identify_cut(window(), measured_mean(), inputs());
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  EXPECT_TRUE(r.converged);
  EXPECT_TRUE(r.summary.warnings.empty());
  // The hammer damping is 40 % off: the sequence needs more than one pass.
  ASSERT_GE(r.passes.size(), 2u);
  EXPECT_EQ(r.passes.front().offset_deg, kTrueOffsetDeg + 0.6);
  for (std::size_t i = 1; i < r.passes.size(); ++i) {
    EXPECT_EQ(r.passes[i].offset_deg, r.passes[i - 1].offset_after_deg);  // each pass's start
  }
  EXPECT_TRUE(passes_settled(r.passes.back(), r.passes[r.passes.size() - 2], {}));
  EXPECT_EQ(r.offset.search.offset_angle_deg, r.passes.back().offset_after_deg);
  const double offset_error = std::abs(r.offset.search.offset_angle_deg - kTrueOffsetDeg);
  chatterlab::testing::record_and_print("passes", static_cast<double>(r.passes.size()));
  chatterlab::testing::record_and_print("offset_error_deg", offset_error);
  EXPECT_LT(offset_error, kOffsetToleranceDeg);
  const ModalParameters t = table52_modal();
  EXPECT_LT(error(r.modal.m_kg, t.m_kg), kMassStiffnessTolerance);
  EXPECT_LT(error(r.modal.k_N_m, t.k_N_m), kMassStiffnessTolerance);
  EXPECT_LT(error(r.modal.c_kg_s, t.c_kg_s), kDampingTolerance);
  chatterlab::testing::record_and_print("m_error_pct", 100 * error(r.modal.m_kg, t.m_kg));
  chatterlab::testing::record_and_print("c_error_pct", 100 * error(r.modal.c_kg_s, t.c_kg_s));
  chatterlab::testing::record_and_print("k_error_pct", 100 * error(r.modal.k_N_m, t.k_N_m));
  const std::vector<ToothCoefficients> k = table52_coefficients();
  ASSERT_EQ(r.coefficients.size(), k.size());
  for (std::size_t p = 0; p < k.size(); ++p) {
    EXPECT_LT(error(r.coefficients[p].Kt_N_m2, k[p].Kt_N_m2), kCoefficientTolerance) << p;
    EXPECT_LT(error(r.coefficients[p].Kr_N_m2, k[p].Kr_N_m2), kCoefficientTolerance) << p;
  }
}

TEST(Identification, OnePassIsTheSequenceAsWritten) {
  IdentificationOptions o;
  o.max_passes = 1;
  const IdentificationResult r = identify_cut(window(), measured_mean(), inputs(), o);
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  ASSERT_EQ(r.passes.size(), 1u);
  EXPECT_FALSE(r.converged);                // nothing to compare with
  EXPECT_TRUE(r.summary.warnings.empty());  // and nothing to warn about with one pass asked
  EXPECT_EQ(r.passes[0].offset_deg, kTrueOffsetDeg + 0.6);
  EXPECT_EQ(r.modal.m_kg, r.passes[0].modal.m_kg);
}

TEST(Identification, UnsettledPassesWarn) {
  // Tolerances no pass can meet: every pass runs and the result says so.
  IdentificationOptions o;
  o.max_passes = 2;
  o.parameter_tolerance = 0.0;
  const IdentificationResult r = identify_cut(window(), measured_mean(), inputs(), o);
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  EXPECT_EQ(r.passes.size(), 2u);
  EXPECT_FALSE(r.converged);
  ASSERT_EQ(r.summary.warnings.size(), 1u);
  EXPECT_EQ(r.summary.warnings[0],
            "identification: not settled after 2 passes (offset and parameters still move by "
            "more than the tolerances)");
}

TEST(Identification, AFailingStepEndsTheSequenceWithItsMessage) {
  IdentificationInputs in = inputs();
  in.hammer.m_kg = -1.0;
  const IdentificationResult r = identify_cut(window(), measured_mean(), in);
  EXPECT_FALSE(r.summary.ok());
  EXPECT_EQ(r.summary.message, "inputs.modal.m_kg = -1: must be > 0");
  EXPECT_TRUE(r.passes.empty());
}

TEST(Identification, BadOptionsNameTheField) {
  IdentificationOptions o;
  o.max_passes = 0;
  try {
    identify_cut(window(), measured_mean(), inputs(), o);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "identification.max_passes = 0: must be >= 1");
  }
  o = IdentificationOptions{};
  o.offset_tolerance_deg = -1.0;
  EXPECT_THROW(identify_cut(window(), measured_mean(), inputs(), o), InputError);
}

IdentificationPass pass(double offset_after_deg, double m_kg, double Kt1) {
  IdentificationPass p;
  p.offset_after_deg = offset_after_deg;
  p.modal = {m_kg, 22.0, 9.8e5};
  p.coefficients = {{Kt1, 2.2e8}, {6.6e9, 4.2e9}};
  return p;
}

TEST(PassesSettled, OffsetAndEveryParameterMustSettle) {
  const IdentificationOptions o;  // 0.05 deg, 0.5 %
  const IdentificationPass before = pass(147.0, 0.0313, 2.5e8);
  EXPECT_TRUE(passes_settled(pass(147.04, 0.0313 * 1.004, 2.5e8 * 0.996), before, o));
  EXPECT_FALSE(passes_settled(pass(147.06, 0.0313, 2.5e8), before, o));         // offset
  EXPECT_FALSE(passes_settled(pass(147.0, 0.0313 * 1.006, 2.5e8), before, o));  // m
  EXPECT_FALSE(passes_settled(pass(147.0, 0.0313, 2.5e8 * 1.006), before, o));  // Kt1
  // The offset is a circular quantity: 359.98 deg and 0.01 deg lie 0.03 deg apart.
  EXPECT_TRUE(passes_settled(pass(0.01, 0.0313, 2.5e8), pass(359.98, 0.0313, 2.5e8), o));
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
