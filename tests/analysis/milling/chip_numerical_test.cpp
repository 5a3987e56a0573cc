#include "analysis/milling/chip_numerical.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/milling/chip_traditional.h"
#include "analysis/milling/engagement.h"
#include "analysis/milling/simulation.h"
#include "tests/support/record_property.h"

namespace chatterlab {
namespace milling {
namespace {

using chatterlab::testing::record;

// 000 sec. 5.2 conditions with the table 5.2 trial-1 parameters.
SimulationOptions trial1() {
  SimulationOptions o;
  o.modal_x = {0.03134, 22.21, 9.840e5};
  o.coefficients = {cutting_coefficients(0.2483e9, 0.2196e9),
                    cutting_coefficients(6.641e9, 4.154e9)};
  return o;
}

// Exact chip of an undeflected tool (second method, continuous): the tooth that passed the ray's
// angle one tooth period earlier (tooth p + 1, leading by 2 pi / n) left the trochoid
//   P(phi) - c = (r sin phi - F(phi), r cos phi),  F(phi) = h + n h (theta - phi) / (2 pi)
// (eq. 2.10: feed n h / (2 pi) per radian of rotation). Newton on r sin(phi - theta) =
// F(phi) cos(theta) gives the crossing; the chip is r minus its distance along the ray. With the
// original surface y = side (r - r_i) as the other bound (000 sec. 2.3).
double exact_undeflected_chip(const SimulationOptions& o, double theta) {
  const double r = o.radius_m, h = o.feed_per_tooth_m, n = o.teeth;
  const auto F = [&](double phi) { return h + n * h * (theta - phi) / (2 * kPi); };
  double phi = theta;
  for (int it = 0; it < 50; ++it) {
    const double f = r * std::sin(phi - theta) - F(phi) * std::cos(theta);
    const double df = r * std::cos(phi - theta) + n * h / (2 * kPi) * std::cos(theta);
    phi -= f / df;
  }
  const double s_path = r * std::cos(phi - theta) - F(phi) * std::sin(theta);
  const double side = workpiece_side(o.operation);
  if (!(side * std::cos(theta) > 0.0)) return -1.0;  // the tooth points away from the workpiece
  const double s_surface = side * (r - o.radial_immersion_m) / std::cos(theta);
  return std::min(r - s_path, r - s_surface);
}

// Undeflected history (all rest paths) and a query of tooth p at step k.
ChipSearchResult undeflected_chip(const SimulationOptions& o, const ToothPathGeometry& g,
                                  std::int64_t k, int p, bool fast) {
  ToothPathHistory h(g.steps_per_revolution, 4 * g.steps_per_revolution, Eigen::Vector2d::Zero(),
                     k);
  ChipSearchQuery q;
  q.step = k;
  q.tooth = p;
  q.window_steps = static_cast<std::int64_t>(2.05 * g.steps_per_revolution);
  (void)o;
  return fast ? chip_numerical_fast(g, h, q) : chip_numerical_plain(g, h, q);
}

TEST(ChipTraditional, Eq27WithoutDeflectionIsStaticChip) {
  // 000 eq. 2.7 with x(t) = x(t - tau): h sin(theta), to rounding.
  for (double th : {0.0, 0.1, 0.3490, 1.0, 2.8}) {
    EXPECT_NEAR(chip_thickness_traditional(6.35e-5, std::sin(th), std::cos(th), 0.0, 0.0),
                6.35e-5 * std::sin(th), 1e-20);
  }
  // Deflection change projected on the radial direction: (h + dx) sin + dy cos, by hand at
  // theta = 30 deg: (50 + 10) * 0.5 + 4 * 0.8660254 = 33.4641016 um.
  EXPECT_NEAR(chip_thickness_traditional(50e-6, 0.5, std::sqrt(3.0) / 2, 10e-6, 4e-6),
              33.46410161513775e-6, 1e-18);
}

// Numerical model on an undeflected trochoid against the exact crossing. The stored path is a
// polygon of chords of angle dtheta; a chord lies inside the arc by at most its sagitta
// r dtheta^2 / 8 = 1.2e-8 m at 800 steps per tooth, the only approximation of the search.
TEST(ChipNumerical, UndeflectedTrochoidMatchesExactCrossingUpAndDownMilling) {
  for (Operation op : {Operation::kUpMilling, Operation::kDownMilling}) {
    SimulationOptions o = trial1();
    o.operation = op;
    const ToothPathGeometry g = tooth_path_geometry(o);
    const double dtheta = 2 * kPi / g.steps_per_revolution;
    const double sagitta = o.radius_m * dtheta * dtheta / 8;  // 1.2e-8 m
    const EngagementWindow w = engagement_window(op, o.radius_m, o.radial_immersion_m);
    int cutting = 0;
    double max_vs_static = 0.0, max_vs_exact = 0.0;
    for (int a = 0; a < g.steps_per_revolution / 2; ++a) {
      const double th = a * dtheta;
      const ChipSearchResult r = undeflected_chip(o, g, a, 1, true);
      const double exact = exact_undeflected_chip(o, th);
      if (exact > sagitta) {
        ASSERT_TRUE(r.cutting) << "angle index " << a;
        EXPECT_NEAR(r.chip_m, exact, 1.5 * sagitta) << "angle index " << a;
        max_vs_exact = std::max(max_vs_exact, std::abs(r.chip_m - exact));
        ++cutting;
      } else if (exact < -sagitta) {
        EXPECT_FALSE(r.cutting) << "angle index " << a;
      }
      if (r.cutting && th > w.entry_rad + 2 * dtheta && th < w.exit_rad - 2 * dtheta) {
        // Away from the original-surface ends the chip is the static chip h sin(theta) plus the
        // trochoid's second-order terms (h cos)^2 / (2 r) - n h^2 sin cos / (2 pi r), at most
        // h^2 / (2 r) + n h^2 / (4 pi r) = 3.2e-7 + 1.0e-7 m.
        max_vs_static =
            std::max(max_vs_static, std::abs(r.chip_m - o.feed_per_tooth_m * std::sin(th)));
      }
    }
    // The engagement window holds 0.349 rad / 0.00393 rad = 88 steps.
    EXPECT_GE(cutting, 85);
    EXPECT_LE(cutting, 92);
    const double h2 = o.feed_per_tooth_m * o.feed_per_tooth_m;
    EXPECT_LT(max_vs_static,
              h2 / (2 * o.radius_m) + o.teeth * h2 / (4 * kPi * o.radius_m) + sagitta);
    EXPECT_GT(max_vs_static, 0.5 * h2 / (2 * o.radius_m));
    const std::string tag = op == Operation::kUpMilling ? "up" : "down";
    record("max_error_vs_exact_m_" + tag, max_vs_exact);
    record("max_difference_vs_h_sin_m_" + tag, max_vs_static);
    record("cutting_steps_" + tag, cutting);
  }
}

TEST(ChipNumerical, OriginalSurfaceBoundsTheChipAtTheExit) {
  // Last engaged step of up-milling (theta just below acos(1 - r_i / r) = 0.3490 rad): the tooth
  // leaves through the original surface, not through the previous tooth path.
  SimulationOptions o = trial1();
  const ToothPathGeometry g = tooth_path_geometry(o);
  const double dtheta = 2 * kPi / g.steps_per_revolution;
  const int a = static_cast<int>(std::acos(1 - o.radial_immersion_m / o.radius_m) / dtheta);
  const ChipSearchResult r = undeflected_chip(o, g, a, 1, false);
  const double th = a * dtheta;
  const double surface_chip = o.radius_m - (o.radius_m - o.radial_immersion_m) / std::cos(th);
  ASSERT_TRUE(r.cutting);
  EXPECT_LT(surface_chip, o.feed_per_tooth_m * std::sin(th));
  EXPECT_NEAR(r.chip_m, surface_chip, 1e-15);
  // The 2.05-revolution window holds four crossing paths (lags 0.5, 1, 1.5 and 2 revolutions);
  // the original surface is nearer the tip than all of them.
  EXPECT_EQ(r.candidates, 4);
}

TEST(ChipNumerical, NoSearchBelowTheOriginalSurfaceAndNegativeChipBeforeEntry) {
  SimulationOptions o = trial1();
  const ToothPathGeometry g = tooth_path_geometry(o);
  // theta = 90 deg: tip at y = 0, far below the surface y = r - r_i: no search, no cost.
  const ChipSearchResult below = undeflected_chip(o, g, g.steps_per_revolution / 4, 1, false);
  EXPECT_FALSE(below.cutting);
  EXPECT_EQ(below.points, 0);
  // theta = -5 deg: tip beyond the original surface, but the previous path lies outside the
  // tip (chip h sin(theta) < 0): a candidate beyond the tip, no contact (000 sec. 2.3).
  const std::int64_t k = g.steps_per_revolution - 22;
  const ChipSearchResult before = undeflected_chip(o, g, k, 1, false);
  EXPECT_FALSE(before.cutting);
  EXPECT_GE(before.candidates, 1);
  EXPECT_GT(before.points, 0);
}

// 000 sec. 2.3 window rule: all history to 5 revolutions, 2.05 to 10, then 1/n + 0.05 with
// re-expansion for one revolution after a sharp change.
TEST(SearchWindowRule, WindowsOf000Section23) {
  NumericalChipOptions o;
  const int S = 1600;
  SearchWindowRule w(o, 2, S, 6.35e-5);
  EXPECT_EQ(w.long_window_steps(), 3280);  // 2.05 S
  EXPECT_EQ(w.short_window_steps(), 880);  // 0.55 S
  EXPECT_EQ(w.window_steps(0), 3280);      // the rest paths before t = 0
  EXPECT_EQ(w.window_steps(5 * S - 1), 5 * S - 1 + 3280);
  EXPECT_EQ(w.window_steps(5 * S), 3280);
  EXPECT_EQ(w.window_steps(10 * S - 1), 3280);
  EXPECT_EQ(w.window_steps(10 * S), 880);
  // Sharp: |d - d(one rev earlier)| > 0.1 h = 6.35 um.
  const std::int64_t k = 20 * S;
  w.observe(k, Eigen::Vector2d(6.0e-6, 0.0));
  EXPECT_EQ(w.window_steps(k), 880);
  w.observe(k, Eigen::Vector2d(6.0e-6, 2.5e-6));  // |.| = 6.5 um
  EXPECT_EQ(w.window_steps(k), 3280);
  EXPECT_EQ(w.window_steps(k + S), 3280);
  EXPECT_EQ(w.window_steps(k + S + 1), 880);
}

// The fast (angle-banded) search against the plain search over whole tooth paths, on tooth paths
// recorded from a simulation that chatters (trial 1 at a constant 3 mm: x_n spread ~60 um) and
// from a stable one, with both window lengths. Same chip to the last bit and the same
// candidates.
TEST(ChipNumerical, FastSearchEqualsPlainSearchOnRecordedToothPaths) {
  for (double depth : {3.0e-3, 1.0e-3}) {
    SimulationOptions o = trial1();
    o.chip_model = ChipModel::kNumerical;
    o.depth = DepthProfile::constant(depth, 40);
    RecordingRequest rq;
    for (int j = 32; j < 40; ++j) rq.full_revolutions.push_back(j);
    const SimulationResult sim = simulate(o, rq);
    ASSERT_TRUE(sim.summary.ok());
    const ToothPathGeometry g = tooth_path_geometry(o);
    const int S = g.steps_per_revolution;
    ToothPathHistory h(S, 8 * S, Eigen::Vector2d::Zero(), sim.records[0].first_step);
    int compared = 0, cutting = 0, multi = 0, beyond_tip = 0;
    std::int64_t plain_points = 0, fast_points = 0;
    for (const RevolutionRecord& rec : sim.records) {
      for (int a = 0; a < S; ++a) {
        const std::int64_t k = rec.first_step + a;
        if (rec.revolution >= 35) {
          for (int p = 1; p <= 2; ++p) {
            double chip_by_window[2] = {0.0, 0.0};
            for (int wi = 0; wi < 2; ++wi) {
              ChipSearchQuery q;
              q.step = k;
              q.tooth = p;
              q.deflection_m = Eigen::Vector2d(rec.x_m[a], rec.y_m[a]);
              q.window_steps = wi == 0 ? 880 : 3280;
              const ChipSearchResult plain = chip_numerical_plain(g, h, q);
              const ChipSearchResult fast = chip_numerical_fast(g, h, q);
              ASSERT_EQ(plain.chip_m, fast.chip_m) << "step " << k << " tooth " << p;
              ASSERT_EQ(plain.cutting, fast.cutting);
              ASSERT_EQ(plain.candidates, fast.candidates);
              plain_points += plain.points;
              fast_points += fast.points;
              if (plain.points > 0) ++compared;
              if (plain.cutting) ++cutting;
              if (plain.candidates > 1) ++multi;
              if (plain.points > 0 && !plain.cutting) ++beyond_tip;
              chip_by_window[wi] = plain.chip_m;
            }
            // The chip the simulation used came from one of the two windows.
            const double used = rec.chip_m(a, p - 1);
            EXPECT_TRUE(used == chip_by_window[0] || used == chip_by_window[1])
                << "step " << k << " tooth " << p;
          }
        }
        h.push(rec.x_m[a], rec.y_m[a]);
      }
    }
    EXPECT_GT(compared, 2000);
    EXPECT_GT(cutting, 500);
    EXPECT_GT(beyond_tip, 200);  // tip beyond the original surface, no contact
    if (depth == 3.0e-3) {
      EXPECT_GT(multi, 200);  // several surfaces cross the ray in chatter
    }
    EXPECT_LT(fast_points * 10, plain_points);
    const std::string tag = depth == 3.0e-3 ? "3mm" : "1mm";
    record("searches_compared_" + tag, compared);
    record("cutting_" + tag, cutting);
    record("several_candidates_" + tag, multi);
    record("tip_beyond_surface_no_contact_" + tag, beyond_tip);
    record("plain_over_fast_points_" + tag,
           static_cast<double>(plain_points) / static_cast<double>(fast_points));
  }
}

}  // namespace
}  // namespace milling
}  // namespace chatterlab
