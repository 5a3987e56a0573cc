#include "analysis/milling/chip_numerical.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "analysis/common/constants.h"
#include "analysis/milling/engagement.h"

namespace chatterlab {
namespace milling {

namespace {

// The fast search falls back to the plain one when its bound is too loose to help: the band
// must stay within a quarter of a revolution (and the small-angle argument within 30 degrees).
constexpr double kMaxBandSine = 0.5;
// asin(x) <= x asin(1/2) / (1/2) for 0 <= x <= 1/2 (asin is convex there): a cheap upper bound.
constexpr double kAsinSlope = 1.0471975511965977;  // (pi / 6) / (1 / 2)

double cross(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

// The cutting tooth at step k: unit direction e and the centre c_k (feed taken relative to k).
struct Tooth {
  double ex, ey;  // e = (sin theta_p, cos theta_p)
  double cx, cy;  // deflection d_k (the feed term cancels in point - centre)
};

// Position of tooth q's tip at step i relative to the current tool centre.
struct PathPoint {
  double px, py;  // P - c
  double dist;    // distance to the tooth line
  double s;       // foot of the perpendicular along e
};

// a: angle index of tooth q at step i (tooth_angle_index), passed in to keep the modulo out of
// the inner loop.
inline PathPoint path_point(const ToothPathGeometry& g, const ToothPathHistory& h, const Tooth& t,
                            std::int64_t k, std::int64_t i, int a) {
  PathPoint p;
  p.px = h.x(i) - t.cx - g.feed_per_step_m * static_cast<double>(k - i) +
         g.radius_m * g.sin_theta[static_cast<std::size_t>(a)];
  p.py = h.y(i) - t.cy + g.radius_m * g.cos_theta[static_cast<std::size_t>(a)];
  p.dist = std::abs(cross(p.px, p.py, t.ex, t.ey));
  p.s = p.px * t.ex + p.py * t.ey;
  return p;
}

// Accumulates candidates and the smallest candidate chip.
struct Candidates {
  double min_chip;
  int count = 0;
};

// Middle point m of three consecutive path points (prev, m, next): candidate test and
// intersection of the tooth line with the line through m and its assisting point.
inline void consider(const ToothPathGeometry& g, const Tooth& t, const PathPoint& prev,
                     const PathPoint& m, const PathPoint& next, Candidates& c) {
  if (!(m.dist <= prev.dist && m.dist < next.dist)) return;  // local minimum along the path
  if (!(m.dist < g.candidate_distance_m) || !(m.s > 0.0)) return;
  const PathPoint& assist = next.dist < prev.dist ? next : prev;
  const double dx = assist.px - m.px;
  const double dy = assist.py - m.py;
  const double den = cross(t.ex, t.ey, dx, dy);
  // Surface line parallel to the tooth: no intersection (000 sec. 2.3).
  if (!(std::abs(den) > 1e-12 * (std::abs(dx) + std::abs(dy)))) return;
  const double s = cross(m.px, m.py, dx, dy) / den;
  ++c.count;
  c.min_chip = std::min(c.min_chip, g.radius_m - s);
}

// Scans path points of tooth q at steps i0..i1 (ascending), testing the interior ones.
inline std::int64_t scan(const ToothPathGeometry& g, const ToothPathHistory& h, const Tooth& t,
                         std::int64_t k, int q, std::int64_t i0, std::int64_t i1, Candidates& c) {
  if (i1 - i0 < 2) return i1 >= i0 ? i1 - i0 + 1 : 0;
  const int S = g.steps_per_revolution;
  int a = tooth_angle_index(g, i0, q);
  const auto next_angle = [S](int x) { return x + 1 == S ? 0 : x + 1; };
  PathPoint prev = path_point(g, h, t, k, i0, a);
  a = next_angle(a);
  PathPoint mid = path_point(g, h, t, k, i0 + 1, a);
  for (std::int64_t i = i0 + 2; i <= i1; ++i) {
    a = next_angle(a);
    const PathPoint next = path_point(g, h, t, k, i, a);
    consider(g, t, prev, mid, next, c);
    prev = mid;
    mid = next;
  }
  return i1 - i0 + 1;
}

// Original surface candidate and tooth set-up. Returns false when the tip is not beyond the
// original surface (no search, 000 sec. 2.3).
inline bool start(const ToothPathGeometry& g, const ChipSearchQuery& q, Tooth& t, Candidates& c) {
  const int a = tooth_angle_index(g, q.step, q.tooth);
  t.ex = g.sin_theta[static_cast<std::size_t>(a)];
  t.ey = g.cos_theta[static_cast<std::size_t>(a)];
  t.cx = q.deflection_m.x();
  t.cy = q.deflection_m.y();
  const double toward = g.side * t.ey;  // component of e towards the workpiece side
  if (!(toward > 0.0)) return false;
  // Along the ray, the surface y = side (r - r_i) is at s = (side (r - r_i) - y_k) / e_y.
  const double s_surface = (g.side * g.original_surface_m - t.cy) / t.ey;
  c.min_chip = g.radius_m - s_surface;
  return c.min_chip > 0.0;
}

ChipSearchResult finish(const Candidates& c, std::int64_t points) {
  ChipSearchResult r;
  r.candidates = c.count;
  r.points = points;
  r.cutting = c.min_chip > 0.0;
  r.chip_m = r.cutting ? c.min_chip : 0.0;
  return r;
}

}  // namespace

ToothPathGeometry tooth_path_geometry(const SimulationOptions& o) {
  validate(o);
  ToothPathGeometry g;
  g.teeth = o.teeth;
  g.steps_per_tooth = o.steps_per_tooth;
  g.steps_per_revolution = o.teeth * o.steps_per_tooth;
  g.radius_m = o.radius_m;
  g.feed_per_step_m = o.feed_per_tooth_m / o.steps_per_tooth;
  g.original_surface_m = o.radius_m - o.radial_immersion_m;
  g.side = workpiece_side(o.operation);
  const double dtheta = kTwoPi / g.steps_per_revolution;
  g.candidate_distance_m = 2.0 * o.radius_m * dtheta;
  g.sin_theta.resize(static_cast<std::size_t>(g.steps_per_revolution));
  g.cos_theta.resize(static_cast<std::size_t>(g.steps_per_revolution));
  for (int a = 0; a < g.steps_per_revolution; ++a) {
    g.sin_theta[static_cast<std::size_t>(a)] = std::sin(a * dtheta);
    g.cos_theta[static_cast<std::size_t>(a)] = std::cos(a * dtheta);
  }
  return g;
}

ToothPathHistory::ToothPathHistory(int steps_per_revolution, std::int64_t capacity_steps,
                                   const Eigen::Vector2d& rest_deflection_m,
                                   std::int64_t first_step)
    : spr_(steps_per_revolution), next_(first_step) {
  std::int64_t cap = 1;
  while (cap < capacity_steps) cap <<= 1;
  mask_ = cap - 1;
  x_.assign(static_cast<std::size_t>(cap), rest_deflection_m.x());
  y_.assign(static_cast<std::size_t>(cap), rest_deflection_m.y());
  rev_max2_.assign(static_cast<std::size_t>(cap / spr_ + 3), rest_deflection_m.squaredNorm());
}

std::size_t ToothPathHistory::revolution_slot(std::int64_t step) const {
  const std::int64_t n = static_cast<std::int64_t>(rev_max2_.size());
  const std::int64_t rev = step >= 0 ? step / spr_ : -((-step + spr_ - 1) / spr_);
  const std::int64_t s = rev % n;
  return static_cast<std::size_t>(s < 0 ? s + n : s);
}

double ToothPathHistory::max_deflection_since(std::int64_t first_step) const {
  double m2 = 0.0;
  // Every revolution overlapping [first_step, next_): the current one holds its partial maximum.
  const std::int64_t last = next_ - 1;
  const std::int64_t first = std::max(first_step, last - (mask_ + 1) + 1);
  const std::int64_t rev_first = first >= 0 ? first / spr_ : -((-first + spr_ - 1) / spr_);
  const std::int64_t rev_last = last >= 0 ? last / spr_ : -((-last + spr_ - 1) / spr_);
  for (std::int64_t r = rev_first; r <= rev_last; ++r) {
    m2 = std::max(m2, rev_max2_[revolution_slot(r * spr_)]);
  }
  return std::sqrt(m2);
}

ChipSearchResult chip_numerical_plain(const ToothPathGeometry& g, const ToothPathHistory& h,
                                      const ChipSearchQuery& q) {
  Tooth t{};
  Candidates c{};
  if (!start(g, q, t, c)) return finish(c, 0);
  std::int64_t points = 0;
  for (int tooth = 1; tooth <= g.teeth; ++tooth) {
    points += scan(g, h, t, q.step, tooth, q.step - q.window_steps, q.step - 1, c);
  }
  return finish(c, points);
}

ChipSearchResult chip_numerical_fast(const ToothPathGeometry& g, const ToothPathHistory& h,
                                     const ChipSearchQuery& q) {
  Tooth t{};
  Candidates c{};
  if (!start(g, q, t, c)) return finish(c, 0);
  const std::int64_t k = q.step;
  const std::int64_t W = q.window_steps;
  const std::int64_t S = g.steps_per_revolution;
  // |c_i - c_k| <= |d_i| + |d_k| + f (k - i): the deflection part over the whole window, the
  // feed part per band from its largest lag.
  const double d_max = h.max_deflection_since(k - W) + q.deflection_m.norm();
  const double dtheta = kTwoPi / static_cast<double>(S);
  const auto half_width = [&](std::int64_t lag_max) -> std::int64_t {
    const double sine =
        (g.candidate_distance_m + d_max + g.feed_per_step_m * static_cast<double>(lag_max)) /
        g.radius_m;
    if (!(sine < kMaxBandSine)) return -1;
    return static_cast<std::int64_t>(sine * kAsinSlope / dtheta) + 1;
  };
  const std::int64_t K_window = half_width(W);
  if (K_window < 0 || 4 * (K_window + 2) >= S) return chip_numerical_plain(g, h, q);
  std::int64_t points = 0;
  for (int tooth = 1; tooth <= g.teeth; ++tooth) {
    // Lags L = k - i at which tooth `tooth` passed the cutting tooth's angle: L = L0 + j S.
    std::int64_t L0 = (static_cast<std::int64_t>(tooth - q.tooth) * g.steps_per_tooth) % S;
    if (L0 < 0) L0 += S;
    for (std::int64_t L = L0; L - K_window - 1 <= W; L += S) {
      // Every point within K_window of L has a lag <= L + K_window + 1, which bounds the feed
      // part of D for this band (K <= K_window).
      const std::int64_t K = half_width(std::min(W, L + K_window + 1));
      // Band lags [L - K, L + K] plus one neighbour each side, clipped to the window [1, W].
      const std::int64_t lag_hi = std::min(L + K + 1, W);
      const std::int64_t lag_lo = std::max<std::int64_t>(L - K - 1, 1);
      if (lag_hi < lag_lo) continue;
      points += scan(g, h, t, k, tooth, k - lag_hi, k - lag_lo, c);
    }
  }
  return finish(c, points);
}

SearchWindowRule::SearchWindowRule(const NumericalChipOptions& o, int teeth,
                                   int steps_per_revolution, double feed_per_tooth_m)
    : spr_(steps_per_revolution) {
  const double S = static_cast<double>(steps_per_revolution);
  all_until_ = static_cast<std::int64_t>(std::llround(o.all_history_until_revolutions * S));
  long_until_ = static_cast<std::int64_t>(std::llround(o.long_until_revolutions * S));
  long_ = static_cast<std::int64_t>(std::llround(o.long_window_revolutions * S));
  short_ = static_cast<std::int64_t>(
      std::llround((1.0 / teeth + o.short_window_margin_revolutions) * S));
  const double sharp = o.sharp_change_fraction_of_feed * feed_per_tooth_m;
  sharp2_ = sharp * sharp;
  last_sharp_ = std::numeric_limits<std::int64_t>::min() / 2;
}

}  // namespace milling
}  // namespace chatterlab
