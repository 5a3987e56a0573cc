#include "analysis/signal/harmonic_fit.h"

#include <Eigen/Cholesky>
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

// The phasor recurrences are re-anchored with an exact angle every this many samples: the
// rounding of the products then stays below ~1e-13.
constexpr Eigen::Index kAnchorSamples = 256;
// Smallest reciprocal condition number (1-norm estimate) of the Jacobi-scaled Gram matrix for
// the normal equations; below it the QR of the design is used.
constexpr double kMinGramRcond = 1e-9;

// b_i = sum_{k=begin}^{end-1} x_k e^{-j 2 pi per_sample_i k}.
Eigen::VectorXcd weighted_phasor_sums(const Eigen::Ref<const Eigen::VectorXd>& x,
                                      Eigen::Index begin, Eigen::Index end,
                                      const Eigen::VectorXd& per_sample) {
  Eigen::VectorXcd b = Eigen::VectorXcd::Zero(per_sample.size());
  for (Eigen::Index i = 0; i < per_sample.size(); ++i) {
    const std::complex<double> step = std::polar(1.0, -kTwoPi * per_sample[i]);
    std::complex<double> sum = 0.0, z = 0.0;
    for (Eigen::Index k = begin; k < end; ++k) {
      z = ((k - begin) % kAnchorSamples == 0) ? std::polar(1.0, -harmonic_angle(per_sample[i], k))
                                              : z * step;
      sum += x[k] * z;
    }
    b[i] = sum;
  }
  return b;
}

// y[r] += sign Re(c_i e^{j 2 pi per_sample_i (first + r)}) for every r of y.
void add_harmonics(const Eigen::VectorXcd& c, const Eigen::VectorXd& per_sample, Eigen::Index first,
                   double sign, Eigen::Ref<Eigen::VectorXd> y) {
  for (Eigen::Index i = 0; i < per_sample.size(); ++i) {
    const std::complex<double> step = std::polar(1.0, kTwoPi * per_sample[i]);
    const std::complex<double> ci = sign * c[i];
    std::complex<double> z = 0.0;
    for (Eigen::Index r = 0; r < y.size(); ++r) {
      z = (r % kAnchorSamples == 0) ? std::polar(1.0, harmonic_angle(per_sample[i], first + r))
                                    : z * step;
      y[r] += ci.real() * z.real() - ci.imag() * z.imag();
    }
  }
}

// D(m) = sum_{k=begin}^{begin+N-1} e^{j 2 pi m f1 k} (f1 = fundamental / fs in cycles per
// sample), the geometric sum z^begin (1 - z^N) / (1 - z), N when z = 1.
std::complex<double> geometric_sum(int m, double f1, Eigen::Index begin, Eigen::Index N) {
  const double per = m * f1;
  const double frac = per - std::round(per);
  if (std::abs(frac) * static_cast<double>(N) < 1e-12) return static_cast<double>(N);
  const std::complex<double> z = std::polar(1.0, kTwoPi * frac);
  const std::complex<double> zb = std::polar(1.0, harmonic_angle(per, begin));
  const std::complex<double> zn = std::polar(1.0, harmonic_angle(per, N));
  return zb * (1.0 - zn) / (1.0 - z);
}

// A^T A of the design with columns 1, cos(h_i theta_k), -sin(h_i theta_k), theta_k =
// 2 pi f1 k: cos a cos b = (cos(a - b) + cos(a + b)) / 2, sin a sin b = (cos(a - b) - cos(a + b))
// / 2, cos a sin b = (sin(a + b) - sin(a - b)) / 2, with sum cos(m theta) = Re D(m) and
// sum sin(m theta) = Im D(m).
Eigen::MatrixXd gram_matrix(const std::vector<int>& h, double f1, Eigen::Index begin,
                            Eigen::Index N) {
  const auto H = static_cast<Eigen::Index>(h.size());
  Eigen::MatrixXd G(1 + 2 * H, 1 + 2 * H);
  const auto D = [&](int m) { return geometric_sum(m, f1, begin, N); };
  G(0, 0) = static_cast<double>(N);
  for (Eigen::Index i = 0; i < H; ++i) {
    const std::complex<double> di = D(h[static_cast<std::size_t>(i)]);
    G(0, 1 + 2 * i) = G(1 + 2 * i, 0) = di.real();
    G(0, 2 + 2 * i) = G(2 + 2 * i, 0) = -di.imag();
    for (Eigen::Index j = i; j < H; ++j) {
      const int a = h[static_cast<std::size_t>(i)], c = h[static_cast<std::size_t>(j)];
      const std::complex<double> dm = D(a - c), dp = D(a + c);
      const double cc = 0.5 * (dm.real() + dp.real());
      const double ss = 0.5 * (dm.real() - dp.real());
      // cos(a) (-sin(c)) and (-sin(a)) cos(c): sin(a - c) = Im D(a - c).
      const double cs = -0.5 * (dp.imag() - dm.imag());  // cos a * (-sin c)
      const double sc = -0.5 * (dp.imag() + dm.imag());  // (-sin a) * cos c
      G(1 + 2 * i, 1 + 2 * j) = G(1 + 2 * j, 1 + 2 * i) = cc;
      G(2 + 2 * i, 2 + 2 * j) = G(2 + 2 * j, 2 + 2 * i) = ss;
      G(1 + 2 * i, 2 + 2 * j) = G(2 + 2 * j, 1 + 2 * i) = cs;
      G(2 + 2 * i, 1 + 2 * j) = G(1 + 2 * j, 2 + 2 * i) = sc;
    }
  }
  return G;
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
  // b_h = sum_k x_k e^{-j h Omega t_k} over the window, by phasor recurrences (O(N H) complex
  // products, no sincos per sample).
  const Eigen::VectorXcd b = weighted_phasor_sums(x, begin, end, per_sample);
  if (whole) {
    // Whole periods of harmonics below Nyquist: the columns 1, cos(h Omega t), sin(h Omega t)
    // are orthogonal over the window and c_h is the DFT bin (2/N) sum x_k e^{-j h Omega t_k}
    // (format sec. 6 "sifs-cut" step 6, the bins of 003 sec. 6.1).
    fit.c0 = x_w.mean();
    for (Eigen::Index i = 0; i < H; ++i) fit.c[i] = (2.0 / static_cast<double>(N)) * b[i];
  } else {
    // x ~ A p with columns 1, cos(h Omega t_k), -sin(h Omega t_k) and p = [c0, Re c_h, Im c_h]:
    // Re(c e^{j theta}) = Re(c) cos(theta) - Im(c) sin(theta). Normal equations A^T A p = A^T x
    // with A^T x = [sum x, Re b_h, Im b_h] and A^T A in closed form from the geometric sums
    // D(m) = sum_k e^{j m Omega_1 t_k} (products of sinusoids are sums of sinusoids at the sum
    // and difference harmonics): O(H^2) instead of a QR of the N x (1 + 2H) design. A Gram matrix
    // too ill-conditioned for that (a window of a fraction of a period) falls back to the QR.
    const Eigen::MatrixXd G = gram_matrix(harmonics, fundamental_hz / fs_hz, begin, N);
    Eigen::VectorXd rhs(cols);
    rhs[0] = x_w.sum();
    for (Eigen::Index i = 0; i < H; ++i) {
      rhs[1 + 2 * i] = b[i].real();
      rhs[2 + 2 * i] = b[i].imag();
    }
    // Jacobi-scaled so the condition estimate reflects the design, not the column norms.
    const Eigen::VectorXd d = G.diagonal().cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd Gs = d.asDiagonal() * G * d.asDiagonal();
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(Gs);
    const double rcond = ldlt.info() == Eigen::Success ? ldlt.rcond() : 0.0;
    Eigen::VectorXd p;
    if (rcond > kMinGramRcond) {
      p = d.asDiagonal() * ldlt.solve(d.asDiagonal() * rhs);
    } else {
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
      p = qr.solve(x_w);
    }
    fit.c0 = p[0];
    for (Eigen::Index i = 0; i < H; ++i) fit.c[i] = {p[1 + 2 * i], p[2 + 2 * i]};
  }

  Eigen::VectorXd model = Eigen::VectorXd::Constant(N, fit.c0);
  add_harmonics(fit.c, per_sample, begin, 1.0, model);
  const double sum_sq = (x_w - model).squaredNorm();
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
  x.array() -= fit.c0;
  add_harmonics(fit.c, per_sample, 0, -1.0, x);
}

}  // namespace signal
}  // namespace chatterlab
