#include "analysis/signal/harmonic_fit.h"

#include <Eigen/QR>
#include <cmath>
#include <limits>
#include <sstream>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"

namespace chatterlab {
namespace signal {

namespace {

// A harmonic's cycle count over the window is taken as whole within this many cycles: the
// DFT bin then differs from the least-squares c_h by about this fraction of the signal.
constexpr double kWholeCycleTolerance = 1e-9;

// h Omega t_k as an angle in [0, 2 pi): the cycle count h f0 k / fs reduced to its fraction
// before the 2 pi, so a long record keeps the phase to rounding of the fraction.
double harmonic_angle(double cycles_per_sample, Eigen::Index k) {
  const double cycles = cycles_per_sample * static_cast<double>(k);
  return kTwoPi * (cycles - std::floor(cycles));
}

void check_rate(double fs_hz) {
  require_rule(std::isfinite(fs_hz) && fs_hz > 0.0, "fs_hz", fs_hz, "must be finite and > 0");
}

}  // namespace

HarmonicFit fit_harmonics(const Eigen::Ref<const Eigen::VectorXd>& x, double fs_hz,
                          Eigen::Index begin, Eigen::Index end, double fundamental_hz,
                          const std::vector<int>& harmonics) {
  check_rate(fs_hz);
  require_rule(std::isfinite(fundamental_hz) && fundamental_hz > 0.0, "fundamental_hz",
               fundamental_hz, "must be finite and > 0");
  if (!(0 <= begin && begin < end && end <= x.size())) {
    std::ostringstream m;
    m << "window [" << begin << ", " << end << "): must satisfy 0 <= begin < end <= " << x.size()
      << " (the signal's length)";
    throw InputError(m.str());
  }
  for (std::size_t i = 0; i < harmonics.size(); ++i) {
    const std::string field = "harmonics[" + std::to_string(i) + "]";
    require_rule(harmonics[i] > 0, field, harmonics[i], "must be > 0");
    for (std::size_t j = 0; j < i; ++j)
      require_rule(harmonics[j] != harmonics[i], field, harmonics[i],
                   "repeats harmonics[" + std::to_string(j) + "]");
    // At or above the Nyquist frequency a harmonic aliases onto another column of the design.
    require_rule(harmonics[i] * fundamental_hz < 0.5 * fs_hz, field, harmonics[i],
                 "h fundamental_hz must be below fs_hz / 2");
  }
  for (Eigen::Index k = begin; k < end; ++k)
    if (!std::isfinite(x[k])) {
      std::ostringstream m;
      m << "x[" << k << "] = " << x[k] << ": must be finite";
      throw InputError(m.str());
    }

  const auto H = static_cast<Eigen::Index>(harmonics.size());
  const Eigen::Index N = end - begin;
  const Eigen::Index cols = 1 + 2 * H;
  HarmonicFit fit;
  fit.fundamental_hz = fundamental_hz;
  fit.harmonics = harmonics;
  fit.samples = N;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  fit.c0 = nan;
  fit.c = Eigen::VectorXcd::Constant(H, std::complex<double>(nan, nan));
  fit.residual_rms = nan;
  if (N < 2 * cols) {
    std::ostringstream m;
    m << "the window holds " << N << " samples, fewer than 2 (1 + 2 H) = " << 2 * cols;
    fit.summary.fail(m.str());
    return fit;
  }

  // Cycles per sample of each harmonic, h f0 / fs; the window holds whole periods of every
  // harmonic when N times it is an integer for each.
  Eigen::VectorXd per_sample(H);
  bool whole = true;
  for (Eigen::Index i = 0; i < H; ++i) {
    per_sample[i] = harmonics[static_cast<std::size_t>(i)] * fundamental_hz / fs_hz;
    const double cycles = per_sample[i] * static_cast<double>(N);
    if (std::abs(cycles - std::round(cycles)) > kWholeCycleTolerance) whole = false;
  }

  const auto x_w = x.segment(begin, N);
  if (whole) {
    // Whole periods of harmonics below Nyquist: the columns 1, cos(h Omega t), sin(h Omega t)
    // are orthogonal over the window and c_h is the DFT bin (2/N) sum x_k e^{-j h Omega t_k}
    // (format sec. 6 "sifs-cut" step 6, the bins of 003 sec. 6.1).
    fit.c0 = x_w.mean();
    for (Eigen::Index i = 0; i < H; ++i) {
      std::complex<double> sum = 0.0;
      for (Eigen::Index k = begin; k < end; ++k)
        sum += x[k] * std::polar(1.0, -harmonic_angle(per_sample[i], k));
      fit.c[i] = (2.0 / static_cast<double>(N)) * sum;
    }
  } else {
    // x ~ A p with columns 1, cos(h Omega t_k), -sin(h Omega t_k) and p = [c0, Re c_h, Im c_h]:
    // Re(c e^{j theta}) = Re(c) cos(theta) - Im(c) sin(theta).
    Eigen::MatrixXd A(N, cols);
    A.col(0).setOnes();
    for (Eigen::Index i = 0; i < H; ++i)
      for (Eigen::Index r = 0; r < N; ++r) {
        const double theta = harmonic_angle(per_sample[i], begin + r);
        A(r, 1 + 2 * i) = std::cos(theta);
        A(r, 2 + 2 * i) = -std::sin(theta);
      }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
    if (qr.rank() < cols) {
      std::ostringstream m;
      m << "the harmonics are not separable over the window (design rank " << qr.rank() << " of "
        << cols << ")";
      fit.summary.fail(m.str());
      return fit;
    }
    const Eigen::VectorXd p = qr.solve(x_w);
    fit.c0 = p[0];
    for (Eigen::Index i = 0; i < H; ++i) fit.c[i] = {p[1 + 2 * i], p[2 + 2 * i]};
  }

  double sum_sq = 0.0;
  for (Eigen::Index k = begin; k < end; ++k) {
    double model = fit.c0;
    for (Eigen::Index i = 0; i < H; ++i)
      model += std::real(fit.c[i] * std::polar(1.0, harmonic_angle(per_sample[i], k)));
    const double e = x[k] - model;
    sum_sq += e * e;
  }
  fit.residual_rms = std::sqrt(sum_sq / static_cast<double>(N));
  fit.summary.succeed();
  return fit;
}

void subtract_harmonics(const HarmonicFit& fit, double fs_hz, Eigen::Ref<Eigen::VectorXd> x) {
  check_rate(fs_hz);
  if (!fit.summary.ok())
    throw InputError("subtract_harmonics: the fit did not succeed (" + fit.summary.message + ")");
  const auto H = static_cast<Eigen::Index>(fit.harmonics.size());
  Eigen::VectorXd per_sample(H);
  for (Eigen::Index i = 0; i < H; ++i)
    per_sample[i] = fit.harmonics[static_cast<std::size_t>(i)] * fit.fundamental_hz / fs_hz;
  // 003 eq. 3-6 as corrected (notes/003.md sec. 2): the air-window fit extrapolated
  // phase-coherently over the whole record.
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    double model = fit.c0;
    for (Eigen::Index i = 0; i < H; ++i)
      model += std::real(fit.c[i] * std::polar(1.0, harmonic_angle(per_sample[i], k)));
    x[k] -= model;
  }
}

}  // namespace signal
}  // namespace chatterlab
