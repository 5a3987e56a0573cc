// The synthetic tap-record generator against closed forms and the modes' receptance.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>

#include "analysis/common/constants.h"
#include "analysis/frf/modal_response.h"
#include "analysis/signal/fft.h"

namespace chatterlab {
namespace frf {
namespace {

const Mode kTool = mode_from_mck(0.03134, 22.21, 9.840e5);  // 000 sec. 5.1
constexpr double kFs = 25600.0;

// Ramp force F = alpha t from rest: x = (alpha/k) [t - 2 zeta/wn + exp(-zeta wn t)
// ((2 zeta/wn) cos wd t + ((2 zeta^2 - 1)/wd) sin wd t)] (particular + homogeneous
// solution of 000 eq. 2.5 with x(0) = x'(0) = 0).
struct RampResponse {
  double x, v;
};
RampResponse ramp_response(const Mode& m, double alpha, double t) {
  const double wn = 2.0 * kPi * m.fn_hz;
  const double z = m.zeta;
  const double wd = wn * std::sqrt(1.0 - z * z);
  const double s = z * wn;
  const double a = 2.0 * z / wn;
  const double b = (2.0 * z * z - 1.0) / wd;
  const double e = std::exp(-s * t);
  const double c = std::cos(wd * t);
  const double sn = std::sin(wd * t);
  RampResponse r;
  r.x = alpha / m.k_N_m * (t - a + e * (a * c + b * sn));
  r.v = alpha / m.k_N_m * (1.0 + e * (-s * (a * c + b * sn) + wd * (-a * sn + b * c)));
  return r;
}

TEST(ModalResponse, FirstOrderHoldIsExactForARamp) {
  // Rounding only: the discretisation is exact for a piecewise-linear force (the closed
  // form's own cancellation early on sets the floor, ~5e-13).
  constexpr double kRelTol = 1e-11;
  const double alpha = 1e5;  // N/s
  const Eigen::Index n = 2000;
  Eigen::VectorXd force(n);
  for (Eigen::Index i = 0; i < n; ++i) force[i] = alpha * static_cast<double>(i) / kFs;
  const Eigen::VectorXd x = modal_response({kTool}, force, kFs, ResponseKind::kDisplacement);
  const Eigen::VectorXd v = modal_response({kTool}, force, kFs, ResponseKind::kVelocity);
  const Eigen::VectorXd a = modal_response({kTool}, force, kFs, ResponseKind::kAcceleration);
  double max_x = 0.0, max_v = 0.0, err_x = 0.0, err_v = 0.0, err_a = 0.0, max_a = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const RampResponse r = ramp_response(kTool, alpha, static_cast<double>(i) / kFs);
    const double acc = (force[i] - kTool.c_kg_s * r.v - kTool.k_N_m * r.x) / kTool.m_kg;
    max_x = std::max(max_x, std::abs(r.x));
    max_v = std::max(max_v, std::abs(r.v));
    max_a = std::max(max_a, std::abs(acc));
    err_x = std::max(err_x, std::abs(x[i] - r.x));
    err_v = std::max(err_v, std::abs(v[i] - r.v));
    err_a = std::max(err_a, std::abs(a[i] - acc));
  }
  std::printf("ramp: relative max errors x %.2e v %.2e a %.2e\n", err_x / max_x, err_v / max_v,
              err_a / max_a);
  EXPECT_LT(err_x / max_x, kRelTol);
  EXPECT_LT(err_v / max_v, kRelTol);
  EXPECT_LT(err_a / max_a, kRelTol);
}

TEST(ModalResponse, ModesSuperpose) {
  constexpr double kRelTol = 1e-12;  // rounding
  const Mode second = mode_from_modal(2500.0, 0.02, 0.05);
  const Eigen::VectorXd f = half_sine_pulses({{0.001, 100.0, 2e-4}}, kFs, 1000);
  const Eigen::VectorXd both = modal_response({kTool, second}, f, kFs, ResponseKind::kAcceleration);
  const Eigen::VectorXd sum = modal_response({kTool}, f, kFs, ResponseKind::kAcceleration) +
                              modal_response({second}, f, kFs, ResponseKind::kAcceleration);
  EXPECT_LT((both - sum).norm(), kRelTol * sum.norm());
}

TEST(ModalResponse, HalfSinePulseSamples) {
  // f(t) = 100 sin(pi (t - 1 ms) / 0.5 ms) on [1, 1.5] ms at fs = 10 kHz: samples 10..15.
  const Eigen::VectorXd f = half_sine_pulses({{1e-3, 100.0, 5e-4}}, 1e4, 20);
  for (Eigen::Index i = 0; i < 20; ++i) {
    const double t = static_cast<double>(i) * 1e-4;
    const double expected = (i >= 10 && i <= 15) ? 100.0 * std::sin(kPi * (t - 1e-3) / 5e-4) : 0.0;
    EXPECT_NEAR(f[i], expected, 1e-9) << "sample " << i;
  }
}

// The FRF of a synthesized record (one hit, fully decayed, no noise) against the mode's
// receptance: DFT(response) / DFT(force), converted to receptance, 50 Hz .. 0.35 fs.
// Stated accuracy: the fine-rate first-order hold scales displacement and velocity by
// sinc^2(f / (8 fs)), a bias of (pi f / (8 fs))^2 / 3 (6e-5 at the tool mode, 6e-3 at
// 0.35 fs), plus a floor of 3e-4 from the FIR's finite stopband; allowed here with 10 %
// margin on the bias.
TEST(ModalResponse, SynthesizedRecordHasTheModesReceptance) {
  constexpr double kFloor = 3e-4;
  constexpr double kBiasMargin = 1.1;
  const Eigen::Index n = 8192;  // 0.32 s: the mode decays by exp(-113)
  const char* names[] = {"acceleration", "velocity", "displacement"};
  for (ResponseKind kind :
       {ResponseKind::kAcceleration, ResponseKind::kVelocity, ResponseKind::kDisplacement}) {
    const TapRecord rec = synthesize_tap_record({kTool}, {{0.01, 100.0, 2e-4}}, kFs, n, kind);
    signal::RealFft fft(n);
    const Eigen::VectorXcd F = fft.forward(rec.force_n);
    const Eigen::VectorXcd X = fft.forward(rec.response);
    double worst_ratio = 0.0;
    double worst_err = 0.0;
    double worst_f = 0.0;
    for (Eigen::Index k = 1; k < n / 2; ++k) {
      const double f = static_cast<double>(k) * kFs / static_cast<double>(n);
      if (f > 0.35 * kFs) break;
      // Below 50 Hz the acceleration spectrum is ~w^2 smaller than its error floor, and near
      // the pulse's spectral zero (1.5 / width = 7.5 kHz) the ratio is 0/0: both are outside
      // what a tap test uses.
      if (f < 50.0 || std::abs(F[k]) < 0.01 * std::abs(F[1])) continue;
      const double w = 2.0 * kPi * f;
      std::complex<double> h = X[k] / F[k];
      if (kind == ResponseKind::kVelocity) h /= std::complex<double>(0.0, w);
      if (kind == ResponseKind::kAcceleration) h /= -w * w;
      Eigen::VectorXd fk(1);
      fk << f;
      const std::complex<double> truth = receptance({kTool}, fk)[0];
      const double err = std::abs(h - truth) / std::abs(truth);
      const double bias = std::pow(kPi * f / (8.0 * kFs), 2) / 3.0;
      const double allowed = kBiasMargin * bias + kFloor;
      EXPECT_LT(err, allowed) << "f = " << f << " Hz";
      if (err / allowed > worst_ratio) {
        worst_ratio = err / allowed;
        worst_err = err;
        worst_f = f;
      }
    }
    std::printf("%s: worst error/allowed %.2f (error %.2e at %.0f Hz)\n",
                names[static_cast<int>(kind)], worst_ratio, worst_err, worst_f);
  }
}

TEST(ModalResponse, NoiseLevelsAreAsStated) {
  // 1 % noise, 32768 samples: the sample std is within 3 % of the stated one (its relative
  // standard error is 1/sqrt(2 n) = 0.4 %, and the response std is measured on a record
  // whose signal is subtracted exactly).
  constexpr double kRelTol = 0.03;
  const Eigen::Index n = 32768;
  TapSynthesisOptions clean;
  TapSynthesisOptions noisy;
  noisy.force_noise_fraction = 0.01;
  noisy.response_noise_fraction = 0.01;
  noisy.seed = 5;
  const std::vector<HammerPulse> pulses = {{0.1, 150.0, 2e-4}, {0.6, 100.0, 2e-4}};
  const TapRecord a =
      synthesize_tap_record({kTool}, pulses, kFs, n, ResponseKind::kAcceleration, clean);
  const TapRecord b =
      synthesize_tap_record({kTool}, pulses, kFs, n, ResponseKind::kAcceleration, noisy);
  const double force_std =
      std::sqrt((b.force_n - a.force_n).squaredNorm() / static_cast<double>(n));
  const double resp_rms = std::sqrt(a.response.squaredNorm() / static_cast<double>(n));
  const double resp_std =
      std::sqrt((b.response - a.response).squaredNorm() / static_cast<double>(n));
  EXPECT_NEAR(force_std / 1.5, 1.0, kRelTol);  // 1 % of the 150 N peak
  EXPECT_NEAR(resp_std / (0.01 * resp_rms), 1.0, kRelTol);
}

TEST(ModalResponse, BadInputIsRejected) {
  const Eigen::VectorXd f = Eigen::VectorXd::Zero(10);
  try {
    modal_response({}, f, kFs, ResponseKind::kDisplacement);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "modal_response: modes is empty: needs at least one mode");
  }
  try {
    half_sine_pulses({{0.0, -1.0, 2e-4}}, kFs, 10);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "pulses[0].peak_n = -1.000000: must be > 0");
  }
  EXPECT_THROW(synthesize_tap_record({kTool}, {}, -1.0, 10, ResponseKind::kDisplacement),
               InputError);
}

}  // namespace
}  // namespace frf
}  // namespace chatterlab
