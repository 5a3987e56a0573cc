// Sliding-mode observer force reconstruction (004 eqs 2.15-2.22 in the format's discrete time).
#include "analysis/forcerec/smo.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

namespace chatterlab {
namespace forcerec {
namespace {

using Eigen::Index;
using Eigen::VectorXd;

constexpr double kFs = 10240.0;     // 004's simulation-like rate (notes/004.md sec. 1)
constexpr double kToothHz = 511.5;  // 15345 rpm, two teeth (004 sec. 7)
constexpr int kHarmonics = 8;       // format: min(12, floor(0.4 fs / f_tp))

struct Mode {
  double fn_hz, zeta, weight;
};
// The x axis poles of 004 Table 3.1 (notes/004.md sec. 2), each a base-excitation section
// w (2 zeta wn s + wn^2) / (s^2 + 2 zeta wn s + wn^2): DC gain sum w = 1, b1 = sum 2 zeta wn w.
const std::vector<Mode> kModes = {
    {1411.8, 0.0214, 0.5}, {1458.8, 0.163, 0.3}, {1518.6, 0.0221, 0.2}};

// Real modal form, one 2 x 2 block per mode in the states (wn q, q'): A = [[0, wn], [-wn,
// -2 zeta wn]], B = [0, wn], C = w [1, 2 zeta] (all O(1) to O(wn)).
ContinuousModel modal_model(const std::vector<Mode>& modes) {
  const Index n = 2 * static_cast<Index>(modes.size());
  ContinuousModel m;
  m.A = Eigen::MatrixXd::Zero(n, n);
  m.B = VectorXd::Zero(n);
  m.C = Eigen::RowVectorXd::Zero(n);
  for (size_t r = 0; r < modes.size(); ++r) {
    const Index i = 2 * static_cast<Index>(r);
    const double wn = 2 * M_PI * modes[r].fn_hz, z = modes[r].zeta;
    m.A(i, i + 1) = wn;
    m.A(i + 1, i) = -wn;
    m.A(i + 1, i + 1) = -2 * z * wn;
    m.B[i + 1] = wn;
    m.C[i] = modes[r].weight;
    m.C[i + 1] = 2 * z * modes[r].weight;
  }
  return m;
}

// Polynomials in sigma = s / w0 (w0 = 1e4 rad/s keeps the coefficients O(1)), lowest power first.
using Poly = std::vector<double>;
Poly multiply(const Poly& a, const Poly& b) {
  Poly c(a.size() + b.size() - 1, 0.0);
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t j = 0; j < b.size(); ++j) c[i + j] += a[i] * b[j];
  return c;
}
// The zeros of sum_r w_r (2 zeta_r wn_r s + wn_r^2) / D_r(s) from the numerator polynomial (an
// independent route to the zeros: companion matrix of the combined numerator), in rad/s.
Eigen::VectorXcd modal_zeros(const std::vector<Mode>& modes) {
  const double w0 = 1e4;
  Poly num(1, 0.0);
  for (size_t r = 0; r < modes.size(); ++r) {
    const double wn = 2 * M_PI * modes[r].fn_hz / w0, z = modes[r].zeta;
    Poly term = {modes[r].weight * wn * wn, modes[r].weight * 2 * z * wn};
    for (size_t q = 0; q < modes.size(); ++q) {
      if (q == r) continue;
      const double wq = 2 * M_PI * modes[q].fn_hz / w0, zq = modes[q].zeta;
      term = multiply(term, {wq * wq, 2 * zq * wq, 1.0});
    }
    if (num.size() < term.size()) num.resize(term.size(), 0.0);
    for (size_t i = 0; i < term.size(); ++i) num[i] += term[i];
  }
  while (num.back() == 0.0) num.pop_back();
  const Index d = static_cast<Index>(num.size()) - 1;
  Eigen::MatrixXd comp = Eigen::MatrixXd::Zero(d, d);
  for (Index i = 1; i < d; ++i) comp(i, i - 1) = 1.0;
  for (Index i = 0; i < d; ++i) comp(i, d - 1) = -num[static_cast<size_t>(i)] / num.back();
  return Eigen::EigenSolver<Eigen::MatrixXd>(comp, false).eigenvalues() * w0;
}

// A milling-like held force: mean + 8 harmonics of the tooth frequency (amplitudes of notes/004.md
// sec. 9 extended), F(k) constant over [k/fs, (k+1)/fs).
VectorXd milling_force(Index n) {
  const double amp[kHarmonics] = {20, 8, 5, 3, 2, 1, 0.6, 0.4};
  const double phase[kHarmonics] = {0.3, 1.9, -2.2, 0.8, 2.7, -1.1, 0.5, -0.4};
  VectorXd F(n);
  for (Index k = 0; k < n; ++k) {
    double v = 30.0;
    for (int h = 0; h < kHarmonics; ++h)
      v += amp[h] * std::cos(2 * M_PI * (h + 1) * kToothHz * k / kFs + phase[h]);
    F[k] = v;
  }
  return F;
}

// The format's evaluation window: 0.05 s <= k / fs < T - 0.01 s.
struct Window {
  Index begin, end;
};
Window eval_window(Index n) {
  return {static_cast<Index>(std::ceil(0.05 * kFs)), n - static_cast<Index>(std::ceil(0.01 * kFs))};
}

double nrmse_pct(const VectorXd& est, const VectorXd& ref, Window w) {
  const Index len = w.end - w.begin;
  return 100.0 * (est.segment(w.begin, len) - ref.segment(w.begin, len)).norm() /
         ref.segment(w.begin, len).norm();
}

// Format: the l in -10..10 maximising sum_k (Fhat(k+l) - mean)(F(k) - mean); > 0: late.
int lag_samples(const VectorXd& est, const VectorXd& ref, Window w) {
  const Index len = w.end - w.begin - 20;
  const double me = est.segment(w.begin, w.end - w.begin).mean();
  const double mr = ref.segment(w.begin, w.end - w.begin).mean();
  int best = 0;
  double best_c = -1e300;
  for (int l = -10; l <= 10; ++l) {
    double c = 0.0;
    for (Index k = w.begin + 10; k < w.begin + 10 + len; ++k)
      c += (est[k + l] - me) * (ref[k] - mr);
    if (c > best_c) {
      best_c = c;
      best = l;
    }
  }
  return best;
}

// Format: A_h = (2/n) |sum_j x(k0 + j) exp(-2 pi i h f_tp j / fs)| over whole tooth periods.
double harmonic_amplitude(const VectorXd& x, Window w, int h) {
  const Index P = static_cast<Index>(std::floor((w.end - w.begin) * kToothHz / kFs));
  const Index n = static_cast<Index>(std::lround(P * kFs / kToothHz));
  std::complex<double> s = 0.0;
  for (Index j = 0; j < n; ++j)
    s += x[w.begin + j] * std::polar(1.0, -2 * M_PI * h * kToothHz * j / kFs);
  return 2.0 / n * std::abs(s);
}

// The SMO in its linear regime (nu = -(rho/delta) e), sampled as the format fixes it, written
// out independently of smo.cpp: e(k+1) = phi e(k) - (1 - phi) b(k) / lambda, and the interval
// mean of nu from the exponential's integral.
VectorXd linear_boundary_layer(const VectorXd& F_zoh, double B2, const SmoOptions& o) {
  const double kappa = o.rho_N_s / o.delta_N, lambda = kappa - o.a22s_1_s, dt = 1.0 / kFs;
  const double phi = std::exp(-lambda * dt);
  VectorXd out(F_zoh.size());
  double e = 0.0;
  for (Index k = 0; k < F_zoh.size(); ++k) {
    const double b = B2 * F_zoh[k], ess = -b / lambda;
    const double int_e = ess * dt + (e - ess) * (1.0 - phi) / lambda;
    out[k] = -kappa * int_e / dt / B2;
    e = ess + (e - ess) * phi;
  }
  return out;
}

TEST(ForcerecSmoCanonical, SameTransferFunctionOutputLastAndA11HoldsTheZeros) {
  const ContinuousModel m = modal_model(kModes);
  const CanonicalForm cf = canonical_form(m);
  const Index n = m.order();
  // B2 = C B = b1 = sum 2 zeta wn w (closed form of the sections), 004 notes sec. 5.
  double b1 = 0.0;
  for (const Mode& md : kModes) b1 += 2 * md.zeta * 2 * M_PI * md.fn_hz * md.weight;
  EXPECT_NEAR(cf.B2, b1, 1e-12 * b1);
  // C = [0 ... 0 1], B = [0 ... 0 B2] (004 eqs 2.15-2.16): rounding of two 6 x 6 products.
  constexpr double kExact = 1e-12;
  for (Index i = 0; i + 1 < n; ++i) {
    EXPECT_NEAR(cf.C[i], 0.0, kExact);
    EXPECT_NEAR(cf.B[i], 0.0, kExact * b1);
  }
  EXPECT_NEAR(cf.C[n - 1], 1.0, kExact);
  EXPECT_NEAR(cf.B[n - 1], b1, kExact * b1);
  // Same frequency response, 10 Hz .. 5 kHz through the three resonances.
  VectorXd f = VectorXd::LinSpaced(500, 10.0, 5000.0);
  const Eigen::VectorXcd g0 = frequency_response(m, f);
  const Eigen::VectorXcd g1 = frequency_response(ContinuousModel{cf.A, cf.B, cf.C}, f);
  constexpr double kFrfRel = 1e-9;  // the acceptance of notes/004.md sec. 2
  for (Index i = 0; i < f.size(); ++i)
    EXPECT_LT(std::abs(g1[i] - g0[i]), kFrfRel * std::abs(g0[i]));
  // eig(A11) = the zeros of the model (004 eq. 2.20), against the numerator polynomial's roots.
  const Eigen::VectorXcd za = Eigen::EigenSolver<Eigen::MatrixXd>(cf.A11(), false).eigenvalues();
  const Eigen::VectorXcd zp = modal_zeros(kModes);
  ASSERT_EQ(za.size(), n - 1);
  ASSERT_EQ(zp.size(), n - 1);
  constexpr double kZeroRel =
      1e-10;  // companion-matrix roots of a degree-5 polynomial (2e-15 seen)
  for (Index i = 0; i < zp.size(); ++i) {
    EXPECT_LT(zp[i].real(), 0.0) << "the test model must be minimum phase";
    double nearest = 1e300;
    for (Index j = 0; j < za.size(); ++j) nearest = std::min(nearest, std::abs(za[j] - zp[i]));
    EXPECT_LT(nearest, kZeroRel * std::abs(zp[i])) << zp[i];
  }
}

TEST(ForcerecSmoStep, MatchesAFineRk4Integration) {
  // Second method: classical RK4 on e' = a22s e - rho e / (delta + |e|) - b with 2e5 steps per
  // interval (h lambda <= 1e-3 at the stiffest case).
  auto rk4 = [](double e, double b, double dt, const SmoOptions& o, double* nu_mean) {
    auto nu = [&](double x) { return -o.rho_N_s * x / (o.delta_N + std::abs(x)); };
    auto f = [&](double x) { return o.a22s_1_s * x + nu(x) - b; };
    const int steps = 200000;
    const double h = dt / steps;
    double int_nu = 0.0;  // integrated as a second state of the same RK4
    for (int i = 0; i < steps; ++i) {
      const double x2 = e + 0.5 * h * f(e);
      const double x3 = e + 0.5 * h * f(x2);
      const double x4 = e + h * f(x3);
      int_nu += h / 6 * (nu(e) + 2 * nu(x2) + 2 * nu(x3) + nu(x4));
      e += h / 6 * (f(e) + 2 * f(x2) + 2 * f(x3) + f(x4));
    }
    *nu_mean = int_nu / dt;
    return e;
  };
  const double dt = 1.0 / kFs;
  SmoOptions defaults;
  SmoOptions slow;  // 004's experimental rule: rho = max|y| |B2| ~ 60 x 1e3
  slow.rho_N_s = 6e4;
  struct Case {
    double e0, b;
    const SmoOptions* o;
    const char* what;
  };
  const Case cases[] = {
      {0.0, 1.5e5, &defaults, "from e = 0 into sliding"},
      {0.05, -2.0e5, &defaults, "crossing e = 0 then sliding"},
      {500.0, 3.0e5, &defaults, "outside the layer, saturated approach"},
      {0.0, 0.0, &defaults, "at rest"},
      {-3.0, 0.0, &defaults, "no drive: decay to 0"},
      {40.0, 5e4, &slow, "slow layer, settling within the interval"},
      {-200.0, 5e4, &slow, "slow layer, no crossing within the interval"},
      {10.0, -1e5, &slow, "slow layer, |drive| > rho"},
  };
  for (const Case& c : cases) {
    double nu_ref = 0.0;
    const double e_ref = rk4(c.e0, c.b, dt, *c.o, &nu_ref);
    const OutputErrorStep st = smo_output_error_step(c.e0, c.b, dt, *c.o);
    // Closed form against RK4 at h = 0.5 ns (h lambda <= 1e-3: local error ~ 1e-15, summed over
    // 2e5 steps; 1.3e-10 relative seen, from the kink of |e| at a crossing).
    constexpr double kRk4Rel = 1e-9;
    const double scale_e = std::abs(c.e0) + std::abs(e_ref) + 1e-6;
    const double scale_nu = std::abs(c.b) + c.o->rho_N_s * 1e-6;
    EXPECT_NEAR(st.e_end_N, e_ref, kRk4Rel * scale_e) << c.what;
    EXPECT_NEAR(st.nu_mean_N_s, nu_ref, kRk4Rel * scale_nu) << c.what;
  }
}

class ForcerecSmoRecord : public ::testing::Test {
 protected:
  static constexpr Index kN = 102400;  // 10 s
  void SetUp() override {
    model = modal_model(kModes);
    dm = zoh(model, kFs);
    F = milling_force(kN);
    y = simulate(dm, F);  // F held over each interval: F_zoh = F exactly
    options.tooth_freq_hz = kToothHz;
    options.harmonic_count = kHarmonics;
  }
  ContinuousModel model;
  DiscreteModel dm;
  VectorXd F, y;
  SmoOptions options;
};

TEST_F(ForcerecSmoRecord, DefaultsReturnTheHeldForceWithoutLag) {
  const SmoResult r = reconstruct_force_smo(model, kFs, y, options);
  ASSERT_TRUE(r.summary.ok()) << r.summary.full_report();
  EXPECT_FALSE(r.bandwidth_warning) << r.summary.full_report();
  EXPECT_TRUE(r.summary.warnings.empty());
  ASSERT_EQ(r.force.size(), kN);
  EXPECT_LT(r.max_sampled_zero_modulus, 1.0);
  const Window w = eval_window(kN);
  // The one-step inverse of the sampled model reproduces the held force (rounding only).
  VectorXd F_zoh(kN);
  run_one_step_inverse(one_step_inverse(dm), y, F_zoh);
  EXPECT_LT(nrmse_pct(F_zoh, F, w), 1e-9);
  // The SMO returns F_zoh but for the boundary layer's fractional delay (rho/delta - a22s)^-1 =
  // 0.0067 samples (smo.h): about 0.0067 |F(k) - F(k-1)|, 0.145 % of rms F for this force.
  const double err = nrmse_pct(r.force, F, w);
  EXPECT_LT(err, 0.2);
  EXPECT_EQ(lag_samples(r.force, F, w), 0);
  // That remainder is the linear boundary layer itself: the sigmoid of 2.22 departs from it by
  // about the reach ratio max|B2 F| / rho (6.4e-4) of it (9e-5 % seen).
  const VectorXd lin = linear_boundary_layer(F, r.B2_1_s, options);
  EXPECT_LT(nrmse_pct(r.force, lin, w), 3 * r.reach_ratio * err);
  // Harmonic amplitudes as the sampled boundary layer predicts: -0.03 % at 511.5 Hz to -1.2 % at
  // 4092 Hz = 0.4 fs, which is also the warning's figure (below its 2 % threshold).
  constexpr double kLeak = 1e-4;  // spectral leakage: 511.5 Hz is 20.02 samples per period
  for (int h = 1; h <= kHarmonics; ++h) {
    const double ratio = harmonic_amplitude(r.force, w, h) / harmonic_amplitude(F, w, h);
    const double predicted = std::abs(smo_boundary_layer_response(options, kFs, h * kToothHz));
    EXPECT_NEAR(ratio, predicted, kLeak) << "harmonic " << h;
    if (h == kHarmonics) {
      EXPECT_NEAR(1.0 - ratio, r.amplitude_error, kLeak);
    }
  }
  EXPECT_NEAR(r.amplitude_error, 0.0120, 0.0002);
  // The output error stays inside the boundary layer: |e| ~ delta |B2 F| / rho.
  EXPECT_LT(r.output_error_N.cwiseAbs().maxCoeff(), 0.01 * options.delta_N);
}

TEST_F(ForcerecSmoRecord, WithNoiseTheErrorIsTheInverseNoiseGain) {
  std::mt19937_64 rng(9004);
  const double R = 0.007;  // 004's x axis air-cut variance (N^2)
  std::normal_distribution<double> noise(0.0, std::sqrt(R));
  VectorXd yn = y;
  for (Index k = 0; k < kN; ++k) yn[k] += noise(rng);
  const SmoResult r = reconstruct_force_smo(model, kFs, yn, options);
  ASSERT_TRUE(r.summary.ok()) << r.summary.full_report();
  const Window w = eval_window(kN);
  // Reference: white noise through the one-step inverse and the linear boundary layer, rms
  // sqrt(R sum g^2), g their impulse response from y (the inverse alone: 0.5622 N; the layer's
  // fractional delay trims the high-frequency noise by 1.1 %).
  VectorXd impulse = VectorXd::Zero(4096), g(4096);
  impulse[1] = 1.0;
  run_one_step_inverse(one_step_inverse(dm), impulse, g);
  g[g.size() - 1] = 0.0;  // the repeated last sample is not part of the response
  const double predicted =
      std::sqrt(R) * linear_boundary_layer(g, canonical_form(model).B2, options).norm();
  const Index len = w.end - w.begin;
  const double rms_err = (r.force - F).segment(w.begin, len).norm() / std::sqrt(double(len));
  // 1 %: the sample rms of 1e5 values of a noise correlated over a few samples.
  EXPECT_NEAR(rms_err, predicted, 0.01 * predicted);
  EXPECT_EQ(lag_samples(r.force, F, w), 0);
}

TEST_F(ForcerecSmoRecord, ExperimentalRuleLowPassesDelaysAndWarns) {
  // 004's experimental rule rho = max|y| |B2| (sec. 4.4) with delta = 65 N.
  SmoOptions o = options;
  o.rho_N_s = y.cwiseAbs().maxCoeff() * std::abs(canonical_form(model).B2);
  const SmoResult r = reconstruct_force_smo(model, kFs, y, o);
  ASSERT_TRUE(r.summary.ok()) << r.summary.full_report();
  EXPECT_TRUE(r.bandwidth_warning);
  ASSERT_EQ(r.summary.warnings.size(), 1u);
  const Window w = eval_window(kN);
  const int lag = lag_samples(r.force, F, w);
  const double err = nrmse_pct(r.force, F, w);
  EXPECT_GE(lag, 2);     // 3 seen
  EXPECT_GT(err, 30.0);  // 45 % seen
  EXPECT_NE(r.summary.warnings[0].find("too small for the harmonics"), std::string::npos);
  // The tooth harmonics are cut: the 4th (2046 Hz) loses more than half.
  EXPECT_LT(harmonic_amplitude(r.force, w, 4), 0.5 * harmonic_amplitude(F, w, 4));
}

TEST_F(ForcerecSmoRecord, LinearRegimeMatchesTheSampledBoundaryLayerAndItsWarning) {
  // A wide boundary layer (|e| << delta) with a 3 kHz corner: the estimate is the linear
  // sampled filter of smo.h applied to F_zoh, and the warning's amplitude error is what the
  // harmonics show.
  SmoOptions o = options;
  o.delta_N = 1e4;
  o.rho_N_s = o.delta_N * 2 * M_PI * 3000.0;
  const SmoResult r = reconstruct_force_smo(model, kFs, y, o);
  ASSERT_TRUE(r.summary.ok()) << r.summary.full_report();
  EXPECT_TRUE(r.bandwidth_warning);
  EXPECT_LT(r.reach_ratio, 0.01);
  const Window w = eval_window(kN);
  const VectorXd lin = linear_boundary_layer(F, r.B2_1_s, o);
  // The sigmoid departs from the line by about the reach ratio (3.4e-4) of the difference.
  EXPECT_LT(nrmse_pct(r.force, lin, w), 3 * r.reach_ratio * nrmse_pct(r.force, F, w));
  for (int h = 1; h <= kHarmonics; ++h) {
    const double predicted =
        std::abs(smo_boundary_layer_response(o, kFs, h * kToothHz, r.reach_ratio));
    const double measured = harmonic_amplitude(r.force, w, h) / harmonic_amplitude(F, w, h);
    // Leakage (511.5 Hz is 20.02 samples per period) and the sigmoid: 1.4e-4 seen.
    EXPECT_NEAR(measured, predicted, 5e-4) << "harmonic " << h;
  }
  EXPECT_NEAR(
      r.amplitude_error,
      1.0 - std::abs(smo_boundary_layer_response(o, kFs, kHarmonics * kToothHz, r.reach_ratio)),
      1e-12);
}

TEST(ForcerecSmoFailures, NonMinimumPhaseModelFails) {
  // One mode with the zero at +0.5 wn: y = (c1 wn^2 + c2 wn s) q / (wn ...), c1 = -0.5, c2 = 1.
  const double wn = 2 * M_PI * 1000.0, zeta = 0.05;
  ContinuousModel m;
  m.A.resize(2, 2);
  m.A << 0, wn, -wn, -2 * zeta * wn;
  m.B = Eigen::Vector2d(0, wn);
  m.C = Eigen::RowVector2d(-0.5, 1.0);
  const VectorXd y = VectorXd::Ones(1000);
  const SmoResult r = reconstruct_force_smo(m, kFs, y);
  EXPECT_TRUE(r.summary.failed());
  EXPECT_NE(r.summary.message.find("not minimum phase"), std::string::npos) << r.summary.message;
  EXPECT_NE(r.summary.message.find("eig(A11) not Hurwitz"), std::string::npos);
  EXPECT_NE(r.summary.message.find("sampled zero"), std::string::npos);
  EXPECT_GT(r.max_sampled_zero_modulus, 1.0);
  ASSERT_EQ(r.zeros_rad_s.size(), 1);
  EXPECT_NEAR(r.zeros_rad_s[0].real(), 0.5 * wn, 1e-9 * wn);
  EXPECT_EQ(r.force.size(), 0);
}

TEST(ForcerecSmoFailures, BadInputAndOptions) {
  const ContinuousModel m = modal_model(kModes);
  VectorXd y = VectorXd::Zero(100);
  y[5] = std::nan("");
  const SmoResult r = reconstruct_force_smo(m, kFs, y);
  EXPECT_TRUE(r.summary.failed());
  EXPECT_EQ(r.summary.message, "smo: y[5] = nan: not finite");
  EXPECT_FALSE(SmoResult().summary.ran());  // a default result is "not run"

  SmoOptions o;
  o.rho_N_s = 0.0;
  try {
    reconstruct_force_smo(m, kFs, VectorXd::Zero(10), o);
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "smo.rho_N_s = 0: must be finite and > 0");
  }
  o = SmoOptions();
  o.a22s_1_s = 1.0;
  EXPECT_THROW(reconstruct_force_smo(m, kFs, VectorXd::Zero(10), o), InputError);
  EXPECT_THROW(reconstruct_force_smo(m, kFs, VectorXd::Zero(1)), std::invalid_argument);
  // Relative degree two: C B = 0.
  ContinuousModel m2 = m;
  m2.C = Eigen::RowVectorXd::Zero(m.order());
  m2.C[0] = 1.0;
  try {
    canonical_form(m2);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not of relative degree one"), std::string::npos);
  }
}

}  // namespace
}  // namespace forcerec
}  // namespace chatterlab
