// Method 2 of lobes.h: the zero-order approximation, Altintas & Budak, "Analytical prediction
// of stability lobes in milling", CIRP Annals 44/1 (1995) 357-362 ("AB1995"), re-derived with
// this project's signs (lobes.h; docs/lobes.md):
//   H0 = (N / 2 pi) int_entry^exit h(theta) dtheta        (AB1995 eqs 4-6: the time-averaged
//        directional matrix, Kt and Kr the means over the teeth)
//   F e^{i w t} = b (1 - e^{-i w tau}) H0 Phi(i w) F e^{i w t}    (AB1995 eqs 7-9)
// with Phi = diag(sum of x modes' 1/(k - m w^2 + i c w), same for y). With Lambda an eigenvalue
// of H0 Phi(i w) (AB1995 eq. 10 writes the eigenvalue of Phi A0 with the opposite sign and a
// factor -N Kt / 4 pi) the depth is b = 1 / ((1 - e^{-i w tau}) Lambda); b real requires
//   kappa = Lambda_I / Lambda_R = -sin(w tau) / (1 - cos(w tau)) = -cot(w tau / 2),
// and then b = 1 / (2 Lambda_R)   (AB1995 eq. 13 in this normalization; b > 0 needs
// Lambda_R > 0). The phase gives w tau = pi + 2 atan(kappa) + 2 pi k (AB1995 eqs 14-15:
// eps = pi - 2 psi, psi = atan kappa), n = 60 / (N tau), lobes k = 0, 1, 2, ...
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <limits>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"
#include "analysis/lobes/directional.h"
#include "analysis/lobes/lobes.h"
#include "analysis/milling/engagement.h"

namespace chatterlab {
namespace lobes {
namespace {

using cd = std::complex<double>;

cd receptance(const std::vector<ModalParameters>& modes, double w) {
  cd g = 0.0;
  for (const ModalParameters& p : modes) g += 1.0 / cd(p.k_N_m - p.m_kg * w * w, p.c_kg_s * w);
  return g;
}

void validate_options(const ZeroOrderOptions& o) {
  require_rule(o.lobes >= 1, "zoa.lobes", o.lobes, "must be >= 1");
  require_rule(o.frequencies >= 10, "zoa.frequencies", o.frequencies, "must be >= 10");
  require_rule(std::isfinite(o.min_frequency_hz) && o.min_frequency_hz >= 0.0,
               "zoa.min_frequency_hz", o.min_frequency_hz, "must be finite and >= 0");
  require_rule(std::isfinite(o.max_frequency_hz) &&
                   (o.max_frequency_hz == 0.0 || o.max_frequency_hz > o.min_frequency_hz),
               "zoa.max_frequency_hz", o.max_frequency_hz, "must be 0 or > min_frequency_hz");
}

}  // namespace

ZeroOrderResult zero_order(const LobesInput& in, const ZeroOrderOptions& o) {
  validate(in);
  validate_options(o);
  const auto start = std::chrono::steady_clock::now();
  const int N = in.teeth;
  double Kt = 0.0, Kr = 0.0;
  for (int p = 0; p < N; ++p) {
    Kt += in.Kt_N_m2[p] / N;
    Kr += in.Kr_N_m2[p] / N;
  }
  const milling::EngagementWindow w =
      milling::engagement_window(in.operation, in.radius_m, in.radial_immersion_m);
  const Eigen::Matrix2d H0 = (N / kTwoPi) * directional_integral(Kt, Kr, w.entry_rad, w.exit_rad);

  double fmin = o.min_frequency_hz, fmax = o.max_frequency_hz;
  if (fmax == 0.0) {
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (const auto* modes : {&in.x_modes, &in.y_modes}) {
      for (const ModalParameters& p : *modes) {
        const double fn = std::sqrt(p.k_N_m / p.m_kg) / kTwoPi;
        lo = std::min(lo, fn);
        hi = std::max(hi, fn);
      }
    }
    fmin = 0.3 * lo;
    fmax = 3.0 * hi;
  }

  ZeroOrderResult z;
  // Lobe curves: per lobe k and eigenvalue branch (ordered by imaginary part), consecutive
  // frequency points; kept as segments for the resampling.
  struct Pt {
    bool valid = false;
    double rpm = 0.0, depth = 0.0, hz = 0.0;
  };
  const int F = o.frequencies;
  std::vector<Pt> curve(static_cast<std::size_t>(o.lobes * 2 * F));
  auto at = [&](int k, int br, int j) -> Pt& {
    return curve[static_cast<std::size_t>((k * 2 + br) * F + j)];
  };
  for (int j = 0; j < F; ++j) {
    const double f = fmin + (fmax - fmin) * j / (F - 1);
    if (f <= 0.0) continue;
    const double wc = kTwoPi * f;
    Eigen::Matrix2cd G = Eigen::Matrix2cd::Zero();
    G(0, 0) = receptance(in.x_modes, wc);
    G(1, 1) = receptance(in.y_modes, wc);
    const Eigen::Matrix2cd M = H0.cast<cd>() * G;
    const cd tr = M.trace(), det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
    const cd root = std::sqrt(tr * tr / 4.0 - det);
    cd lam[2] = {tr / 2.0 + root, tr / 2.0 - root};
    if (lam[0].imag() < lam[1].imag()) std::swap(lam[0], lam[1]);
    for (int br = 0; br < 2; ++br) {
      const cd L = lam[br];
      if (!(L.real() > 0.0)) continue;
      const double depth = 1.0 / (2.0 * L.real());
      const double phase = kPi + 2.0 * std::atan(L.imag() / L.real());  // w tau mod 2 pi
      for (int k = 0; k < o.lobes; ++k) {
        const double tau = (phase + kTwoPi * k) / wc;
        Pt& p = at(k, br, j);
        p.valid = true;
        p.rpm = 60.0 / (N * tau);
        p.depth = depth;
        p.hz = f;
        z.raw.push_back({k, f, p.rpm, depth});
      }
    }
  }

  // Lower envelope on the requested speeds: linear interpolation along each lobe curve between
  // consecutive valid frequency points that bracket the speed.
  LobesResult& r = z.lobes;
  for (const double rpm : in.spindle_rpm) {
    SpeedResult s;
    s.spindle_rpm = rpm;
    double best = std::numeric_limits<double>::infinity(), best_hz = 0.0;
    for (int k = 0; k < o.lobes; ++k) {
      for (int br = 0; br < 2; ++br) {
        for (int j = 0; j + 1 < F; ++j) {
          const Pt& a = at(k, br, j);
          const Pt& b = at(k, br, j + 1);
          if (!a.valid || !b.valid) continue;
          if ((rpm - a.rpm) * (rpm - b.rpm) > 0.0 || a.rpm == b.rpm) continue;
          const double t = (rpm - a.rpm) / (b.rpm - a.rpm);
          const double depth = a.depth + t * (b.depth - a.depth);
          if (depth < best) {
            best = depth;
            best_hz = a.hz + t * (b.hz - a.hz);
          }
        }
      }
    }
    if (best <= in.max_depth_m) {
      s.limit_depth_m = best;
      s.chatter_hz = best_hz;
    }
    r.speeds.push_back(s);
  }
  r.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.summary.succeed();
  return z;
}

}  // namespace lobes
}  // namespace chatterlab
