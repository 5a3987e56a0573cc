#include "analysis/milling/symplectic_euler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "analysis/common/constants.h"
#include "analysis/milling/simulation.h"
#include "tests/support/record_property.h"

namespace chatterlab {
namespace milling {
namespace {

using chatterlab::testing::record;

// Table 5.2 trial-1 modal parameters on x; a different, stiffer mode on y so a mix-up of axes
// shows.
const AxisModal kX{0.03134, 22.21, 9.840e5};
const AxisModal kY{0.05, 30.0, 2.0e6};

// Tool spinning in air (depth 0: no cutting force) from an initial deflection.
SimulationOptions free_vibration(EulerOrder order, int revolutions) {
  SimulationOptions o;
  o.modal_x = kX;
  o.modal_y = kY;
  o.coefficients = {cutting_coefficients(0.2483e9, 0.2196e9),
                    cutting_coefficients(6.641e9, 4.154e9)};
  o.depth = DepthProfile::constant(0.0, revolutions);
  o.initial_deflection_m = {10e-6, -5e-6};
  o.euler_order = order;
  return o;
}

// Concatenated x or y of consecutive full records.
std::vector<double> series(const SimulationResult& r, bool y) {
  std::vector<double> v;
  for (const RevolutionRecord& rec : r.records) {
    const Eigen::VectorXd& s = y ? rec.y_m : rec.x_m;
    v.insert(v.end(), s.data(), s.data() + s.size());
  }
  return v;
}

// Damped frequency from the mean spacing of upward zero crossings (linear interpolation) and
// decay rate from the log of successive positive peaks (local maxima, parabolic vertex).
struct FreeResponse {
  double omega_d = 0.0, sigma = 0.0;
};
FreeResponse measure(const std::vector<double>& x, double h) {
  std::vector<double> up, peak_t, peak_v;
  for (std::size_t i = 1; i + 1 < x.size(); ++i) {
    if (x[i - 1] < 0.0 && x[i] >= 0.0) up.push_back((i - 1) + x[i - 1] / (x[i - 1] - x[i]));
    if (x[i] > 0.0 && x[i] > x[i - 1] && x[i] >= x[i + 1]) {
      const double a = 0.5 * (x[i + 1] - 2 * x[i] + x[i - 1]);
      const double b = 0.5 * (x[i + 1] - x[i - 1]);
      peak_t.push_back(i - b / (2 * a));
      peak_v.push_back(x[i] - b * b / (4 * a));
    }
  }
  FreeResponse f;
  f.omega_d = 2 * kPi * (up.size() - 1) / ((up.back() - up.front()) * h);
  f.sigma = std::log(peak_v.front() / peak_v.back()) / ((peak_t.back() - peak_t.front()) * h);
  return f;
}

// Closed form of m x'' + c x' + k x = 0: omega_d = omega_n sqrt(1 - zeta^2), decay
// sigma = zeta omega_n = c / (2 m). Both orders have the step matrix trace 2 - h c/m - h^2 k/m and
// determinant 1 - h c/m, so their eigenvalues are sqrt(det) e^{+-i omega' h} with
//   cos(omega' h) = trace / (2 sqrt(det)),   sigma' = -ln(det) / (2 h):
// the explicit damping term shifts both by O(h c / m) (the backward-difference velocity acts like
// a mass m - c h / 2): +4.4e-4 on the frequency and +8.9e-4 on the decay for x at h = 2.5 us.
// Measured against the discrete closed form to 1e-7 (zero-crossing and peak interpolation), and
// against the continuous one to h c / m (first-order bound).
TEST(SymplecticEuler, FreeVibrationFrequencyAndDecayMatchClosedForm) {
  for (EulerOrder order : {EulerOrder::kVelocityFirst, EulerOrder::kPositionFirst}) {
    RecordingRequest rq;
    for (int j = 0; j < 12; ++j) rq.full_revolutions.push_back(j);
    const SimulationResult r = simulate(free_vibration(order, 12), rq);
    ASSERT_TRUE(r.summary.ok());
    const double h = r.time_step_s;
    for (bool y : {false, true}) {
      const AxisModal& a = y ? kY : kX;
      const double wn = std::sqrt(a.k_N_m / a.m_kg);
      const double zeta = a.c_kg_s / (2 * std::sqrt(a.k_N_m * a.m_kg));
      const double det = 1 - h * a.c_kg_s / a.m_kg;
      const double trace = 2 - h * a.c_kg_s / a.m_kg - h * h * a.k_N_m / a.m_kg;
      const double omega_discrete = std::acos(trace / (2 * std::sqrt(det))) / h;
      const double sigma_discrete = -std::log(det) / (2 * h);
      const FreeResponse f = measure(series(r, y), h);
      EXPECT_NEAR(f.omega_d / omega_discrete, 1.0, 1e-7) << "axis y=" << y;
      const std::string tag =
          std::string(y ? "y" : "x") + (order == EulerOrder::kVelocityFirst ? "_vf" : "_pf");
      record("omega_rel_error_vs_closed_form_" + tag,
             f.omega_d / (wn * std::sqrt(1 - zeta * zeta)) - 1);
      record("sigma_rel_error_vs_closed_form_" + tag, f.sigma / (zeta * wn) - 1);
      record("omega_rel_error_vs_discrete_" + tag, f.omega_d / omega_discrete - 1);
      record("sigma_rel_error_vs_discrete_" + tag, f.sigma / sigma_discrete - 1);
      EXPECT_NEAR(f.sigma / sigma_discrete, 1.0, 1e-7) << "axis y=" << y;
      const double first_order = h * a.c_kg_s / a.m_kg;
      EXPECT_NEAR(f.omega_d / (wn * std::sqrt(1 - zeta * zeta)), 1.0, first_order) << y;
      EXPECT_NEAR(f.sigma / (zeta * wn), 1.0, first_order) << "axis y=" << y;
    }
  }
}

// No damping, no cutting: the step is a symplectic map and conserves
//   Q = v^2 + w^2 x^2 - h w^2 x v  (velocity first),  + h w^2 x v  (position first),
// so over 200 revolutions (560 periods, 320,000 steps) Q stays to rounding (1e-10 relative) and,
// since |h w^2 x v| <= (w h / 2)(v^2 + w^2 x^2), the energy (m v^2 + k x^2) / 2 stays within
// E0 / (1 -+ w h / 2) (w h / 2 = 7.0e-3 for x) instead of drifting.
TEST(SymplecticEuler, EnergyBoundedWithoutDampingOverManyPeriods) {
  for (EulerOrder order : {EulerOrder::kVelocityFirst, EulerOrder::kPositionFirst}) {
    SimulationOptions o = free_vibration(order, 200);
    o.modal_x.c_kg_s = 0.0;
    o.modal_y = AxisModal{kY.m_kg, 0.0, kY.k_N_m};
    RecordingRequest rq;
    rq.full_revolutions = {0, 100, 199};
    const SimulationResult r = simulate(o, rq);
    ASSERT_TRUE(r.summary.ok());
    const double h = r.time_step_s;
    const double sign = order == EulerOrder::kVelocityFirst ? -1.0 : 1.0;
    for (bool y : {false, true}) {
      const AxisModal& a = y ? *o.modal_y : o.modal_x;
      const double w2 = a.k_N_m / a.m_kg;
      const double Q0 =
          w2 * std::pow(y ? o.initial_deflection_m.y() : o.initial_deflection_m.x(), 2);
      const double E0 = 0.5 * a.m_kg * Q0;
      double worst_Q = 0.0, worst_E = 0.0;
      for (const RevolutionRecord& rec : r.records) {
        const Eigen::VectorXd& x = y ? rec.y_m : rec.x_m;
        const Eigen::VectorXd& v = y ? rec.vy_m_s : rec.vx_m_s;
        for (Eigen::Index i = 0; i < x.size(); ++i) {
          const double Q = v[i] * v[i] + w2 * x[i] * x[i] + sign * h * w2 * x[i] * v[i];
          const double E = 0.5 * (a.m_kg * v[i] * v[i] + a.k_N_m * x[i] * x[i]);
          worst_Q = std::max(worst_Q, std::abs(Q / Q0 - 1.0));
          worst_E = std::max(worst_E, std::abs(E / E0 - 1.0));
        }
      }
      const double wh2 = std::sqrt(w2) * h / 2;
      EXPECT_LT(worst_Q, 1e-10);
      const std::string tag =
          std::string(y ? "y" : "x") + (order == EulerOrder::kVelocityFirst ? "_vf" : "_pf");
      record("invariant_rel_change_" + tag, worst_Q);
      record("energy_rel_excursion_" + tag, worst_E);
      record("omega_h_over_2_" + tag, wh2);
      EXPECT_LT(worst_E, wh2 / (1 - wh2) * (1 + 1e-9));
      EXPECT_GT(worst_E, wh2 * 0.5);  // the oscillation is there: the check is not vacuous
    }
  }
}

// Constant force: both orders have x = F / k, v = 0 as their exact fixed point; heavy damping
// (zeta = 1) reaches it from rest in 4,000 steps (e^{-22}).
TEST(SymplecticEuler, StaticForceBalance) {
  const AxisModal a{0.03134, 2 * std::sqrt(9.840e5 * 0.03134), 9.840e5};
  const SymplecticEulerAxis s = symplectic_euler_axis(a, 2.5e-6);
  for (EulerOrder order : {EulerOrder::kVelocityFirst, EulerOrder::kPositionFirst}) {
    double x = 0.0, v = 0.0;
    for (int i = 0; i < 4000; ++i) symplectic_euler_step(s, order, x, v, 12.5);
    EXPECT_NEAR(x, 12.5 / 9.840e5, 1e-12 * 12.5 / 9.840e5);
    EXPECT_NEAR(v, 0.0, 1e-12);
  }
}

// With the force of step j evaluated at (x_j, theta_j), both orders follow the same position
// recursion x_{k+1} - 2 x_k + x_{k-1} = h^2 a(x_k, (x_k - x_{k-1}) / h) and differ only in the
// first step (by h^2 a_0, zero from rest): the once-per-revolution samples of an incline agree to
// rounding before the bifurcation (stable: rounding differences decay) and the bifurcation
// depth is the same. Table 5.2 trial 3 (incline 3, the sensitive one), traditional model.
TEST(SymplecticEuler, BothOrdersGiveTheSamePositions) {
  SimulationOptions o;
  o.modal_x = {0.03172, 30.25, 0.9630e6};
  o.coefficients = {cutting_coefficients(0.2785e9, 0.2668e9),
                    cutting_coefficients(3.978e9, 2.852e9)};
  const SimulationResult vf = simulate(o);
  o.euler_order = EulerOrder::kPositionFirst;
  const SimulationResult pf = simulate(o);
  ASSERT_TRUE(vf.summary.ok() && pf.summary.ok());
  double worst = 0.0;
  for (Eigen::Index j = 0; j < vf.samples.x_m.size(); ++j) {
    if (vf.samples.depth_m[j] > 5.0e-3) break;  // incline 3 bifurcates near 5.5 mm
    worst = std::max(worst, std::abs(vf.samples.x_m[j] - pf.samples.x_m[j]));
  }
  EXPECT_LT(worst, 1e-17);  // deflections are ~1e-4 m: rounding level
  record("max_x_n_difference_below_5mm_m", worst);
  // First revolution whose 20-revolution x_n spread exceeds 1 um, for both orders.
  const auto first = [](const OncePerRevolution& s) {
    for (Eigen::Index j = 0; j + 20 <= s.x_m.size(); ++j) {
      const Eigen::VectorXd w = s.x_m.segment(j, 20);
      if (w.maxCoeff() - w.minCoeff() > 1e-6) return s.depth_m[j];
    }
    return -1.0;
  };
  EXPECT_EQ(first(vf.samples), first(pf.samples));
  record("bifurcation_depth_mm", first(vf.samples) * 1e3);
}

}  // namespace
}  // namespace milling
}  // namespace chatterlab
