#include "analysis/sysid/gavish_donoho.h"

#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"

namespace chatterlab {
namespace sysid {
namespace {

void require_ratio(double b) {
  require_rule(std::isfinite(b) && b > 0.0 && b <= 1.0, "aspect ratio b", b,
               "must be in (0, 1] (rows / columns of the smaller over the larger side)");
}

// Mass of the Marchenko-Pastur law of ratio b on [a, x], a = (1 - sqrt b)^2.
// With t = a + (c - a) sin^2(th), dt = 2 (c - a) sin th cos th dth and
// sqrt((c - t)(t - a)) = (c - a) sin th cos th, so the integrand becomes
// 2 (c - a)^2 sin^2 th cos^2 th / (2 pi b t): smooth on [0, th_x]. Composite Gauss-Legendre
// (5 points, 64 panels) integrates it to rounding.
double mp_mass(double b, double x) {
  const double sb = std::sqrt(b);
  const double a = (1.0 - sb) * (1.0 - sb);
  const double c = (1.0 + sb) * (1.0 + sb);
  const double th_x = std::asin(std::sqrt(std::fmin(1.0, std::fmax(0.0, (x - a) / (c - a)))));
  static const double kNodes[5] = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                   0.5384693101056831, 0.9061798459386640};
  static const double kWeights[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                     0.4786286704993665, 0.2369268850561891};
  const int panels = 64;
  const double h = th_x / panels;
  double sum = 0.0;
  for (int p = 0; p < panels; ++p) {
    const double mid = (p + 0.5) * h;
    for (int q = 0; q < 5; ++q) {
      const double th = mid + 0.5 * h * kNodes[q];
      const double s = std::sin(th);
      const double co = std::cos(th);
      const double t = a + (c - a) * s * s;
      sum +=
          0.5 * h * kWeights[q] * 2.0 * (c - a) * (c - a) * s * s * co * co / (2.0 * kPi * b * t);
    }
  }
  return sum;
}

}  // namespace

double gavish_donoho_lambda(double b) {
  require_ratio(b);
  return std::sqrt(2.0 * (b + 1.0) + 8.0 * b / ((b + 1.0) + std::sqrt(b * b + 14.0 * b + 1.0)));
}

double marchenko_pastur_median(double b) {
  require_ratio(b);
  const double sb = std::sqrt(b);
  double lo = (1.0 - sb) * (1.0 - sb);
  double hi = (1.0 + sb) * (1.0 + sb);
  while (hi - lo > 1e-13) {
    const double mid = 0.5 * (lo + hi);
    if (mp_mass(b, mid) < 0.5) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

double gavish_donoho_omega(double b) {
  return gavish_donoho_lambda(b) / std::sqrt(marchenko_pastur_median(b));
}

}  // namespace sysid
}  // namespace chatterlab
