// Joint identification (analysis/estimate/joint_identification.h) on synthetic records written
// by the cut-record generator and read through the cut chain (tests/support/synthetic_cuts.h),
// whose truth is the simulator's parameters. The generator and the fit share the simulator, so
// the model is exact and the 95 % intervals should contain the truth in about 95 % of records.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "analysis/common/constants.h"
#include "analysis/estimate/joint_identification.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab {
namespace estimate {
namespace {

double circular_difference_deg(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d > 180.0) d -= 360.0;
  if (d < -180.0) d += 360.0;
  return d;
}

struct Truth {
  ModalParameters modal;
  std::vector<CuttingCoefficients> coefficients;
  double offset_deg = 0.0;
};

// A record of 60 revolutions at `depth_m` (the sync tests' record, testing::sync_test_cut) with
// the truth's values and offset.
sync::CutRecordSpec record(const Truth& t, double depth_m, std::uint64_t seed) {
  sync::CutRecordSpec s = testing::sync_test_cut();
  s.cut.modal_x = t.modal;
  s.cut.coefficients = t.coefficients;
  s.cut.depth = milling::DepthProfile::constant(depth_m, 60);
  s.offset_angle_deg = t.offset_deg;
  s.seed = seed;
  return s;
}

// The truth's steady revolution at depth_m: whether it settles (the last two of 60 differ by
// < 0.1 % RMS) and its RMS about the mean over x and y, m.
struct Steady {
  bool settles = false;
  double ac_rms_m = 0.0;
};
Steady steady(const Truth& t, double depth_m) {
  milling::SimulationOptions o = testing::cut_options(t.modal, t.coefficients);
  o.depth = milling::DepthProfile::constant(depth_m, 60);
  milling::RecordingRequest request;
  request.full_revolutions = {58, 59};
  const milling::SimulationResult sim = milling::simulate(o, request);
  Steady s;
  if (!sim.summary.ok()) return s;
  const milling::RevolutionRecord& a = sim.records[0];
  const milling::RevolutionRecord& b = sim.records[1];
  s.settles = (b.x_m - a.x_m).squaredNorm() + (b.y_m - a.y_m).squaredNorm() <
              1e-6 * (b.x_m.squaredNorm() + b.y_m.squaredNorm());
  s.ac_rms_m = std::sqrt(((b.x_m.array() - b.x_m.mean()).square().sum() +
                          (b.y_m.array() - b.y_m.mean()).square().sum()) /
                         (2.0 * static_cast<double>(b.x_m.size())));
  return s;
}

// The start the sequence would give: every value off by a few per cent, the offset off by a
// degree or two, the damping off by up to 30 % (issue 13), k exact; drawn again until its cut
// at depth_m is stable (the sequence's values come from a stable cut).
struct Start {
  ModalParameters modal;
  std::vector<CuttingCoefficients> coefficients;
  double offset_deg = 0.0;
};
Start perturbed(const Truth& t, std::mt19937_64& rng, double depth_m) {
  std::uniform_real_distribution<double> few(-0.05, 0.05), damping(-0.3, 0.3), angle(-1.6, 1.6);
  for (;;) {
    Start s;
    s.modal = {t.modal.m_kg * (1.0 + few(rng)), t.modal.c_kg_s * (1.0 + damping(rng)),
               t.modal.k_N_m};
    for (const CuttingCoefficients& k : t.coefficients) {
      s.coefficients.push_back({k.Kt_N_m2 * (1.0 + few(rng)), k.Kr_N_m2 * (1.0 + few(rng))});
    }
    s.offset_deg = t.offset_deg + angle(rng);
    if (steady({s.modal, s.coefficients, s.offset_deg}, depth_m).settles) return s;
  }
}

JointIdentificationResult fit(const sync::CutRecordSpec& spec, const Start& start) {
  const testing::MeasuredRevolution measured = testing::measured_revolution(spec, 20);
  milling::SimulationOptions model = spec.cut;
  return identify_joint(measured.mean, model, measured.depth_m, start.offset_deg, start.modal,
                        start.coefficients);
}

void print(const char* name, const JointIdentificationResult& r) {
  std::printf(
      "%s: %s, %d iterations, %d simulations, %.3f s; offset %.4f +- %.4f deg; fn %.3f +- %.3f "
      "Hz; zeta %.5f +- %.5f; m %.5g +- %.2g; c %.4g +- %.2g; rms %.3g m (start %.3g), s %.3g, "
      "condition %.2g, lag-1 correlation %.2f, variance inflation %.2f\n",
      name, r.converged ? "converged" : "not converged", r.iterations, r.simulations, r.runtime_s,
      r.offset_deg.value, r.offset_deg.hi - r.offset_deg.value, r.fn_hz.value,
      r.fn_hz.hi - r.fn_hz.value, r.zeta.value, r.zeta.hi - r.zeta.value, r.m_kg.value,
      r.m_kg.hi - r.m_kg.value, r.c_kg_s.value, r.c_kg_s.hi - r.c_kg_s.value, r.rms_error_m,
      r.start_rms_error_m, r.residual_sd_m, r.condition, r.residual_correlation_lag1,
      r.variance_inflation);
  for (std::size_t p = 0; p < r.Kt_N_m2.size(); ++p) {
    std::printf("  tooth %zu: Kt %.5g [%.5g, %.5g], Kr %.5g [%.5g, %.5g]\n", p + 1,
                r.Kt_N_m2[p].value, r.Kt_N_m2[p].lo, r.Kt_N_m2[p].hi, r.Kr_N_m2[p].value,
                r.Kr_N_m2[p].lo, r.Kr_N_m2[p].hi);
  }
}

Truth table52(double offset_deg) {
  return {testing::table52_modal(), testing::table52_coefficients(), offset_deg};
}

// The offset of the truth (a circle) in the interval (a line around the start).
bool offset_covered(const IntervalValue& v, double truth_deg) {
  const double d = circular_difference_deg(truth_deg, v.value);
  return std::abs(d) <= v.hi - v.value;
}

// 000 table 5.2's cut (unequal teeth), started 1.6 deg, 5 % and 30 % (damping) off: the fit
// lands on the truth, and its intervals, of a few tenths of a per cent, contain it.
TEST(JointIdentification, RecoversTable52FromAnOffStart) {
  const Truth t = table52(147.3);
  std::mt19937_64 rng(7);
  const Start start = perturbed(t, rng, 1e-3);
  const JointIdentificationResult r = fit(record(t, 1e-3, 11), start);
  print("table 5.2", r);
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.parameters, 7);
  EXPECT_TRUE(r.not_identifiable().empty());
  // Tolerances: the goals of issue 13 (offset 0.5 deg, damping 10 %) and the EKFs' 2 %.
  EXPECT_LT(std::abs(circular_difference_deg(r.offset_deg.value, t.offset_deg)), 0.5);
  EXPECT_NEAR(r.c_kg_s.value, t.modal.c_kg_s, 0.10 * t.modal.c_kg_s);
  EXPECT_NEAR(r.m_kg.value, t.modal.m_kg, 0.02 * t.modal.m_kg);
  EXPECT_EQ(r.k_N_m, t.modal.k_N_m);
  for (std::size_t p = 0; p < 2; ++p) {
    EXPECT_NEAR(r.Kt_N_m2[p].value, t.coefficients[p].Kt_N_m2, 0.02 * t.coefficients[p].Kt_N_m2);
    EXPECT_NEAR(r.Kr_N_m2[p].value, t.coefficients[p].Kr_N_m2, 0.02 * t.coefficients[p].Kr_N_m2);
  }
  // The residual is the noise of the mean revolution: 5e-7 m at the tip over 20 revolutions plus
  // the air contour's over about 10, at most sigma sqrt(1/20 + 1/10) = 1.9e-7 m at a sample; the
  // linear interpolations at fractional sample positions (mean revolution, contour) average
  // neighbouring samples, at most halving the variance of the 20-revolution mean, and correlate
  // neighbouring phase points, which the intervals account for (variance inflation > 1).
  EXPECT_LE(r.residual_sd_m, 5e-7 * std::sqrt(1.0 / 20 + 1.0 / 10));
  EXPECT_GE(r.residual_sd_m, 5e-7 * std::sqrt(0.5 / 20));
  EXPECT_GT(r.residual_correlation_lag1, 0.2);
  EXPECT_GT(r.variance_inflation, 1.5);
  EXPECT_LT(r.rms_error_m, 0.5 * r.start_rms_error_m);
}

// The scale anchor off by 4 % (the hammer test at rest against the spinning tool, 000 sec. 5.1):
// the scale-free values and the offset do not move; m, c and every K carry the factor.
TEST(JointIdentification, ScaleFreeValuesDoNotDependOnTheAnchor) {
  const Truth t = table52(212.5);
  std::mt19937_64 rng(8);
  const Start exact = perturbed(t, rng, 1e-3);
  Start off = exact;
  off.modal.m_kg *= 1.04;
  off.modal.c_kg_s *= 1.04;
  off.modal.k_N_m *= 1.04;
  for (CuttingCoefficients& k : off.coefficients) {
    k.Kt_N_m2 *= 1.04;
    k.Kr_N_m2 *= 1.04;
  }
  const sync::CutRecordSpec spec = record(t, 1e-3, 12);
  const JointIdentificationResult a = fit(spec, exact);
  const JointIdentificationResult b = fit(spec, off);
  ASSERT_TRUE(a.summary.ok()) << a.summary.message;
  ASSERT_TRUE(b.summary.ok()) << b.summary.message;
  // The same optimum in theta: equal to the solver's tolerance (1e-10 relative in theta,
  // bounded here by 1e-6 of the value).
  EXPECT_NEAR(b.fn_hz.value, a.fn_hz.value, 1e-6 * a.fn_hz.value);
  EXPECT_NEAR(b.zeta.value, a.zeta.value, 1e-6 * a.zeta.value);
  EXPECT_NEAR(b.offset_deg.value, a.offset_deg.value, 1e-4);
  for (std::size_t p = 0; p < 2; ++p) {
    EXPECT_NEAR(b.Kt_over_k_per_m[p].value, a.Kt_over_k_per_m[p].value,
                1e-6 * a.Kt_over_k_per_m[p].value);
    EXPECT_NEAR(b.Kt_N_m2[p].value, 1.04 * a.Kt_N_m2[p].value, 1e-6 * a.Kt_N_m2[p].value);
  }
  EXPECT_NEAR(b.m_kg.value, 1.04 * a.m_kg.value, 1e-6 * a.m_kg.value);
  EXPECT_NEAR(b.c_kg_s.value, 1.04 * a.c_kg_s.value, 1e-6 * a.c_kg_s.value);
  EXPECT_EQ(b.k_N_m, off.modal.k_N_m);
}

// A start that chatters (the cut far above its limit) cannot be fitted: the fit says so.
TEST(JointIdentification, SaysWhyWhenTheStartIsNotSteady) {
  const Truth t = table52(147.3);
  Start s{t.modal, t.coefficients, t.offset_deg};
  const testing::MeasuredRevolution measured = testing::measured_revolution(record(t, 1e-3, 3));
  milling::SimulationOptions model = testing::table52_incline1();
  const JointIdentificationResult r =
      identify_joint(measured.mean, model, 8e-3, s.offset_deg, s.modal, s.coefficients);
  EXPECT_TRUE(r.summary.failed());
  EXPECT_NE(r.summary.message.find("not steady"), std::string::npos) << r.summary.message;
  // Bad input names what is wrong.
  auto message = [&](const Start& start, const sync::RevolutionMean& mean,
                     const JointIdentificationOptions& o) {
    try {
      identify_joint(mean, model, 1e-3, start.offset_deg, start.modal, start.coefficients, o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Start bad = s;
  bad.modal.c_kg_s = -1.0;
  EXPECT_EQ(message(bad, measured.mean, {}),
            "joint identification: start c_kg_s = -1: must be finite and > 0");
  JointIdentificationOptions o;
  o.max_iterations = 0;
  EXPECT_EQ(message(s, measured.mean, o), "joint identification: max_iterations = 0: must be >= 1");
  bad = s;
  bad.coefficients.pop_back();
  EXPECT_EQ(message(bad, measured.mean, {}),
            "joint identification: 1 coefficient pairs for 2 teeth");
  sync::RevolutionMean few = measured.mean;  // 4 phase points, fewer than 8
  few.phase_rad.conservativeResize(4);
  few.x_m.conservativeResize(4);
  few.y_m.conservativeResize(4);
  EXPECT_EQ(message(s, few, {}),
            "joint identification: the measured revolution needs >= 8 finite phase points on x "
            "and y");
}

// Random campaigns: teeth ratio Kt2 / Kt1 log-uniform in `ratio` ([1.02, 27]: nearly alike to
// 000's 27x), zeta uniform in `zeta` ([0.01, 0.065]: light damping to 000's 0.063), fn and k
// within 10 % of 000's, offset uniform, Kr / Kt in [0.4, 0.9]. The depth is 1 mm, or less until
// twice the depth is stable. A lab identifies from a cut it can see: a draw whose steady
// revolution varies by less than 1 um RMS (5 times the noise of the 20-revolution mean; light
// damping with strong coefficients, whose stable depths are a few um) is drawn again.
struct Range {
  double lo = 0.0, hi = 0.0;
};
Truth random_truth(std::mt19937_64& rng, Range ratio, Range zeta, double* depth_m) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (;;) {
    const double r = std::exp(std::log(ratio.lo) + u(rng) * std::log(ratio.hi / ratio.lo));
    const double z = zeta.lo + (zeta.hi - zeta.lo) * u(rng);
    const double kt_mean = 6e8 * std::exp(u(rng) * std::log(5.0));
    Truth t;
    const double k = 9.84e5 * (0.9 + 0.2 * u(rng));
    const double fn = 890.0 * (0.9 + 0.2 * u(rng));
    const double m = k / std::pow(kTwoPi * fn, 2);
    t.modal = {m, 2.0 * z * std::sqrt(k * m), k};
    const double kt1 = 2.0 * kt_mean / (1.0 + r);
    for (double kt : {kt1, r * kt1}) t.coefficients.push_back({kt, kt * (0.4 + 0.5 * u(rng))});
    t.offset_deg = 360.0 * u(rng);
    double depth = 1e-3;
    while (depth > 1e-6 && !steady(t, 2.0 * depth).settles) depth /= 1.5;
    if (steady(t, depth).ac_rms_m < 1e-6) continue;
    *depth_m = depth;
    return t;
  }
}

// Issue 13's accuracy goals: the offset within 0.5 deg, the damping within 10 %.
constexpr double kOffsetGoalDeg = 0.5;
constexpr double kDampingGoal = 0.10;

struct GroupResult {
  int cases = 0;
  int offset = 0, fn = 0, zeta = 0, m = 0, c = 0, kt = 0, kr = 0;  // covered; Kt, Kr: both teeth
  int honest = 0;  // cuts meeting both goals, or whose intervals contain the truth where not
  double worst_offset_deg = 0.0, worst_c = 0.0;
  int intervals() const { return 9 * cases; }
  double pooled() const {
    return static_cast<double>(offset + fn + zeta + m + c + kt + kr) / intervals();
  }
};

GroupResult run_group(const char* name, int cuts, Range ratio, Range zeta, std::uint64_t seed) {
  GroupResult n;
  std::mt19937_64 rng(seed);
  for (int i = 0; i < cuts; ++i) {
    double depth_m = 0.0;
    const Truth t = random_truth(rng, ratio, zeta, &depth_m);
    const Start start = perturbed(t, rng, depth_m);
    const JointIdentificationResult r = fit(record(t, depth_m, 1000 * seed + i), start);
    EXPECT_TRUE(r.summary.ok()) << name << " cut " << i << ": " << r.summary.message;
    if (!r.summary.ok()) continue;
    ++n.cases;
    const bool offset_in = offset_covered(r.offset_deg, t.offset_deg);
    const bool c_in = r.c_kg_s.contains(t.modal.c_kg_s);
    n.offset += offset_in;
    n.fn += r.fn_hz.contains(natural_frequency_hz(t.modal));
    n.zeta += r.zeta.contains(damping_ratio(t.modal));
    n.m += r.m_kg.contains(t.modal.m_kg);
    n.c += c_in;
    for (std::size_t p = 0; p < 2; ++p) {
      n.kt += r.Kt_N_m2[p].contains(t.coefficients[p].Kt_N_m2);
      n.kr += r.Kr_N_m2[p].contains(t.coefficients[p].Kr_N_m2);
    }
    const double offset_error = std::abs(circular_difference_deg(r.offset_deg.value, t.offset_deg));
    const double c_error = std::abs(r.c_kg_s.value / t.modal.c_kg_s - 1.0);
    n.honest += (offset_error < kOffsetGoalDeg || offset_in) && (c_error < kDampingGoal || c_in);
    n.worst_offset_deg = std::max(n.worst_offset_deg, offset_error);
    n.worst_c = std::max(n.worst_c, c_error);
  }
  std::printf(
      "%s, %d cuts: covered offset %d, fn %d, zeta %d, m %d, c %d, Kt %d/%d, Kr %d/%d, pooled "
      "%.3f; worst offset error %.3f deg, worst damping error %.1f %%; goals met or truth "
      "inside the interval in %d\n",
      name, n.cases, n.offset, n.fn, n.zeta, n.m, n.c, n.kt, 2 * n.cases, n.kr, 2 * n.cases,
      n.pooled(), n.worst_offset_deg, 100.0 * n.worst_c, n.honest);
  return n;
}

// Issue 13: the truth inside the 95 % interval in 90-99 % of at least 50 seeded cuts of
// different teeth ratios, damping and offsets. Asserted pooled over the nine intervals of each
// cut (450 intervals: binomial sd 1 % at 95 %; 50 intervals of one value alone would put 100 %
// outside 90-99 % one time in 13); every value's own coverage is printed, and 300 cuts are in
// docs/identification.md.
TEST(JointIdentification, IntervalCoverageOver50Seeds) {
  const GroupResult n = run_group("random", 50, {1.02, 27.0}, {0.01, 0.065}, 20261203);
  EXPECT_EQ(n.cases, 50);
  EXPECT_GE(n.pooled(), 0.90);
  EXPECT_LE(n.pooled(), 0.99);
  // Issue 13's goals, or an interval that contains the truth where the cut cannot meet them: in
  // at least 48 of 50 (a 95 % interval misses one cut in 20).
  EXPECT_GE(n.honest, 48);
}

// The two kinds of campaign where 000's sequence does not settle (issue 13): nearly alike teeth
// (Kt2 / Kt1 in [1.02, 1.1]) and light damping (zeta 0.01-0.02), 20 cuts each.
TEST(JointIdentification, NearlyAlikeTeethAndLightDampingOver20Seeds) {
  const GroupResult alike = run_group("nearly alike teeth", 20, {1.02, 1.1}, {0.01, 0.065}, 77);
  const GroupResult light = run_group("light damping", 20, {1.02, 27.0}, {0.01, 0.02}, 78);
  // A cut's nine intervals move together (one noise realisation), so 20 cuts measure the
  // coverage to about +-5 %: at least 80 % pooled (measured 96.1 % and 86.7 % here; 95.0 % and
  // 94.3 % over 150 cuts each, docs/identification.md), and the goals met or the truth inside the
  // interval in 18 of 20 (measured 20 and 20).
  for (const GroupResult* g : {&alike, &light}) {
    EXPECT_EQ(g->cases, 20);
    EXPECT_GE(g->pooled(), 0.80);
    EXPECT_GE(g->honest, 18);
  }
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab

namespace chatterlab {
namespace estimate {
namespace {

// Parametric bootstrap (issue 13): records simulated at one cut's fitted values with fresh noise
// and refitted; the spread of the refits against the Jacobian's standard errors of the first fit.
TEST(JointIdentification, StandardErrorsMatchABootstrapOver40Seeds) {
  const Truth t = table52(147.3);
  std::mt19937_64 rng(5);
  const JointIdentificationResult first = fit(record(t, 1e-3, 100), perturbed(t, rng, 1e-3));
  ASSERT_TRUE(first.summary.ok()) << first.summary.message;
  Truth fitted{first.modal(), first.coefficients(), first.offset_deg.value};
  const int B = 40;
  std::vector<double> offset, fn, zeta, kt1, kt2, kr2;
  for (int b = 0; b < B; ++b) {
    const Start start{fitted.modal, fitted.coefficients, fitted.offset_deg};
    const JointIdentificationResult r = fit(record(fitted, 1e-3, 200 + b), start);
    ASSERT_TRUE(r.summary.ok()) << r.summary.message;
    offset.push_back(r.offset_deg.value);
    fn.push_back(r.fn_hz.value);
    zeta.push_back(r.zeta.value);
    kt1.push_back(r.Kt_N_m2[0].value);
    kt2.push_back(r.Kt_N_m2[1].value);
    kr2.push_back(r.Kr_N_m2[1].value);
  }
  auto sd = [](const std::vector<double>& v) {
    double mean = 0.0, ss = 0.0;
    for (double x : v) mean += x / v.size();
    for (double x : v) ss += (x - mean) * (x - mean);
    return std::sqrt(ss / (v.size() - 1));
  };
  const double ratios[] = {sd(offset) / first.offset_deg.sd, sd(fn) / first.fn_hz.sd,
                           sd(zeta) / first.zeta.sd,         sd(kt1) / first.Kt_N_m2[0].sd,
                           sd(kt2) / first.Kt_N_m2[1].sd,    sd(kr2) / first.Kr_N_m2[1].sd};
  std::printf(
      "bootstrap spread / standard error over %d refits: offset %.2f fn %.2f zeta %.2f "
      "Kt1 %.2f Kt2 %.2f Kr2 %.2f\n",
      B, ratios[0], ratios[1], ratios[2], ratios[3], ratios[4], ratios[5]);
  // The sample sd of 40 refits lies within 0.78-1.22 of the true sd with 95 % probability
  // (chi-square, 39 dof); 0.7-1.3 for six ratios at once. With Bartlett-weighted correlations
  // they were 1.03-1.14 over 150 refits, and 1.45-1.60 with white-noise intervals.
  for (double q : ratios) {
    EXPECT_GT(q, 0.7);
    EXPECT_LT(q, 1.3);
  }
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
