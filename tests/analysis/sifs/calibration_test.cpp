// Static SIFS calibration (format sec. 6 "sifs-static", notes/003.md sec. 2) on a synthetic
// campaign built from a known calibration matrix C: three tests (x, y, z), seven 44.5 N steps
// (003 sec. 3.2: 10 lb weights) each way, linear drift and white noise on every washer.
#include "analysis/sifs/calibration.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "tests/support/expect_input_error.h"
#include "tests/support/record_property.h"

namespace chatterlab {
namespace sifs {
namespace {

using chatterlab::testing::expect_input_error;

constexpr double kFs = 1024.0;   // 003 sec. 1: static calibration rate
constexpr double kStepN = 44.5;  // one 10 lb weight (003 sec. 3.2)
constexpr int kSteps = 7;
constexpr double kSigmaN = 0.05;  // washer noise, washer newtons per sample
constexpr double kHoldS = 5.0;    // steady time per step
constexpr double kRampS = 1.0;    // load change between steps
constexpr double kRestS = 10.0;   // unloaded spells
constexpr double kMarginS = 0.5;  // window margin inside a steady spell

// Noise-free records: drift is exactly linear, so every step is exact to rounding of sums over
// ~1e5 samples of O(10 N).
constexpr double kRoundingRel = 1e-9;

// The format's truth example (EXPERIMENT_FORMAT.md sec. 6 truth.yaml).
Eigen::Matrix3d truth_C() {
  Eigen::Matrix3d C;
  C << 18.9, -19.0, 2.10, 0.28, 23.3, -1.62, 1.83, -3.09, 53.9;
  return C;
}

struct Record {
  Washers w;
  std::vector<LoadWindow> windows;
  Eigen::Matrix<double, 6, 1> drift_offset, drift_per_s;  // truth
};

// One static test: unloaded, +1..+7 steps, unloaded, -1..-7 steps, unloaded. Washers from the
// pair signals s = S f: x1 = a + s_x, x2 = a - s_x, y1 = b - s_y, y2 = b + s_y,
// z1 = s_z + d, z2 = s_z - d, plus drift o_c + b_c t and noise. `quadratic` adds
// quadratic * load^2 to the loaded axis's pair signal (a non-linear washer).
Record make_record(Axis axis, const Eigen::Matrix3d& S, double sigma, std::uint64_t seed,
                   double quadratic = 0.0) {
  struct Spell {
    double load, seconds;
  };
  std::vector<Spell> spells = {{0.0, kRestS}};
  for (int sign : {1, -1}) {
    for (int j = 1; j <= kSteps; ++j) spells.push_back({sign * j * kStepN, kHoldS});
    spells.push_back({0.0, kRestS});
  }
  Record rec;
  double t0 = 0.0, prev = 0.0;
  std::vector<double> knot_t = {0.0}, knot_f = {0.0};
  for (const Spell& s : spells) {
    const double ramp = s.load == prev ? 0.0 : kRampS;
    knot_t.push_back(t0 + ramp);
    knot_f.push_back(s.load);
    knot_t.push_back(t0 + ramp + s.seconds);
    knot_f.push_back(s.load);
    rec.windows.push_back({t0 + ramp + kMarginS, t0 + ramp + s.seconds - kMarginS, s.load});
    t0 += ramp + s.seconds;
    prev = s.load;
  }
  const auto n = static_cast<Eigen::Index>(t0 * kFs);

  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int c = 0; c < 6; ++c) {
    rec.drift_offset[c] = 20.0 * uniform(rng);
    rec.drift_per_s[c] = 5.0 / 60.0 * uniform(rng);  // up to 5 N/min (003 sec. 1)
  }
  const double a = 3.0, b = -2.0, d = 1.5;  // common-mode offsets
  rec.w.resize(n, 6);
  std::size_t knot = 1;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / kFs;
    while (knot + 1 < knot_t.size() && t > knot_t[knot]) ++knot;
    const double u = knot_t[knot] > knot_t[knot - 1]
                         ? (t - knot_t[knot - 1]) / (knot_t[knot] - knot_t[knot - 1])
                         : 1.0;
    const double load =
        knot_f[knot - 1] + std::min(1.0, std::max(0.0, u)) * (knot_f[knot] - knot_f[knot - 1]);
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    f[static_cast<int>(axis)] = load;
    Eigen::Vector3d s = S * f;
    s[static_cast<int>(axis)] += quadratic * load * load;
    Eigen::Matrix<double, 1, 6> row;
    row << a + s[0], a - s[0], b - s[1], b + s[1], s[2] + d, s[2] - d;
    for (int c = 0; c < 6; ++c)
      row[c] += rec.drift_offset[c] + rec.drift_per_s[c] * t + sigma * normal(rng);
    rec.w.row(k) = row;
  }
  // The common-mode offsets are part of each channel's drift offset.
  rec.drift_offset += (Eigen::Matrix<double, 6, 1>() << a, a, b, b, d, -d).finished();
  return rec;
}

std::vector<StaticReduction> campaign(const Eigen::Matrix3d& S, double sigma,
                                      std::vector<Record>* records = nullptr) {
  std::vector<StaticReduction> out;
  std::uint64_t seed = 1;
  for (Axis axis : {Axis::kX, Axis::kY, Axis::kZ}) {
    const Record rec = make_record(axis, S, sigma, seed++);
    out.push_back(reduce_static_test(rec.w, kFs, axis, rec.windows));
    if (records) records->push_back(rec);
  }
  return out;
}

TEST(SifsCalibration, PairSignalsFollowEq31) {
  Washers w(1, 6);
  w << 5.0, 1.0, 2.0, 7.0, 3.0, 4.0;
  const Pairs p = pair_signals(w);
  // s_x = 0.5 (5 - 1), s_y = -0.5 (2 - 7), s_z = 0.5 (3 + 4): exact in binary.
  EXPECT_EQ(p(0, 0), 2.0);
  EXPECT_EQ(p(0, 1), 2.5);
  EXPECT_EQ(p(0, 2), 3.5);
  EXPECT_STREQ(to_string(Axis::kY), "y");
}

TEST(SifsCalibration, NoiseFreeCampaignIsExact) {
  const Eigen::Matrix3d C = truth_C();
  std::vector<Record> records;
  const std::vector<StaticReduction> tests = campaign(C.inverse(), 0.0, &records);
  for (std::size_t i = 0; i < tests.size(); ++i) {
    ASSERT_TRUE(tests[i].summary.ok());
    EXPECT_LT((tests[i].drift_per_s - records[i].drift_per_s).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((tests[i].drift_offset - records[i].drift_offset).cwiseAbs().maxCoeff(), 1e-9);
  }
  const CalibrationFit fit = fit_calibration(tests);
  ASSERT_TRUE(fit.summary.ok()) << fit.summary.message;
  EXPECT_LT((fit.C - C).cwiseAbs().maxCoeff(), kRoundingRel * C.cwiseAbs().maxCoeff());
  EXPECT_LT((fit.S * C - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), kRoundingRel);
  EXPECT_LT(fit.residual_rms_n, kRoundingRel * kSteps * kStepN);
  EXPECT_EQ(fit.windows, 3 * 17);  // 3 unloaded + 14 loaded per test
  EXPECT_EQ(fit.residuals_n.size(), 3u * 14u);
  // The condition number of S equals that of C.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(C);
  EXPECT_NEAR(fit.cond_S, svd.singularValues()[0] / svd.singularValues()[2], 1e-9 * fit.cond_S);
}

TEST(SifsCalibration, RecoversCalibrationAndDriftFromNoisyCampaign) {
  const Eigen::Matrix3d C = truth_C();
  std::vector<Record> records;
  const std::vector<StaticReduction> tests = campaign(C.inverse(), kSigmaN, &records);

  // Propagated noise. A window mean of a pair signal has standard deviation
  // sigma_s = sigma / sqrt(2) / sqrt(4 s x 1024 Hz) = 5.5e-4 N; the drift line of a channel,
  // fitted over ~2.9e4 unloaded samples spread over ~116 s, has a slope error of about
  // sigma / (sqrt(2.9e4) 45 s) = 6.5e-6 N/s. Bounds below are ~8 of those.
  constexpr double kSlopeTolNPerS = 5e-5;
  constexpr double kOffsetTolN = 5e-3;
  const double sigma_s = kSigmaN / std::sqrt(2.0) / std::sqrt((kHoldS - 2 * kMarginS) * kFs);
  double worst_slope = 0.0;
  for (std::size_t i = 0; i < tests.size(); ++i) {
    ASSERT_TRUE(tests[i].summary.ok());
    const double e = (tests[i].drift_per_s - records[i].drift_per_s).cwiseAbs().maxCoeff();
    EXPECT_LT(e, kSlopeTolNPerS) << "test " << i;
    EXPECT_LT((tests[i].drift_offset - records[i].drift_offset).cwiseAbs().maxCoeff(), kOffsetTolN);
    worst_slope = std::max(worst_slope, e);
  }

  const CalibrationFit fit = fit_calibration(tests);
  ASSERT_TRUE(fit.summary.ok()) << fit.summary.message;
  // C error: an error dS in S gives dC = -C dS C. dS ~ sigma_s / (RMS load sqrt(windows))
  // = 5.5e-4 / (180 N sqrt(17)) = 7e-7 per N; |C|^2 ~ 3e3 gives ~2e-3. Bound 1e-2 (in
  // N per washer N, against entries up to 54).
  constexpr double kCTol = 1e-2;
  const double c_err = (fit.C - C).cwiseAbs().maxCoeff();
  EXPECT_LT(c_err, kCTol);

  // Residuals: C times the noise of s_w, RMS ~ sigma_s |C|_F / sqrt(3) = 0.025 N; between half
  // and twice that (the fit absorbs 9 of 126 degrees of freedom; drift errors add a little).
  const double expected_rms = sigma_s * C.norm() / std::sqrt(3.0);
  EXPECT_GT(fit.residual_rms_n, 0.5 * expected_rms);
  EXPECT_LT(fit.residual_rms_n, 2.0 * expected_rms);
  // Largest residual: < 5 expected RMS, in % of the 311.5 N full load.
  EXPECT_LT(fit.residual_max_pct, 100.0 * 5.0 * expected_rms / (kSteps * kStepN));
  // Linearity of a linear sensor: the window-mean noise over the full-scale pair signal,
  // ~3 sigma_s / 10 N = 0.02 %; far below the washers' 1 %FSO (003 table 1).
  constexpr double kLinearPct = 0.05;
  for (int a = 0; a < 3; ++a) EXPECT_LT(fit.linearity_pct[a], kLinearPct) << "axis " << a;

  chatterlab::testing::record_and_print("C_max_abs_error", c_err);
  chatterlab::testing::record_and_print("C_max_rel_error", c_err / C.cwiseAbs().maxCoeff());
  chatterlab::testing::record_and_print("drift_slope_max_error_N_per_min", 60.0 * worst_slope);
  chatterlab::testing::record_and_print("residual_rms_N", fit.residual_rms_n);
  chatterlab::testing::record_and_print("residual_rms_expected_N", expected_rms);
  chatterlab::testing::record_and_print("residual_max_pct", fit.residual_max_pct);
  chatterlab::testing::record_and_print("linearity_max_pct", fit.linearity_pct.maxCoeff());
}

TEST(SifsCalibration, LinearityMeasuresAQuadraticWasher) {
  // s_x = S_xx f + kappa f^2 over the symmetric loads {0 x3, +-44.5 j, j = 1..7}: the f^2 term
  // is uncorrelated with f, so the line's slope is S_xx and its intercept kappa mean(f^2) =
  // kappa 44.5^2 280/17. Largest deviation at |f| = 7 steps: kappa 44.5^2 (49 - 280/17); full
  // scale at f = +7 steps (kappa > 0, S_xx > 0): S_xx 311.5 + kappa 311.5^2.
  const Eigen::Matrix3d S = truth_C().inverse();
  const double kappa = 2e-6;  // per N
  const Record rx = make_record(Axis::kX, S, 0.0, 5, kappa);
  const Record ry = make_record(Axis::kY, S, 0.0, 6);
  const Record rz = make_record(Axis::kZ, S, 0.0, 7);
  const std::vector<StaticReduction> tests = {reduce_static_test(rx.w, kFs, Axis::kX, rx.windows),
                                              reduce_static_test(ry.w, kFs, Axis::kY, ry.windows),
                                              reduce_static_test(rz.w, kFs, Axis::kZ, rz.windows)};
  const CalibrationFit fit = fit_calibration(tests);
  ASSERT_TRUE(fit.summary.ok());
  const double full = kSteps * kStepN;
  const double expected = 100.0 * kappa * kStepN * kStepN * (49.0 - 280.0 / 17.0) /
                          (S(0, 0) * full + kappa * full * full);
  EXPECT_NEAR(fit.linearity_pct[0], expected, kRoundingRel * 100.0);
  EXPECT_LT(fit.linearity_pct[1], kRoundingRel * 100.0);
  EXPECT_LT(fit.linearity_pct[2], kRoundingRel * 100.0);
  chatterlab::testing::record_and_print("quadratic_linearity_pct", fit.linearity_pct[0]);
}

TEST(SifsCalibration, TwoLoadedAxesFail) {
  const Eigen::Matrix3d S = truth_C().inverse();
  const Record rx = make_record(Axis::kX, S, kSigmaN, 1);
  const Record ry = make_record(Axis::kY, S, kSigmaN, 2);
  const CalibrationFit fit = fit_calibration({reduce_static_test(rx.w, kFs, Axis::kX, rx.windows),
                                              reduce_static_test(ry.w, kFs, Axis::kY, ry.windows)});
  EXPECT_TRUE(fit.summary.failed());
  EXPECT_EQ(fit.summary.message,
            "the loads span 2 independent axes (loaded: x y); the calibration needs loads along "
            "x, y and z");
  EXPECT_TRUE(std::isnan(fit.linearity_pct[2]));
}

TEST(SifsCalibration, InsensitiveAxisMakesSSingular) {
  // A ring whose Z pair does not respond: the third row of S is zero.
  Eigen::Matrix3d S = truth_C().inverse();
  S.row(2).setZero();
  const CalibrationFit fit = fit_calibration(campaign(S, 0.0));
  EXPECT_TRUE(fit.summary.failed());
  EXPECT_EQ(fit.summary.message.rfind("S is singular (2-norm condition number ", 0), 0u)
      << fit.summary.message;
}

TEST(SifsCalibration, FailedReductionIsRejected) {
  StaticReduction not_run;
  expect_input_error([&] { fit_calibration({not_run}); },
                     "tests[0]: the static reduction did not succeed (not run)");
}

TEST(SifsCalibration, WindowErrorsNameTheWindow) {
  const Record rec = make_record(Axis::kX, truth_C().inverse(), 0.0, 1);
  const double duration = static_cast<double>(rec.w.rows()) / kFs;  // 116 s
  ASSERT_EQ(duration, 116.0);
  auto with = [&](std::size_t i, LoadWindow w) {
    std::vector<LoadWindow> v = rec.windows;
    v[i] = w;
    return v;
  };
  auto reduce = [&](const std::vector<LoadWindow>& v) {
    return [&rec, v] { reduce_static_test(rec.w, kFs, Axis::kX, v); };
  };
  expect_input_error(reduce(with(2, {20.0, 120.0, 89.0})),
                     "loads[2]: window [20, 120] s ends after the record (116 s)");
  expect_input_error(reduce(with(2, {-1.0, 4.0, 89.0})),
                     "loads[2]: window [-1, 4] s starts before the record (0 s)");
  expect_input_error(reduce(with(3, {30.0, 30.0, 89.0})),
                     "loads[3]: window [30, 30] s does not end after its start");
  expect_input_error(reduce(with(3, {30.0, 30.0005, 89.0})),
                     "loads[3]: window [30, 30.0005] s holds fewer than 2 samples");
  expect_input_error(reduce(with(4, {5.0, 6.0, 89.0})),
                     "loads[4]: window [5, 6] s overlaps loads[0] (window [0.5, 9.5] s)");
  expect_input_error(reduce(with(1, {std::nan(""), 6.0, 89.0})),
                     "loads[1] = [nan, 6, 89]: must be finite");
  // Drop the unloaded window after the positive and after the negative steps and at the end.
  std::vector<LoadWindow> no_tail(rec.windows.begin(), rec.windows.end() - 1);
  expect_input_error(reduce(no_tail), "loads: no unloaded window after the last load");
  std::vector<LoadWindow> no_head(rec.windows.begin() + 1, rec.windows.end());
  expect_input_error(reduce(no_head), "loads: no unloaded window before the first load");
  expect_input_error(reduce({{1.0, 2.0, 0.0}, {3.0, 4.0, 0.0}}),
                     "loads: no loaded window (every load is 0)");
  expect_input_error(reduce({}), "loads: no window");
  expect_input_error([&] { reduce_static_test(rec.w, 0.0, Axis::kX, rec.windows); },
                     "sample_rate_hz = 0: must be finite and > 0");
  Washers bad = rec.w;
  bad(2048, 3) = std::nan("");
  expect_input_error([&] { reduce_static_test(bad, kFs, Axis::kX, rec.windows); },
                     "data row 2048 (t = 2 s, inside loads[0]): non-finite washer value");
}

}  // namespace
}  // namespace sifs
}  // namespace chatterlab
