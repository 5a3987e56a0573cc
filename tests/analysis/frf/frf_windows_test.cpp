// Force and exponential windows, and undoing the exponential window's damping.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>

#include "analysis/common/constants.h"
#include "analysis/frf/modal_response.h"
#include "analysis/frf/windows.h"
#include "analysis/signal/fft.h"

namespace chatterlab {
namespace frf {
namespace {

TEST(Windows, ForceWindowKeepsThePulseAndZeroesTheRest) {
  // Pulse on samples [40, 45): margin = 5 samples (factor 1), flat on [35, 50), cosine tapers
  // of 5 samples on [30, 35) and [50, 55), zero elsewhere.
  const Eigen::VectorXd w = force_window(100, 40, 45, 1.0);
  for (Eigen::Index i = 0; i < 100; ++i) {
    if (i < 30 || i >= 55) {
      EXPECT_EQ(w[i], 0.0) << i;
    } else if (i >= 35 && i < 50) {
      EXPECT_EQ(w[i], 1.0) << i;
    } else {
      EXPECT_GT(w[i], 0.0) << i;
      EXPECT_LT(w[i], 1.0) << i;
    }
  }
  // Taper: w[50 + j] = (1 + cos(pi (j + 1) / 6)) / 2, symmetric with the leading one.
  for (int j = 0; j < 5; ++j) {
    EXPECT_NEAR(w[50 + j], 0.5 * (1.0 + std::cos(kPi * (j + 1) / 6.0)), 1e-15);
    EXPECT_NEAR(w[34 - j], w[50 + j], 1e-15);
  }
  // A pulse at the record start: the window is clipped to the record.
  const Eigen::VectorXd w0 = force_window(20, 1, 3, 1.0);
  EXPECT_EQ(w0[0], 1.0);
  EXPECT_THROW(force_window(20, 5, 25, 1.0), InputError);
}

TEST(Windows, ExponentialWindowValues) {
  const Eigen::VectorXd w = exponential_window(10, 2, 0.01, 1000.0);  // tau = 10 samples
  for (Eigen::Index i = 0; i < 10; ++i) {
    EXPECT_NEAR(w[i], std::exp(-(static_cast<double>(i) - 2.0) / 10.0), 1e-15);
  }
  EXPECT_TRUE(exponential_window(5, 0, 0.0, 1000.0).isOnes());  // tau = 0: no window
  EXPECT_THROW(exponential_window(5, 0, -1.0, 1000.0), InputError);
}

TEST(Windows, UndoExponentialWindowInvertsThePoleShift) {
  // Closed form: a mode (fn, zeta) under exp(-t/tau) has poles -zeta wn - 1/tau +- j wd,
  // i.e. wn'^2 = wd^2 + (zeta wn + 1/tau)^2 and zeta' = (zeta wn + 1/tau) / wn'.
  constexpr double kTol = 1e-12;  // rounding
  const double fn = 891.8, zeta = 0.002, tau = 0.05;
  const double wn = 2.0 * kPi * fn;
  const double wd = wn * std::sqrt(1.0 - zeta * zeta);
  const double sigma_w = zeta * wn + 1.0 / tau;
  const double wn_w = std::sqrt(wd * wd + sigma_w * sigma_w);
  const PoleShift back = undo_exponential_window(wn_w / (2.0 * kPi), sigma_w / wn_w, tau);
  EXPECT_NEAR(back.fn_hz / fn, 1.0, kTol);
  EXPECT_NEAR(back.zeta / zeta, 1.0, kTol);
  // The usual first-order rule zeta = zeta' - 1/(tau wn) agrees to O(zeta'^2).
  EXPECT_NEAR(sigma_w / wn_w - 1.0 / (tau * wn_w), zeta, 1e-4 * zeta);
  const PoleShift same = undo_exponential_window(fn, zeta, 0.0);
  EXPECT_EQ(same.fn_hz, fn);
  EXPECT_EQ(same.zeta, zeta);
}

TEST(Windows, ExponentialWindowShiftsTheFrfArgument) {
  // H_w(jw) = H(jw + 1/tau) for exp(-t/tau) on both channels: the windowed DFT ratio of a
  // decayed single-mode record equals the receptance with poles moved by -1/tau.
  // Generator accuracy near the mode: 3e-4 floor + 6e-5 hold bias (modal_response_test).
  constexpr double kRelTol = 5e-4;
  const double fs = 25600.0;
  const Mode mode = mode_from_modal(891.8, 0.01, 0.03134);
  const Eigen::Index n = 16384;
  const TapRecord rec =
      synthesize_tap_record({mode}, {{0.01, 100.0, 2e-4}}, fs, n, ResponseKind::kDisplacement);
  const double tau = 0.02;
  const Eigen::VectorXd w = exponential_window(n, 256, tau, fs);
  const Eigen::VectorXd fw = rec.force_n.cwiseProduct(w);
  const Eigen::VectorXd xw = rec.response.cwiseProduct(w);
  signal::RealFft fft(n);
  const Eigen::VectorXcd F = fft.forward(fw);
  const Eigen::VectorXcd X = fft.forward(xw);
  const double wn = 2.0 * kPi * mode.fn_hz;
  double worst = 0.0;
  for (Eigen::Index k = 500; k <= 650; ++k) {  // 781 .. 1016 Hz around the mode
    const std::complex<double> s(1.0 / tau, 2.0 * kPi * static_cast<double>(k) * fs / n);
    const std::complex<double> shifted =
        (1.0 / mode.m_kg) / (s * s + 2.0 * mode.zeta * wn * s + wn * wn);
    worst = std::max(worst, std::abs(X[k] / F[k] - shifted) / std::abs(shifted));
    EXPECT_NEAR(std::abs(X[k] / F[k] - shifted) / std::abs(shifted), 0.0, kRelTol) << k;
  }
  std::printf("windowed FRF vs shifted-pole receptance: worst relative error %.2e\n", worst);
}

}  // namespace
}  // namespace frf
}  // namespace chatterlab
