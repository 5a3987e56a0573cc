// The grinding model of 002 (analysis/grinding/grinding_model.h): the analytic Jacobians of
// eqs 1-3, 8 and appendix A / eq. 11 against central finite differences (with the guards of the
// format's section 7), the wear constant and G-ratio of eq. 3, and the noise-free magnitudes of
// the spec notes on 002 section 5 ("expected magnitudes [derived]", tau = 1.5 s, Euler).
#include "analysis/grinding/grinding_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace grinding {
namespace {

using Mat4 = Eigen::Matrix<double, 4, 4>;

// Jacobian check: an analytic entry a and its central difference d (step h_c) agree when
//   |a - d| <= kJacobianRelTol max(|a|, |d|) + kRoundoffFactor eps |f_r| / h_c,
// the second term bounding the rounding of f_r (the output row) in (f(x+h) - f(x-h)) / 2h.
// Steps h_c = kStepRel |x_c| make the truncation error ~ kStepRel^2 relative (1e-8).
constexpr double kJacobianRelTol = 1e-6;  // spec notes 7.1 test 2
constexpr double kRoundoffFactor = 16.0;
constexpr double kStepRel = 1e-4;

// Central differences of f at X, column c stepped by kStepRel |X_c| (1e-8 for X_c = 0).
Mat4 central_difference(const std::function<Eigen::Vector4d(const ProcessState&)>& f,
                        const ProcessState& X, Eigen::Vector4d* steps) {
  Mat4 D;
  for (int c = 0; c < 4; ++c) {
    const double h = X[c] != 0.0 ? kStepRel * std::abs(X[c]) : 1e-8;
    (*steps)[c] = h;
    ProcessState Xp = X, Xm = X;
    Xp[c] += h;
    Xm[c] -= h;
    D.col(c) = (f(Xp) - f(Xm)) / (2.0 * h);
  }
  return D;
}

void expect_jacobian(const Mat4& analytic,
                     const std::function<Eigen::Vector4d(const ProcessState&)>& f,
                     const ProcessState& X, const char* what) {
  Eigen::Vector4d steps;
  const Mat4 fd = central_difference(f, X, &steps);
  const Eigen::Vector4d y = f(X);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      const double a = analytic(r, c), d = fd(r, c);
      const double bound = kJacobianRelTol * std::max(std::abs(a), std::abs(d)) +
                           kRoundoffFactor * 2.220446049250313e-16 * std::abs(y[r]) / steps[c];
      EXPECT_LE(std::abs(a - d), bound)
          << what << " (" << r << ", " << c << ") at X = " << X.transpose() << ": analytic " << a
          << ", finite difference " << d;
    }
  }
}

GrindingParameters table_ii() {
  GrindingParameters p;  // defaults: 002 table II in the format's units
  p.vw_m_s = 0.533;
  p.rm_um = 2.4;
  p.r0 = 1.0;
  return p;
}

struct Point {
  ProcessState X;
  double u;
  const char* what;
};

std::vector<Point> points() {
  return {
      {ProcessState(120.0, 0.02, 49.99, 3.3), 0.0254, "roughing"},
      {ProcessState(54.6, 3.2e-4, 49.9918, 3.6), 0.0, "end of spark-out"},
      {ProcessState(400.0, 0.0021, 49.95, 2.8), 0.002, "finishing, late cycle"},
      {ProcessState(30.0, 2e-6, 49.99, 3.0), 0.0, "x2 just above the 1e-6 h guard"},
      {ProcessState(30.0, 5e-7, 49.99, 3.0), 0.0254, "0 < x2 < 1e-6 (h guard)"},
      {ProcessState(30.0, -1e-4, 49.99, 3.0), 0.0, "x2 <= 0 (wear and h guards)"},
      {ProcessState(-5.0, 0.01, 49.99, 3.0), 0.0254, "x1 <= 0 (x1^delta guard)"},
  };
}

TEST(GrindingModel, ProcessJacobianMatchesCentralDifferences) {
  for (const GrindingParameters& p : {table_ii(), [] {
                                        GrindingParameters q = table_ii();
                                        q.delta = 0.8;
                                        return q;
                                      }()}) {
    for (const Point& pt : points()) {
      Mat4 J;
      process_derivative(pt.X, pt.u, p, &J);
      expect_jacobian(
          J, [&](const ProcessState& X) { return process_derivative(X, pt.u, p); }, pt.X, pt.what);
    }
  }
}

TEST(GrindingModel, EulerStepJacobianMatchesCentralDifferences) {
  const GrindingParameters p = table_ii();
  constexpr double kTf = 0.02;
  for (const Point& pt : points()) {
    Mat4 A, J;
    const ProcessState next = euler_step(pt.X, pt.u, kTf, p, &A);
    // 002 eq. 8: X+ = X + T_f F and A = I + T_f dF/dX.
    const ProcessState expected = pt.X + kTf * process_derivative(pt.X, pt.u, p, &J);
    EXPECT_EQ(next, expected) << pt.what;
    EXPECT_EQ(A, (Mat4::Identity() + kTf * J).eval()) << pt.what;
    expect_jacobian(
        A, [&](const ProcessState& X) { return euler_step(X, pt.u, kTf, p); }, pt.X, pt.what);
  }
}

TEST(GrindingModel, OutputJacobianMatchesCentralDifferences) {
  for (const GrindingParameters& p : {table_ii(), [] {
                                        GrindingParameters q = table_ii();
                                        q.delta = 0.8;
                                        return q;
                                      }()}) {
    for (const Point& pt : points()) {
      Mat4 H;
      outputs(pt.X, p, &H);
      expect_jacobian(
          H, [&](const ProcessState& X) { return outputs(X, p); }, pt.X, pt.what);
    }
  }
}

TEST(GrindingModel, GuardsZeroTheDerivatives) {
  const GrindingParameters p = table_ii();
  Mat4 J, H;
  // x2 <= 0: no wear (x2^(1+g) of max(x2, 0)), and dR_a/dx2 = 0 below 1e-6 mm/s.
  const ProcessState Xneg(30.0, -1e-4, 49.99, 3.0);
  const ProcessState F = process_derivative(Xneg, 0.0, p, &J);
  EXPECT_EQ(F[kDs], 0.0);
  EXPECT_EQ(J(kDs, kV), 0.0);
  const Outputs y = outputs(Xneg, p, &H);
  EXPECT_EQ(H(kRa, kV), 0.0);
  EXPECT_TRUE(std::isfinite(y[kRa]));
  // x1 <= 0: dP/dx1 = 0, and P uses s0 alone.
  const ProcessState Xx1(-5.0, 0.01, 49.99, 3.0);
  const Outputs y1 = outputs(Xx1, p, &H);
  EXPECT_EQ(H(kPower, kVw), 0.0);
  EXPECT_DOUBLE_EQ(y1[kPower], p.Ks_W_s_mm * p.s0 * 0.01);
}

TEST(GrindingModel, WearConstantAndGRatio) {
  const GrindingParameters p = table_ii();
  // Reference (002 eq. 3 with table II, v_s in m/s): k = 2 pi^0.9 70^1.9 37^-0.9 / (50 * 13)
  //   pi^0.9 = 2.80178, 70^1.9 = 3202.6, 37^-0.9 = 0.038775: k = 695.9 / 650 = 1.0712 (notes
  //   section 2.3: 1.0712).
  constexpr double kKReference = 1.0712;
  constexpr double kKTol = 1e-4;  // the reference's last digit
  EXPECT_NEAR(wear_constant(p), kKReference, kKTol);

  // The G-ratio at steady roughing v = u = 0.0254 mm/s, from the model: removed volume rate per
  // width Q'_w = x1' = pi d_w v over the wheel volume rate (pi d_s0 / 2) |x3'| (eq. 3 keeps d_s0).
  // Reference: the G-ratio law eq. 3 rests on, G = G1 (v_s / Q'_w)^g with Q'_w =
  // pi 70 0.0254 = 5.5857 mm^2/s: 13 (37 / 5.5857)^0.9 = 13 * 5.4827 = 71.28 (notes: "71").
  constexpr double kU = 0.0254;
  const ProcessState F = process_derivative(ProcessState(100.0, kU, 50.0, 3.0), kU, p);
  const double G = F[kVw] / (kPi * p.ds0_mm / 2.0 * -F[kDs]);
  const double G_law = p.G1 * std::pow(p.vs_m_s / (kPi * p.dw_mm * kU), p.g);
  constexpr double kGLawRelTol = 1e-12;  // the same law, rounding only
  EXPECT_NEAR(G, G_law, kGLawRelTol * G_law);
  constexpr double kGReference = 71.28;
  constexpr double kGTol = 0.01;
  EXPECT_NEAR(G, kGReference, kGTol);
  // Wheel wear rate during roughing (notes section 2.3: -9.98e-4 mm/s).
  EXPECT_NEAR(F[kDs], -9.98e-4, 0.005e-4);
}

// The noise-free series of 002 sec. V: ten identical cycles of 850 Euler steps (u = 0.0254 for
// j = 0..474, 0.002 for 475..664, 0 for 665..849), x2 = 0 at each cycle start, x1, x3 carried.
struct CycleMagnitudes {
  double dVw, dDw, dds_um, peak_P_kW, v_end, Ra_end, dRa_dR0_end, r_end;
};

std::vector<CycleMagnitudes> noise_free_series(const GrindingParameters& p, double T_f, double R0) {
  std::vector<CycleMagnitudes> out;
  ProcessState X(0.0, 0.0, p.ds0_mm, R0);
  for (int i = 1; i <= 10; ++i) {
    X[kV] = 0.0;  // 002 eq. 12 and the new-cycle rule: v restarts from 0
    const ProcessState X0 = X;
    const Outputs y0 = outputs(X0, p);
    double peak = 0.0;
    for (int j = 0; j <= 850; ++j) {
      peak = std::max(peak, outputs(X, p)[kPower]);
      if (j == 850) break;
      const double u = j < 475 ? 0.0254 : (j < 665 ? 0.002 : 0.0);
      X = euler_step(X, u, T_f, p);
    }
    Mat4 H;
    const Outputs y = outputs(X, p, &H);
    out.push_back({X[kVw] - X0[kVw], y[kDw] - y0[kDw], (X0[kDs] - X[kDs]) * 1e3, peak / 1e3, X[kV],
                   y[kRa], H(kRa, kR0), roundness_um(X, p)});
  }
  return out;
}

TEST(GrindingModel, NoiseFreeSeriesReproducesTheDerivedMagnitudes) {
  GrindingParameters p = table_ii();
  p.tau_s = 1.5;
  const std::vector<CycleMagnitudes> m = noise_free_series(p, 0.02, 3.6);
  // Reference: the notes' "expected magnitudes [derived]" (002 notes section 5), recomputed
  // independently (a short script of the same Euler recursion) as dV'_w = 54.6307 mm^2,
  // dD_w = 0.49684 mm, dd_s = 8.2258 um per cycle, peak P 3209.13 W (cycle 1) and 5582.90 W
  // (cycle 10), v(i, n_i) = 3.1911e-4 mm/s, R_a(i, n_i) = 0.889943 / 0.333856 um, dR_a/dR0 =
  // 0.237964 / 0.0462102, r = 2.5317 um: the notes agree to the digits they state. Each check is
  // against the notes' value with half a unit of its last digit.
  for (int i = 0; i < 10; ++i) {
    SCOPED_TRACE(i + 1);
    EXPECT_NEAR(m[i].dVw, 54.6, 0.05);
    EXPECT_NEAR(m[i].dDw, 0.497, 0.0005);
    EXPECT_NEAR(m[i].dds_um, 8.2, 0.05);
    EXPECT_NEAR(m[i].v_end, 3.2e-4, 0.05e-4);
    EXPECT_NEAR(m[i].r_end, 2.53, 0.005);
  }
  double total_wear_um = 0.0;
  for (const CycleMagnitudes& c : m) total_wear_um += c.dds_um;
  EXPECT_NEAR(total_wear_um, 82.0, 0.5);  // "about 82 um over 10 cycles"
  EXPECT_NEAR(m[0].peak_P_kW, 3.21, 0.005);
  EXPECT_NEAR(m[9].peak_P_kW, 5.58, 0.005);
  EXPECT_NEAR(m[0].Ra_end, 0.89, 0.005);
  EXPECT_NEAR(m[9].Ra_end, 0.33, 0.005);
  EXPECT_NEAR(m[0].dRa_dR0_end, 0.24, 0.005);
  EXPECT_NEAR(m[9].dRa_dR0_end, 0.046, 0.0005);
  // The recomputation's own digits (an independent script of the same recursion, double
  // precision), relative kRecomputedRelTol: tighter than the notes' rounding.
  constexpr double kRecomputedRelTol = 1e-4;
  const auto near = [&](double value, double reference, const char* what) {
    EXPECT_NEAR(value, reference, kRecomputedRelTol * std::abs(reference)) << what;
  };
  near(m[0].dVw, 54.6307, "dV'_w");
  near(m[0].dDw, 0.49684, "dD_w");
  near(m[0].dds_um, 8.2258, "dd_s");
  near(m[0].peak_P_kW, 3.20913, "peak P, cycle 1");
  near(m[9].peak_P_kW, 5.58290, "peak P, cycle 10");
  near(m[0].v_end, 3.1911e-4, "v(i, n_i)");
  near(m[0].Ra_end, 0.889943, "R_a, cycle 1");
  near(m[9].Ra_end, 0.333856, "R_a, cycle 10");
  near(m[0].dRa_dR0_end, 0.237964, "dR_a/dR0, cycle 1");
  near(m[9].dRa_dR0_end, 0.0462102, "dR_a/dR0, cycle 10");
  near(m[0].r_end, 2.5317, "r");
  // The cycles are identical in removal and wear (eq. 3 keeps d_s0; nothing depends on x1 or x3).
  constexpr double kIdenticalCycleTol = 1e-9;  // relative, rounding of the accumulated x1, x3
  for (int i = 1; i < 10; ++i) {
    EXPECT_NEAR(m[i].dVw, m[0].dVw, kIdenticalCycleTol * m[0].dVw);
    EXPECT_NEAR(m[i].dds_um, m[0].dds_um, 1e-6);  // um; x3 ~ 50 mm rounds at ~1e-11 mm a step
  }
  // R_a at the end of cycle 1 for tau = 1 and 2 s (notes A2: 0.64 and 1.08 um).
  p.tau_s = 1.0;
  EXPECT_NEAR(noise_free_series(p, 0.02, 3.6)[0].Ra_end, 0.64, 0.005);
  p.tau_s = 2.0;
  EXPECT_NEAR(noise_free_series(p, 0.02, 3.6)[0].Ra_end, 1.08, 0.005);
}

TEST(GrindingModel, RemovalIsTheCommandedIntegralWhenTauEqualsTheSamplePeriod) {
  // With tau = T_f, eq. 8 gives x2(j+1) = u(j) exactly, so dV'_w = pi d_w T_f sum_j u(j) =
  // pi 70 0.02 (475 * 0.0254 + 190 * 0.002) = 54.7357 mm^2 (notes 7.1 test 1: the tau -> 0
  // limit pi 70 (0.0254 * 9.5 + 0.002 * 3.8) = 54.7 mm^2).
  GrindingParameters p = table_ii();
  p.tau_s = 0.02;
  const double reference = kPi * 70.0 * 0.02 * (475 * 0.0254 + 190 * 0.002);
  constexpr double kRelTol = 1e-12;
  EXPECT_NEAR(noise_free_series(p, 0.02, 3.6)[0].dVw, reference, kRelTol * reference);
  EXPECT_NEAR(reference, 54.7, 0.05);
}

}  // namespace
}  // namespace grinding
}  // namespace chatterlab
