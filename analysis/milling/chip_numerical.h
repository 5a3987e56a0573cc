// Numerical chip thickness, 000 sec. 2.3 (eqs 2.10-2.14): intersections of the cutting tooth
// with the stored tooth paths of the previous revolutions.
//
// Tooth tip of tooth q at step i (eqs 2.10-2.11, feed f per step along +x, f = h / T):
//   P_q(i) = (r sin theta_q(i) + x_i + f i,  r cos theta_q(i) + y_i).
// The cutting tooth p at step k is the ray from the tool centre c = (x_k + f k, y_k) through its
// tip, direction e = (sin theta_p, cos theta_p). For every stored path point the distance to
// the tooth line and the foot of the perpendicular are computed analytically (eqs 2.12-2.14 in
// vector form: the slope form of eq. 2.12 is singular for the vertical tooth at theta = 0, the
// up-milling entry). A path point is a candidate when its distance is a local minimum along
// its own path (both neighbours stored inside the window), below candidate_distance_m, and on
// the tooth's side of the centre (the other half of the line carries the opposite tooth of a
// two-flute tool). The nearer neighbour is the assisting point; the tooth line meets the line
// through candidate and assisting point at s along e, giving the candidate chip r - s. The
// original surface (y = +-(r - r_i), never cut) is one more candidate (the case of a tooth
// leaving through the original surface, 000 sec. 2.3 and [41]). The chip is the smallest
// candidate chip (the outermost surface); the tooth cuts when it is > 0. A candidate beyond
// the tip makes it <= 0: "no valid intersection" of 000 sec. 2.3. "Beyond" is measured along
// the tooth (s > r), which is the text's "y-component greater than the tip" for up-milling.
//
// Two searches give the same chip:
//   plain: every point of every tooth path in the window.
//   fast:  only the points whose angle is within K steps of the tooth's angle, with K from a
//          bound on the tool-centre displacement D: a point at angle phi on a path whose centre
//          is within D of c has distance >= r |sin(phi - theta)| - D from the line, so no point
//          outside |phi - theta| < asin((threshold + D) / r) can be a candidate. The local
//          minimum test still sees both neighbours, so candidates, assisting points and
//          intersections are the same numbers as in the plain search.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "analysis/milling/simulation_options.h"

namespace chatterlab {
namespace milling {

// Fixed geometry of a run, precomputed once.
struct ToothPathGeometry {
  int teeth = 0;
  int steps_per_tooth = 0;       // T
  int steps_per_revolution = 0;  // S = n T
  double radius_m = 0.0;
  double feed_per_step_m = 0.0;              // h / T
  double original_surface_m = 0.0;           // r - r_i: the original surface is y = side (r - r_i)
  double side = 1.0;                         // +1 up-milling (workpiece on +y), -1 down-milling
  double candidate_distance_m = 0.0;         // 2 r dtheta: a crossing segment's nearer end lies
                                             // within half a segment (~r dtheta / 2) of the line
  std::vector<double> sin_theta, cos_theta;  // of theta = a 2 pi / S, a = 0..S-1
};

// Throws InputError unless `o` is valid.
ToothPathGeometry tooth_path_geometry(const SimulationOptions& o);

// Angle index (0..S-1) of tooth p (1..n) at step k (any sign): theta_p = (k + (p-1) T) 2 pi / S.
inline int tooth_angle_index(const ToothPathGeometry& g, std::int64_t k, int p) {
  const std::int64_t a =
      (k + static_cast<std::int64_t>(p - 1) * g.steps_per_tooth) % g.steps_per_revolution;
  return static_cast<int>(a < 0 ? a + g.steps_per_revolution : a);
}

// Tool-centre deflections, one per step, in a ring buffer; steps before 0 hold the rest
// deflection (the tool assumed at rest there, cutting undeflected paths). Tooth paths follow
// from it and the geometry. Keeps a per-revolution maximum of |d| for the fast search's bound.
class ToothPathHistory {
 public:
  // capacity_steps: how many past steps stay readable (rounded up to a power of two);
  // first_step: the step the first push() records (steps before it read as the rest deflection).
  ToothPathHistory(int steps_per_revolution, std::int64_t capacity_steps,
                   const Eigen::Vector2d& rest_deflection_m, std::int64_t first_step = 0);

  // Stores the deflection of step next_step() and advances it.
  void push(double x_m, double y_m) {
    const std::size_t slot = static_cast<std::size_t>(next_ & mask_);
    x_[slot] = x_m;
    y_[slot] = y_m;
    const double r2 = x_m * x_m + y_m * y_m;
    double& rev_max = rev_max2_[revolution_slot(next_)];
    if (next_ % spr_ == 0)
      rev_max = r2;
    else if (r2 > rev_max)
      rev_max = r2;
    ++next_;
  }
  std::int64_t next_step() const { return next_; }
  std::int64_t capacity() const { return mask_ + 1; }
  // Deflection of step i; requires next_step() - capacity() <= i < next_step() (unchecked).
  double x(std::int64_t i) const { return x_[static_cast<std::size_t>(i & mask_)]; }
  double y(std::int64_t i) const { return y_[static_cast<std::size_t>(i & mask_)]; }
  // An upper bound of |d_i| over first_step <= i < next_step() (whole revolutions' maxima).
  double max_deflection_since(std::int64_t first_step) const;

 private:
  std::size_t revolution_slot(std::int64_t step) const;

  std::int64_t spr_;
  std::int64_t mask_;
  std::int64_t next_ = 0;
  std::vector<double> x_, y_;
  std::vector<double> rev_max2_;  // per revolution floor(step / S), ring of revolutions
};

struct ChipSearchQuery {
  std::int64_t step = 0;  // k; the history must hold steps k - window_steps .. k - 1
  int tooth = 1;          // p, 1..n
  Eigen::Vector2d deflection_m = Eigen::Vector2d::Zero();  // d_k, the tool centre now
  std::int64_t window_steps = 0;  // W: path points of steps k - W .. k - 1 are searched
};

struct ChipSearchResult {
  double chip_m = 0.0;      // w_p > 0 when cutting, else 0
  bool cutting = false;     // the switching function g_p
  int candidates = 0;       // path candidates found (the original surface not counted)
  std::int64_t points = 0;  // path points whose distance was evaluated (cost)
};

ChipSearchResult chip_numerical_plain(const ToothPathGeometry& g, const ToothPathHistory& h,
                                      const ChipSearchQuery& q);
ChipSearchResult chip_numerical_fast(const ToothPathGeometry& g, const ToothPathHistory& h,
                                     const ChipSearchQuery& q);

// The search window of 000 sec. 2.3, in steps: every stored step (plus the long window of rest
// paths before t = 0) until all_history_until_revolutions, then long_window_revolutions until
// long_until_revolutions, then one tooth pass plus a margin, widened to the long window for one
// revolution after any step whose deflection differs from one revolution earlier by more than
// sharp_change_fraction_of_feed * h.
class SearchWindowRule {
 public:
  SearchWindowRule(const NumericalChipOptions& o, int teeth, int steps_per_revolution,
                   double feed_per_tooth_m);
  // Call once per step, before window_steps(k), with d_k - d_{k-S}.
  void observe(std::int64_t k, const Eigen::Vector2d& change_over_revolution_m) {
    if (change_over_revolution_m.squaredNorm() > sharp2_) last_sharp_ = k;
  }
  std::int64_t window_steps(std::int64_t k) const {
    if (k < all_until_) return k + long_;
    if (k < long_until_) return long_;
    return k - last_sharp_ <= spr_ ? long_ : short_;
  }
  // Steps of history the searches need (largest window, its neighbours, one revolution).
  std::int64_t history_steps_needed() const { return all_until_ + long_ + spr_ + 2; }
  std::int64_t long_window_steps() const { return long_; }
  std::int64_t short_window_steps() const { return short_; }

 private:
  std::int64_t spr_, all_until_, long_until_, long_, short_;
  double sharp2_;
  std::int64_t last_sharp_;
};

}  // namespace milling
}  // namespace chatterlab
