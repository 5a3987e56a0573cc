// Augmented Kalman filter force reconstruction (004 eqs 2.6-2.11, EXPERIMENT_FORMAT.md sec. 4
// `akf`).
#include "analysis/forcerec/akf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>
#include <vector>

#include "analysis/kalman/kalman_filter.h"

namespace chatterlab {
namespace forcerec {
namespace {

using Eigen::Index;
using Eigen::VectorXd;
using cd = std::complex<double>;

constexpr double kFs = 10240.0;       // 004's simulation-like rate (notes/004.md sec. 1)
constexpr double kToothHz = 511.5;    // 15345 rpm, 2 teeth (notes/004.md sec. 7)
constexpr double kNoiseVarX = 0.007;  // 004's R for X (N^2)

struct PoleZero {
  double fn_hz, zeta;
};

cd root(const PoleZero& r) {
  const double w = 2.0 * M_PI * r.fn_hz;
  return {-r.zeta * w, w * std::sqrt(1.0 - r.zeta * r.zeta)};
}

// H(s) = g prod(s - z) / prod(s - p) with complex pole and zero pairs and optional real zeros,
// g such that H(0) = 1, realized as a sum of second-order sections in real modal form: per pair
// p = s + j w with residue r, states [Re xi, Im xi] of xi' = p xi + F, output 2 Re(r xi).
// Relative degree one (one zero fewer than poles) and minimum phase when every zero is.
ContinuousModel modal_model(const std::vector<PoleZero>& poles, const std::vector<PoleZero>& zeros,
                            const std::vector<double>& real_zeros_rad_s) {
  std::vector<cd> p, z;
  for (const PoleZero& r : poles) {
    p.push_back(root(r));
    p.push_back(std::conj(root(r)));
  }
  for (const PoleZero& r : zeros) {
    z.push_back(root(r));
    z.push_back(std::conj(root(r)));
  }
  for (double r : real_zeros_rad_s) z.emplace_back(r, 0.0);
  cd h0 = 1.0;  // prod(-z) / prod(-p)
  for (const cd& zi : z) h0 *= -zi;
  for (const cd& pi : p) h0 /= -pi;
  const double g = 1.0 / h0.real();
  const Index n = static_cast<Index>(p.size());
  ContinuousModel m;
  m.A = Eigen::MatrixXd::Zero(n, n);
  m.B = VectorXd::Zero(n);
  m.C = Eigen::RowVectorXd::Zero(n);
  for (Index i = 0; i < n; i += 2) {
    const cd pi = p[static_cast<std::size_t>(i)];
    cd r = g;
    for (const cd& zi : z) r *= pi - zi;
    for (Index l = 0; l < n; ++l) {
      if (l != i) r /= pi - p[static_cast<std::size_t>(l)];
    }
    m.A.block<2, 2>(i, i) << pi.real(), -pi.imag(), pi.imag(), pi.real();
    m.B[i] = 1.0;
    m.C[i] = 2.0 * r.real();
    m.C[i + 1] = -2.0 * r.imag();
  }
  return m;
}

// 004's X axis (notes/004.md sec. 2, roots of Table 3.1's Hxx): poles 1411.8 Hz (0.0214),
// 1458.8 Hz (0.163), 1518.6 Hz (0.0221); zeros 1421.0 Hz (0.041), 1570.9 Hz (0.050) and
// -21734 rad/s; DC gain set to 1.
ContinuousModel x_axis_model() {
  return modal_model({{1411.8, 0.0214}, {1458.8, 0.163}, {1518.6, 0.0221}},
                     {{1421.0, 0.041}, {1570.9, 0.050}}, {-21734.0});
}

// Milling-like held force: mean 30 N and the first five tooth harmonics (20, 8, 5, 3, 2 N; the
// smooth truth of notes/004.md sec. 9.3a) with seeded random phases, at the interval centres.
VectorXd milling_force(Index samples, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * M_PI);
  const double amp[5] = {20.0, 8.0, 5.0, 3.0, 2.0};
  double ph[5];
  for (double& v : ph) v = phase(rng);
  VectorXd F(samples);
  for (Index k = 0; k < samples; ++k) {
    const double t = (static_cast<double>(k) + 0.5) / kFs;
    double v = 30.0;
    for (int h = 0; h < 5; ++h) v += amp[h] * std::cos(2.0 * M_PI * (h + 1) * kToothHz * t + ph[h]);
    F[k] = v;
  }
  return F;
}

VectorXd with_noise(const VectorXd& y, double variance, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd(0.0, std::sqrt(variance));
  VectorXd out = y;
  for (Index k = 0; k < out.size(); ++k) out[k] += nd(rng);
  return out;
}

// The format's evaluation window: 0.05 s <= k / fs < T - 0.01 s.
struct Window {
  Index begin, end;
};
Window evaluation_window(Index samples) {
  return {static_cast<Index>(std::ceil(0.05 * kFs)),
          static_cast<Index>(std::ceil(static_cast<double>(samples) - 0.01 * kFs))};
}

double nrmse_pct(const VectorXd& est, const VectorXd& truth, Window w) {
  const Index n = w.end - w.begin;
  const VectorXd d = est.segment(w.begin, n) - truth.segment(w.begin, n);
  return 100.0 * std::sqrt(d.squaredNorm() / truth.segment(w.begin, n).squaredNorm());
}

// The format's lag_samples: l in -10..10 maximising sum (Fhat(k + l) - mean)(F(k) - mean).
int lag_samples(const VectorXd& est, const VectorXd& truth, Window w) {
  const Index n = w.end - w.begin;
  const double me = est.segment(w.begin, n).mean(), mt = truth.segment(w.begin, n).mean();
  int best = 0;
  double best_c = -1e300;
  for (int l = -10; l <= 10; ++l) {
    double c = 0.0;
    for (Index k = w.begin; k < w.end; ++k) {
      if (k + l < 0 || k + l >= est.size()) continue;
      c += (est[k + l] - me) * (truth[k] - mt);
    }
    if (c > best_c) {
      best_c = c;
      best = l;
    }
  }
  return best;
}

struct Record {
  DiscreteModel model;
  VectorXd force, y;
};

// 2 s of the X axis at 10240 Hz: y = simulate(model, F) + white noise of variance 0.007 N^2.
Record x_record(Index samples = 20480) {
  Record r;
  r.model = zoh(x_axis_model(), kFs);
  r.force = milling_force(samples, 11);
  r.y = with_noise(simulate(r.model, r.force), kNoiseVarX, 12);
  return r;
}

TEST(ForcerecAkfModel, TestModelIsTheXAxisOf004) {
  const ContinuousModel m = x_axis_model();
  VectorXd f(2);
  f << 0.0, 1534.5;
  const Eigen::VectorXcd H = frequency_response(m, f);
  EXPECT_NEAR(H[0].real(), 1.0, 1e-12);  // DC gain set to 1
  // |Hxx(1534.5 Hz)| = 6.71 (notes/004.md sec. 7, from Table 3.1's coefficients); 2 % covers the
  // rounding of the roots to 0.1 Hz and 3 digits of zeta.
  EXPECT_NEAR(std::abs(H[1]), 6.71, 0.02 * 6.71);
}

TEST(ForcerecAkf, ReconstructsAMillingForceWithoutLag) {
  const Record r = x_record();
  const Window w = evaluation_window(r.y.size());
  const SampleWindow tw =
      akf_tuning_window(r.y.size(), kFs, 0.0, static_cast<double>(r.y.size()) / kFs);
  EXPECT_EQ(tw.begin, 0);
  EXPECT_EQ(tw.end, 10752);  // 0.05 s skipped + 1 s summed
  const AkfResult a = reconstruct_force_akf(r.model, r.y, kNoiseVarX, tw);
  ASSERT_TRUE(a.summary.ok()) << a.summary.full_report();
  ASSERT_EQ(a.force.size(), r.y.size());
  EXPECT_EQ(a.S_grid_N2.size(), 101);
  EXPECT_TRUE(a.modal);
  const double nrmse = nrmse_pct(a.force, r.force, w);
  const double measured = nrmse_pct(r.y, r.force, w);
  // Measured on this record (seeds 11, 12): knee S = 6.31 N^2 (grid index 58), AKF 0.75 %, the
  // measured force 81 % (the third harmonic sits by the 1518.6 Hz mode, |H| = 6.7, and y lags by
  // the dynamometer's phase). Bounds: 1.5 % for the AKF (twice the figure: other noise seeds), and
  // the measured force at least 20 times worse.
  constexpr double kAkfNrmseBoundPct = 1.5;
  EXPECT_LT(nrmse, kAkfNrmseBoundPct) << "S = " << a.S_N2;
  EXPECT_GT(measured, 20.0 * nrmse);
  EXPECT_EQ(lag_samples(a.force, r.force, w), 0);
  // Without the format's one-step shift (p(k|k) as sample k) the estimate is one sample late.
  VectorXd filtered(a.force.size());
  filtered[0] = 0.0;
  filtered.tail(a.force.size() - 1) = a.force.head(a.force.size() - 1);
  EXPECT_EQ(lag_samples(filtered, r.force, w), 1);
  EXPECT_EQ(a.force[a.force.size() - 1], a.force[a.force.size() - 2]);  // last sample repeated
}

TEST(ForcerecAkf, ChosenSObeysTheKneeRule) {
  const Record r = x_record();
  const SampleWindow tw =
      akf_tuning_window(r.y.size(), kFs, 0.0, static_cast<double>(r.y.size()) / kFs);
  const AkfResult a = reconstruct_force_akf(r.model, r.y, kNoiseVarX, tw);
  ASSERT_TRUE(a.summary.ok());
  ASSERT_TRUE(a.E.allFinite());
  const double m = a.E.minCoeff();
  const Index last = a.E.size() - 1;
  ASSERT_GE(a.knee_index, 0);
  EXPECT_EQ(a.S_N2, a.S_grid_N2[a.knee_index]);
  if (a.E[last] > 1.01 * m) {
    EXPECT_EQ(a.E[a.knee_index], m);
  } else {
    EXPECT_LE(a.E[a.knee_index], 1.02 * m);
    for (Index i = 0; i < a.knee_index; ++i) EXPECT_GT(a.E[i], 1.02 * m) << i;
  }
  // E falls from the stiff end: the smallest S is far from the minimum.
  EXPECT_GT(a.E[0], 2.0 * m);
}

TEST(ForcerecAkf, KneeOfAFallingCurveThatFlattens) {
  // E_i = 1 + 9 * 0.8^i: the knee is the first i with 9 * 0.8^i <= 0.02 min E (closed form).
  VectorXd E(101);
  for (Index i = 0; i < 101; ++i) E[i] = 1.0 + 9.0 * std::pow(0.8, static_cast<double>(i));
  const double m = E[100];
  const Index expected =
      static_cast<Index>(std::ceil(std::log((0.02 * m + 1.0 - 1.0) / 9.0) / std::log(0.8)));
  EXPECT_EQ(expected, 28);
  EXPECT_EQ(akf_knee_index(E, 0.02, 0.01), expected);
}

TEST(ForcerecAkf, KneeOfACurveThatDips) {
  // Minimum 1 at i = 60, rising to 1.05 at the end (> 1 % above): the S of the minimum.
  VectorXd E(101);
  for (Index i = 0; i < 101; ++i) {
    const double d = (static_cast<double>(i) - 60.0) / 40.0;
    E[i] = i < 60 ? 1.0 + 4.0 * d * d : 1.0 + 0.05 * d * d;
  }
  EXPECT_EQ(akf_knee_index(E, 0.02, 0.01), 60);
  // The same curve rising only 0.5 % at the end is not a dip: the knee rule applies. The first
  // i < 60 with 4 d^2 <= 0.02 is i = 60 - floor(40 sqrt(0.005)) = 60 - floor(2.83) = 58.
  for (Index i = 60; i < 101; ++i) {
    const double d = (static_cast<double>(i) - 60.0) / 40.0;
    E[i] = 1.0 + 0.005 * d * d;
  }
  EXPECT_EQ(akf_knee_index(E, 0.02, 0.01), 58);
}

TEST(ForcerecAkf, KneeIgnoresFailedDesigns) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  VectorXd E(5);
  E << nan, 5.0, 1.0, 1.01, nan;
  EXPECT_EQ(akf_knee_index(E, 0.02, 0.01), 2);
  E.setConstant(nan);
  EXPECT_EQ(akf_knee_index(E, 0.02, 0.01), -1);
}

TEST(ForcerecAkf, OnlySOverRMatters) {
  const Record r = x_record(6000);
  const double S = 0.01;  // 004's X value
  const AkfResult a = reconstruct_force_akf_fixed_S(r.model, r.y, kNoiseVarX, S);
  ASSERT_TRUE(a.summary.ok());
  for (double c : {1e-3, 1e3}) {
    const AkfFilter f1 = design_akf(r.model, S, kNoiseVarX);
    const AkfFilter fc = design_akf(r.model, c * S, c * kNoiseVarX);
    ASSERT_TRUE(fc.summary.ok());
    // The gain from two DARE solutions converged to 1e-13 (dare.h): 1e-10 relative.
    constexpr double kGainRel = 1e-10;
    EXPECT_LT((fc.K - f1.K).norm(), kGainRel * f1.K.norm()) << c;
    const AkfResult b = reconstruct_force_akf_fixed_S(r.model, r.y, c * kNoiseVarX, c * S);
    ASSERT_TRUE(b.summary.ok());
    // The estimates to rounding: 1e-9 of the force's size (30 N mean).
    constexpr double kEstimateRel = 1e-9;
    EXPECT_LT((b.force - a.force).cwiseAbs().maxCoeff(),
              kEstimateRel * a.force.cwiseAbs().maxCoeff())
        << c;
  }
  // The innovations are the same too, so E(c S; c R) = E(S; R): the knee is the same S/R.
  const AkfFilter f1 = design_akf(r.model, S, kNoiseVarX);
  const AkfFilter fc = design_akf(r.model, 1e3 * S, 1e3 * kNoiseVarX);
  const double e1 = akf_error_norm(f1, r.y, 0, 6000, 512);
  EXPECT_NEAR(akf_error_norm(fc, r.y, 0, 6000, 512), e1, 1e-9 * e1);
}

// The format's filter (x0 = 0, P0 = p0 I, time-varying gain) on the project's general core:
// sample k = p(k+1|k+1).
VectorXd time_varying_akf(const DiscreteModel& model, const VectorXd& y, double S, double R,
                          double P0) {
  constexpr int N = 7;
  kalman::LinearModel<N, 0, 1> m;
  m.A.setZero();
  m.A.topLeftCorner<6, 6>() = model.Ad;
  m.A.topRightCorner<6, 1>() = model.Bd;
  m.A(6, 6) = 1.0;
  m.C.setZero();
  m.C.leftCols<6>() = model.C;
  m.Q.setZero();
  m.Q(6, 6) = S;
  m.R(0, 0) = R;
  kalman::FilterOptions o;
  o.covariance_update = kalman::CovarianceUpdate::kJoseph;
  kalman::KalmanFilter<N, 0, 1> kf(m, kalman::Matrix<N, 1>::Zero(),
                                   P0 * kalman::Matrix<N, N>::Identity(), o);
  VectorXd out(y.size());
  kalman::Matrix<1, 1> z;
  const kalman::Matrix<0, 1> u;
  for (Index k = 0; k < y.size(); ++k) {
    z(0) = y[k];
    kf.update(z);
    if (k >= 1) out[k - 1] = kf.state()[6];  // p(k|k) is sample k - 1
    kf.predict(u);
  }
  out[y.size() - 1] = out[y.size() - 2];
  return out;
}

TEST(ForcerecAkf, SteadyStateAgreesWithTheTimeVaryingFilterAfter50ms) {
  const Record r = x_record(6000);
  const Index skip = static_cast<Index>(std::ceil(0.05 * kFs));
  for (double S : {1e-4, 0.01, 1.0, 100.0}) {
    const AkfResult a = reconstruct_force_akf_fixed_S(r.model, r.y, kNoiseVarX, S);
    ASSERT_TRUE(a.summary.ok()) << S;
    const VectorXd tv = time_varying_akf(r.model, r.y, S, kNoiseVarX, 1e6);
    const Index n = r.y.size() - skip;
    const double diff = (a.force.tail(n) - tv.tail(n)).cwiseAbs().maxCoeff();
    // The two start-up transients (from a force of ~30 N) decay like rho^k, rho the spectral
    // radius of the steady-state closed loop (0.975 at S = 1e-4, 0.965 above: the 1421 Hz zero).
    // Bound: 10 x 30 N x rho^512. Measured: 1.5e-5 N at S = 1e-4, 1e-7 N for S >= 0.01.
    const double bound_N = 10.0 * 30.0 * std::pow(a.spectral_radius, static_cast<double>(skip));
    EXPECT_LT(diff, bound_N) << "S = " << S;
    EXPECT_LT(bound_N, 1e-3);  // the bound itself is tight enough to mean something
  }
}

// The format's time-varying filter is invariant when R, S and P0 are scaled together (akf.h:
// P_k scales by c by induction, the gain K_k = P_k G^T (G P_k G^T + R)^-1 does not change).
// In floating point the invariance is exact for a power of two (every product and quotient
// scales exactly): the estimates must be bit-identical. For c = 1e-3 each scaling rounds, and
// the start from P0 = 1e6 I (covariances 1e8 times R) amplifies that rounding in the first
// samples (1.5 N at sample 14), a difference that decays like the closed loop's rho^k (0.965^k:
// 1.5 N x 0.965^512 = 2e-8 N); after 0.05 s, where the format evaluates, the two agree to 1e-8
// of the force's size (measured 1.2e-9). (At c = 1e3, P0 = 1e9 I, the time-varying filter itself
// breaks down: the reason the kind runs the steady-state filter, akf.h.)
TEST(ForcerecAkf, TimeVaryingFilterIsInvariantUnderScalingRSAndP0Together) {
  const Record r = x_record(6000);
  const double S = 0.01, P0 = 1e6;
  const VectorXd a = time_varying_akf(r.model, r.y, S, kNoiseVarX, P0);
  const double size = a.cwiseAbs().maxCoeff();
  for (double c : {1.0 / 1024, 1024.0}) {
    const VectorXd b = time_varying_akf(r.model, r.y, c * S, c * kNoiseVarX, c * P0);
    EXPECT_EQ((b - a).cwiseAbs().maxCoeff(), 0.0) << c;
  }
  const Index skip = static_cast<Index>(std::ceil(0.05 * kFs));
  const VectorXd b = time_varying_akf(r.model, r.y, 1e-3 * S, 1e-3 * kNoiseVarX, 1e-3 * P0);
  EXPECT_LT((b - a).tail(a.size() - skip).cwiseAbs().maxCoeff(), 1e-8 * size);
  // P0 left unscaled (S and R by 1/1024 only): the start-up differs, so the checks above are
  // not vacuous.
  const VectorXd d = time_varying_akf(r.model, r.y, S / 1024, kNoiseVarX / 1024, P0);
  EXPECT_GT((d - a).head(50).cwiseAbs().maxCoeff(), 1e-6 * size);
}

TEST(ForcerecAkf, ModalAndDenseFormsAgree) {
  const Record r = x_record(6000);
  const AkfFilter f = design_akf(r.model, 0.01, kNoiseVarX);
  ASSERT_TRUE(f.summary.ok());
  ASSERT_TRUE(f.modal);
  EXPECT_LT(f.spectral_radius, 1.0);
  AkfFilter d = f;  // the dense form of the same filter
  d.modal = false;
  d.b = d.L;
  d.g = d.G_a;
  d.h = -d.K[6] * d.G_a;
  d.h[6] += 1.0;
  VectorXd fm, fd;
  run_akf(f, r.y, &fm);
  run_akf(d, r.y, &fd);
  // Rounding of the modal transformation (modal_residual < 1e-10): 1e-9 of the force.
  EXPECT_LT((fm - fd).cwiseAbs().maxCoeff(), 1e-9 * fd.cwiseAbs().maxCoeff());
  const double em = akf_error_norm(f, r.y, 100, 6000, 512);
  const double ed = akf_error_norm(d, r.y, 100, 6000, 512);
  EXPECT_NEAR(em, ed, 1e-9 * ed);
  // E is the innovation norm: about sqrt(R * count) once the filter is tuned near the knee.
  EXPECT_GT(em, std::sqrt(kNoiseVarX * (6000 - 612)));
}

TEST(ForcerecAkf, OtherOrdersWork) {
  // n = 2, 4, 8, 10 (the last runs the run-time-sized kernels): noiseless held force, S/R = 1e6.
  const std::vector<PoleZero> poles = {
      {1108.4, 0.026}, {1138.1, 0.161}, {1856.9, 0.0273}, {2400.0, 0.03}, {3000.0, 0.05}};
  const std::vector<PoleZero> zeros = {
      {1173.1, 0.071}, {1721.8, 0.022}, {2600.0, 0.04}, {3200.0, 0.05}};
  const VectorXd F = milling_force(4096, 21);
  const Window w = evaluation_window(F.size());
  for (std::size_t modes : {1u, 2u, 4u, 5u}) {
    const std::vector<PoleZero> p(poles.begin(), poles.begin() + modes);
    const std::vector<PoleZero> z(zeros.begin(), zeros.begin() + (modes - 1));
    const DiscreteModel d = zoh(modal_model(p, z, {-22000.0}), kFs);
    const VectorXd y = simulate(d, F);
    const AkfResult a = reconstruct_force_akf_fixed_S(d, y, 1e-6, 1.0);
    ASSERT_TRUE(a.summary.ok()) << modes << ": " << a.summary.full_report();
    // Measured: 0.0007 % (n = 2) to 0.0016 % (n = 10); S/R = 1e6 is nearly the exact inverse.
    EXPECT_LT(nrmse_pct(a.force, F, w), 0.01) << "n = " << 2 * modes;
    EXPECT_EQ(lag_samples(a.force, F, w), 0);
  }
}

TEST(ForcerecAkf, FailuresGoToTheSummary) {
  Record r = x_record(2000);
  const SampleWindow tw{0, 2000};
  AkfResult a = reconstruct_force_akf_fixed_S(r.model, r.y, 0.0, 0.01);
  EXPECT_TRUE(a.summary.failed());
  EXPECT_EQ(a.summary.message, "akf: R_N2 = 0: must be finite and > 0 (the noise variance)");
  r.y[5] = std::nan("");
  a = reconstruct_force_akf(r.model, r.y, kNoiseVarX, tw);
  EXPECT_TRUE(a.summary.failed());
  EXPECT_EQ(a.summary.message, "akf: y[5] = nan: every sample must be finite");
  EXPECT_EQ(a.force.size(), 0);
  r.y[5] = 0.0;
  a = reconstruct_force_akf(r.model, r.y, kNoiseVarX, SampleWindow{0, 400});
  EXPECT_TRUE(a.summary.failed());
  EXPECT_EQ(a.summary.message,
            "akf: the tuning window [0, 400) holds no sample after the 512 skipped (akf.skip_s = "
            "0.05)");
  // A model whose static gain is 0 cannot see a constant force: the DARE fails (F undetectable).
  DiscreteModel blind = r.model;
  blind.C.setZero();
  a = reconstruct_force_akf_fixed_S(blind, r.y, kNoiseVarX, 0.01);
  EXPECT_TRUE(a.summary.failed());
  EXPECT_NE(a.summary.message.find("akf: the steady-state gain failed at S_N2 = 0.01"),
            std::string::npos)
      << a.summary.message;
}

TEST(ForcerecAkf, RefusesBadShapesAndOptions) {
  const Record r = x_record(2000);
  EXPECT_THROW(reconstruct_force_akf_fixed_S(r.model, r.y.head(1), kNoiseVarX, 0.01),
               std::invalid_argument);
  EXPECT_THROW(reconstruct_force_akf(r.model, r.y, kNoiseVarX, SampleWindow{0, 2001}),
               std::invalid_argument);
  DiscreteModel bad = r.model;
  bad.Bd = VectorXd::Ones(3);
  EXPECT_THROW(design_akf(bad, 1.0, 1.0), std::invalid_argument);
  AkfOptions o;
  o.S_per_decade = 0;
  try {
    akf_S_grid(o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "akf.S_per_decade = 0: must be in 1..1000");
  }
  const VectorXd grid = akf_S_grid(AkfOptions{});
  ASSERT_EQ(grid.size(), 101);
  EXPECT_DOUBLE_EQ(grid[0], 1e-5);
  EXPECT_NEAR(grid[100], 1e5, 1e5 * 1e-14);
  EXPECT_NEAR(grid[50], 1.0, 1e-15);
}

}  // namespace
}  // namespace forcerec
}  // namespace chatterlab
