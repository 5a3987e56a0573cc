// Spread of a once-per-revolution sequence x_n about its slow trend, revolution by revolution:
// the statistic of the bifurcation criterion (docs/bifurcation.md sec. 2).
//
// A chatter-free run is a period-one orbit: x_n is the same point every revolution, drifting
// slowly as the depth changes, plus measurement noise (000 sec. 5.2: "the once-per-revolution
// points lie in close vicinity to each other"). Chatter spreads x_n (period-two or -four
// clusters, a quasi-periodic ellipse, a cloud). The statistic removes the drift with a local
// quadratic and measures what is left with an order statistic, robust to glitches:
//
//   window J_n: the W revolutions centred on n (shifted inward at the ends of the run),
//   fit x_k ~ q_n(k), a quadratic in k, over J_n by least squares, then again without the
//   points more than 3 robust stds off the first fit (a glitch of many noise stds would
//   otherwise tilt the trend and lift every residual),
//   r_k = x_k - q_n(k),
//   s_n = sqrt(W / (W - 3)) q75_{k in J_n} |r_k| / 1.1503,
//
// q75 the upper quartile (kSpreadQuantile) and 1.1503 = Phi^-1(7/8) the upper quartile of
// |N(0,1)|, so that white noise of std sigma gives s_n ~ sigma with a relative std of
// 0.914 / sqrt(W) (the median's would be 1.166 / sqrt(W)). x_n = trend + A cos(2 pi nu n + phi)
// gives s_n ~ 0.82 A for a rotation number nu at least ~1.5 / W from an integer (the upper
// quartile of |cos| of a uniform phase is cos(pi/8) = 0.924); alternating clusters +-A give
// s_n ~ 0.90 A.
//
// Why a quadratic: the period-one orbit of a simulated incline bends most near zero depth (it
// rose from 0 to 7e-6 m over the first 0.4 mm in a 000 sec. 5.1 run); a local line left 9e-9 m
// of that curvature, above the 1 nm floor of noise-free data, a quadratic 2e-10 m. The price is
// a slightly wider blind band for slow chatter (docs sec. 2).
// Why the upper quartile and not the median (MAD): the median ignores any pattern that keeps
// half of its points near the trend, such as four clusters (A, 0, -A, 0), common when a
// period-four orbit has a phase near 0; the upper quartile sees any pattern with more than a
// quarter of its points off the trend, still ignores up to a quarter of glitches per window,
// and has a smaller variance on noise. A burst of chatter is seen once it fills a quarter of a
// window: s_n rises about W/4 revolutions before a step in amplitude.
#pragma once

#include <Eigen/Core>

namespace chatterlab {
namespace dynamics {

// The order statistic of |r| that s_n is built on: the upper quartile.
constexpr double kSpreadQuantile = 0.75;
// Degree of the local trend (a quadratic).
constexpr int kTrendDegree = 2;

struct LocalSpread {
  // s_n, in the unit of x (m for a deflection), one per revolution.
  Eigen::VectorXd spread;
  // Standardised central residual e_n = r_n / sqrt(1 - h_n): the residual of x_n from the trend
  // of its own window, divided by its leverage factor (h_n: the diagonal of the hat matrix of
  // the window's quadratic fit at n), so that white noise of std sigma gives e_n of std sigma.
  // Nearly independent from one revolution to the next; the noise-floor estimate pools these.
  Eigen::VectorXd central_residual;
};

// @param x                   once-per-revolution samples x_n, finite, at least W of them
// @param window_revolutions  W, odd, >= 5
// @throws InputError if W is even or < 5, if x has fewer than W samples or a non-finite one
LocalSpread local_spread(const Eigen::Ref<const Eigen::VectorXd>& x, int window_revolutions);

// The same statistic over the whole of x (one window of M = x.size() values, the quadratic
// fitted and trimmed as above; the quartile interpolated between order statistics at
// 0.75 (M - 1)):  sqrt(M / (M - 3)) q75|x_k - q(k)| / 1.1503.
// Residuals of the trend are also returned through `residual` when it is not null.
// @param x  at least 4 finite values (not checked beyond the size)
// @throws InputError if x has fewer than 4 values
double detrended_spread(const Eigen::Ref<const Eigen::VectorXd>& x,
                        Eigen::VectorXd* residual = nullptr);

// Robust std of values centred on zero, from their upper quartile: q75|v| / 1.1503 (white
// noise of std sigma gives sigma). Sees any pattern with more than a quarter of its values away
// from zero, which a median would miss when half of them sit at zero.
// @throws InputError if v is empty
double quartile_scale(const Eigen::Ref<const Eigen::VectorXd>& v);

}  // namespace dynamics
}  // namespace chatterlab
