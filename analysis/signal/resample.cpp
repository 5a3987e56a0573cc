#include "analysis/signal/resample.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <sstream>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"

namespace chatterlab {
namespace signal {

namespace {

// Rates are compared in micro-hertz (the header's 1e-6 Hz rounding).
constexpr double kMicroHzPerHz = 1e6;

// Modified Bessel function of the first kind, order 0, by its power series
// sum_k ((x/2)^k / k!)^2: every term is positive, so it converges without cancellation; the
// terms fall below 1e-17 of the sum for the beta <= ~50 a Kaiser window uses.
double bessel_i0(double x) {
  const double q = 0.25 * x * x;
  double term = 1.0, sum = 1.0;
  for (int k = 1; k < 500 && term > 1e-17 * sum; ++k) {
    term *= q / (static_cast<double>(k) * static_cast<double>(k));
    sum += term;
  }
  return sum;
}

}  // namespace

RationalResampler::RationalResampler(double from_hz, double to_hz, const ResampleOptions& o)
    : from_hz_(from_hz), to_hz_(to_hz) {
  require_rule(std::isfinite(from_hz) && from_hz > 0.0, "from_hz", from_hz,
               "must be finite and > 0");
  require_rule(std::isfinite(to_hz) && to_hz > 0.0, "to_hz", to_hz, "must be finite and > 0");
  require_rule(o.cutoff_fraction > 0.0 && o.cutoff_fraction <= 1.0, "resample.cutoff_fraction",
               o.cutoff_fraction, "must be in (0, 1]");
  require_rule(std::isfinite(o.kaiser_beta) && o.kaiser_beta >= 0.0, "resample.kaiser_beta",
               o.kaiser_beta, "must be finite and >= 0");
  require_rule(o.half_length_per_phase >= 1, "resample.half_length_per_phase",
               o.half_length_per_phase, "must be >= 1");
  require_rule(o.max_factor >= 1, "resample.max_factor", o.max_factor, "must be >= 1");
  // Rates up to ~9e12 Hz fit an int64 in micro-hertz; far beyond any acquisition.
  require_rule(from_hz * kMicroHzPerHz < 9e18, "from_hz", from_hz, "must be < 9e12");
  require_rule(to_hz * kMicroHzPerHz < 9e18, "to_hz", to_hz, "must be < 9e12");
  const auto from_u = static_cast<std::int64_t>(std::llround(from_hz * kMicroHzPerHz));
  const auto to_u = static_cast<std::int64_t>(std::llround(to_hz * kMicroHzPerHz));
  require_rule(from_u > 0, "from_hz", from_hz, "must be >= 1e-6 Hz");
  require_rule(to_u > 0, "to_hz", to_hz, "must be >= 1e-6 Hz");
  const std::int64_t g = std::gcd(from_u, to_u);
  const std::int64_t up_r = to_u / g, down_r = from_u / g;
  if (up_r > o.max_factor || down_r > o.max_factor) {
    std::ostringstream m;
    m << "resampling " << from_hz << " Hz -> " << to_hz << " Hz: the ratio reduces to " << up_r
      << "/" << down_r << ", above resample.max_factor = " << o.max_factor;
    throw InputError(m.str());
  }
  up_ = static_cast<int>(up_r);
  down_ = static_cast<int>(down_r);
  if (identity()) return;

  // Kaiser-windowed sinc at the up-sampled rate from_hz up: cut-off at cutoff_fraction of the
  // lower Nyquist frequency, min(from, to) / 2 = (from up / 2) / max(up, down), i.e.
  // fc = cutoff_fraction / (2 max(up, down)) cycles per up-sampled sample.
  const int wider = std::max(up_, down_);
  half_ = static_cast<Eigen::Index>(o.half_length_per_phase) * wider;
  const double fc = o.cutoff_fraction / (2.0 * wider);
  taps_.resize(2 * half_ + 1);
  const double i0_beta = bessel_i0(o.kaiser_beta);
  for (Eigen::Index n = 0; n <= 2 * half_; ++n) {
    const double m = static_cast<double>(n - half_);
    const double r = m / static_cast<double>(half_);
    const double window =
        bessel_i0(o.kaiser_beta * std::sqrt(std::max(0.0, 1.0 - r * r))) / i0_beta;
    const double sinc = n == half_ ? 1.0 : std::sin(kTwoPi * fc * m) / (kTwoPi * fc * m);
    taps_[n] = 2.0 * fc * sinc * window;
  }
  // Gain up: each input sample is followed by up - 1 zeros, so the DC gain of the prototype
  // must be up for a unit DC gain per output.
  taps_ *= static_cast<double>(up_) / taps_.sum();
}

Eigen::Index RationalResampler::output_size(Eigen::Index n) const {
  require_rule(n >= 0, "n", n, "must be >= 0");
  return (n * up_ + down_ - 1) / down_;
}

Eigen::VectorXd RationalResampler::apply(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  if (identity()) return x;
  const Eigen::Index n = x.size();
  const Eigen::Index out_n = output_size(n);
  Eigen::VectorXd y(out_n);
  const Eigen::Index up_n = up_, down_n = down_;
  // Up-sampled index J = m down is the output time m / to_hz. With the zero-stuffed input
  // u[k up] = x[k] and the filter centred on J (delay half_ removed),
  //   y[m] = sum_k taps[J + half - k up] x[k],   J - half <= k up <= J + half,
  // and the record extended by zeros outside [0, n).
  for (Eigen::Index m = 0; m < out_n; ++m) {
    const Eigen::Index J = m * down_n;
    const Eigen::Index lo = J - half_;
    const Eigen::Index k_first = lo <= 0 ? 0 : (lo + up_n - 1) / up_n;
    const Eigen::Index k_last = std::min(n - 1, (J + half_) / up_n);
    double acc = 0.0;
    for (Eigen::Index k = k_first, t = J + half_ - k_first * up_n; k <= k_last; ++k, t -= up_n)
      acc += taps_[t] * x[k];
    y[m] = acc;
  }
  return y;
}

}  // namespace signal
}  // namespace chatterlab
