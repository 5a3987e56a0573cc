#include "analysis/milling/inertial.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/milling/simulation.h"
#include "tests/support/record_property.h"

namespace chatterlab {
namespace milling {
namespace {

constexpr double kOmega = 15000.0 * 2 * kPi / 60.0;  // 1570.796 rad/s
// Hand values below are products of a few exact decimals: 1e-12 relative is rounding.
constexpr double kHandRel = 1e-12;

using chatterlab::testing::record;

// 000 eqs 7.1-7.7 by hand. d = (3, 4) um: R = 5 um, phi = atan(4/3); v = (0.1, -0.05) m/s:
// Rdot = (3e-6 * 0.1 - 4e-6 * 0.05) / 5e-6 = 0.02 m/s. m = 0.03 kg, w = 1570.796 rad/s:
//   F_cen = m R w^2 = 0.03 * 5e-6 * 2467401.10 = 0.370110165 N along (0.6, 0.8);
//   F_Cor = 2 m Rdot w = 2 * 0.03 * 0.02 * 1570.796 = 1.88495559 N along (-sin, cos) = (-0.8, 0.6).
TEST(InertialForces, Eqs71To77ByHand) {
  const InertialForces f =
      inertial_forces(Eigen::Vector2d(3e-6, 4e-6), Eigen::Vector2d(0.1, -0.05), 0.03, kOmega);
  const double cen = 0.03 * 5e-6 * kOmega * kOmega;
  const double cor = 2 * 0.03 * 0.02 * kOmega;
  EXPECT_NEAR(cen, 0.3701101650, 1e-9);
  EXPECT_NEAR(cor, 1.8849555922, 1e-9);
  EXPECT_NEAR(f.centrifugal_N.x(), 0.6 * cen, kHandRel * cen);
  EXPECT_NEAR(f.centrifugal_N.y(), 0.8 * cen, kHandRel * cen);
  EXPECT_NEAR(f.coriolis_N.x(), -0.8 * cor, kHandRel * cor);
  EXPECT_NEAR(f.coriolis_N.y(), 0.6 * cor, kHandRel * cor);
}

// The vector form against eqs 7.1-7.7 written literally (phi by the quadrant rule of eq. 7.7,
// then cos/sin), in all four quadrants.
TEST(InertialForces, VectorFormEqualsLiteralEquationsInEveryQuadrant) {
  const double m = 0.03134;
  for (const Eigen::Vector2d& d : {Eigen::Vector2d(2e-6, 1e-6), Eigen::Vector2d(-2e-6, 1e-6),
                                   Eigen::Vector2d(-2e-6, -3e-6), Eigen::Vector2d(1e-6, -3e-6)}) {
    const Eigen::Vector2d v(0.07, 0.02);
    const double phi = d.x() >= 0 ? std::atan(d.y() / d.x()) : kPi + std::atan(d.y() / d.x());
    const double R = std::sqrt(d.x() * d.x() + d.y() * d.y());
    const double Rdot = (d.x() * v.x() + d.y() * v.y()) / R;
    const double Fcen = m * R * kOmega * kOmega;
    const double Fcor = 2 * m * Rdot * kOmega;  // eq. 7.3 with the mass (see inertial.h)
    const InertialForces f = inertial_forces(d, v, m, kOmega);
    EXPECT_NEAR(f.centrifugal_N.x(), Fcen * std::cos(phi), 1e-12 * Fcen);
    EXPECT_NEAR(f.centrifugal_N.y(), Fcen * std::sin(phi), 1e-12 * Fcen);
    EXPECT_NEAR(f.coriolis_N.x(), -Fcor * std::sin(phi), 1e-12 * std::abs(Fcor));
    EXPECT_NEAR(f.coriolis_N.y(), Fcor * std::cos(phi), 1e-12 * std::abs(Fcor));
  }
  // At R = 0 the Coriolis direction is undefined: taken as zero (000 sec. 7.2).
  const InertialForces z =
      inertial_forces(Eigen::Vector2d::Zero(), Eigen::Vector2d(1, 1), m, kOmega);
  EXPECT_EQ(z.coriolis_N.norm(), 0.0);
  EXPECT_EQ(z.centrifugal_N.norm(), 0.0);
}

TEST(InertialForces, EccentricSpringReferenceEqs78To79) {
  // r0 (sin(theta - theta0), cos(theta - theta0)): at theta = theta0 the reference sits on +y.
  const Eigen::Vector2d a = eccentric_spring_reference_m(1e-5, 5.17, 5.17);
  EXPECT_NEAR(a.x(), 0.0, 1e-20);
  EXPECT_NEAR(a.y(), 1e-5, 1e-20);
  // A quarter turn later (theta1 increasing, clockwise) it is on +x.
  const Eigen::Vector2d b = eccentric_spring_reference_m(1e-5, 5.17, 5.17 + kPi / 2);
  EXPECT_NEAR(b.x(), 1e-5, 1e-20);
  EXPECT_NEAR(b.y(), 0.0, 1e-20);
}

// Steady orbit of the tool spinning in air with eccentricity r0 = 10 um at theta0 = 5.17 rad
// (000 sec. 7.2) against the closed form. In complex form z = x + i y the spring reference is
// z_ref = i r0 e^{i theta0} e^{-i Omega t}; the circular response z = Z e^{-i Omega t} has R'
// = 0, so the Coriolis force vanishes and the centrifugal force m Omega^2 z only softens the
// spring:
//   Z (k - m Omega^2 [- m Omega^2 with inertial forces] - i c Omega) = k Z_ref.
// The scheme's own steady state replaces -m Omega^2 by m (q - 2 + 1/q) / h^2 and -i c Omega by
// c (1 - 1/q) / h with q = e^{-i Omega h}, and its backward-difference velocity gives a
// Coriolis force i 2 m Omega (1 - cos Omega h) / h Z. The simulated orbit matches that discrete
// closed form to 1e-9 (transients decayed as e^{-70}) and the continuous one to 5e-4: the
// scheme's damping adds c Omega^2 h / 2 = 69 N/m and its Coriolis term m Omega^3 h = 304 N/m,
// 8e-5 and 3.7e-4 of |k - 2 m Omega^2|.
TEST(InertialForces, EccentricSteadyOrbitMatchesClosedForm) {
  using C = std::complex<double>;
  const double m = 0.03134, c = 22.21, k = 9.840e5, r0 = 1e-5, th0 = 5.17;
  for (bool inertial : {false, true}) {
    SimulationOptions o;
    o.modal_x = {m, c, k};
    o.coefficients = {cutting_coefficients(0.2483e9, 0.2196e9),
                      cutting_coefficients(6.641e9, 4.154e9)};
    o.depth = DepthProfile::constant(0.0, 50);
    o.inertial.enabled = inertial;
    o.inertial.eccentricity_m = r0;
    o.inertial.eccentricity_angle_rad = th0;
    o.initial_deflection_m = {1e-8, 1e-8};  // 000 sec. 7.2
    RecordingRequest rq;
    rq.full_revolutions = {49};
    rq.trace_first_revolution = 40;
    rq.trace_revolutions = 10;
    const SimulationResult r = simulate(o, rq);
    ASSERT_TRUE(r.summary.ok());
    const double h = r.time_step_s;
    const C i(0.0, 1.0);
    const C q = std::exp(-i * kOmega * h);
    const C Zref = i * r0 * std::exp(i * th0);
    const double soft = inertial ? m * kOmega * kOmega : 0.0;
    const C Zc = k * Zref / (k - m * kOmega * kOmega - soft - i * c * kOmega);
    const C cor = inertial ? i * 2.0 * m * kOmega * (1 - std::cos(kOmega * h)) / h : C(0.0);
    const C Zd =
        k * Zref / (m * (q - 2.0 + 1.0 / q) / (h * h) + c * (1.0 - 1.0 / q) / h + k - soft - cor);
    const RevolutionRecord& rec = r.records[0];
    double worst_d = 0.0, worst_c = 0.0, worst_mean = 0.0;
    for (Eigen::Index a = 0; a < rec.x_m.size(); ++a) {
      const C z(rec.x_m[a], rec.y_m[a]);
      const C qk = std::exp(-i * kOmega * h * static_cast<double>(rec.first_step + a));
      worst_d = std::max(worst_d, std::abs(z - Zd * qk) / std::abs(Zd));
      worst_c = std::max(worst_c, std::abs(z - Zc * qk) / std::abs(Zc));
      const C mean(r.trace.mean_x_m[a], r.trace.mean_y_m[a]);
      worst_mean = std::max(worst_mean, std::abs(mean - Zd * qk) / std::abs(Zd));
    }
    EXPECT_LT(worst_d, 1e-9) << "inertial " << inertial;
    const std::string tag = inertial ? "_inertial" : "_spring_only";
    record("orbit_vs_discrete_closed_form" + tag, worst_d);
    record("orbit_vs_continuous_closed_form" + tag, worst_c);
    record("orbit_radius_m" + tag, std::abs(Zd));
    EXPECT_LT(worst_c, 5e-4) << "inertial " << inertial;
    // Every revolution is the same orbit, so the mean trajectory over revolutions 40-49 is it too.
    EXPECT_LT(worst_mean, 1e-9) << "inertial " << inertial;
    // Recorded inertial forces are eqs 7.1-7.7 of the recorded state (velocity first: v_k).
    if (inertial) {
      for (Eigen::Index a = 0; a < rec.x_m.size(); a += 97) {
        const InertialForces f =
            inertial_forces(Eigen::Vector2d(rec.x_m[a], rec.y_m[a]),
                            Eigen::Vector2d(rec.vx_m_s[a], rec.vy_m_s[a]), m, kOmega);
        EXPECT_EQ(rec.centrifugal_x_N[a], f.centrifugal_N.x());
        EXPECT_EQ(rec.coriolis_y_N[a], f.coriolis_N.y());
      }
      EXPECT_NEAR(rec.centrifugal_x_N.cwiseAbs().maxCoeff(), m * kOmega * kOmega * std::abs(Zd),
                  1e-6 * m * kOmega * kOmega * std::abs(Zd));
    }
  }
}

// Inertial forces with cutting (000 figs 7.3-7.4: trial 1 near 0.4 mm): the Coriolis force is
// of the order of the cutting force and acts over the whole revolution while the cutting force
// acts only while a tooth is engaged (~11 % of the revolution at 0.382 mm immersion).
TEST(InertialForces, ActThroughoutTheRevolutionUnlikeCuttingForces) {
  SimulationOptions o;
  o.modal_x = {0.03134, 22.21, 9.840e5};
  o.coefficients = {cutting_coefficients(0.2483e9, 0.2196e9),
                    cutting_coefficients(6.641e9, 4.154e9)};
  o.depth = DepthProfile::ramp(0.0, 0.5e-3, 1290.0);
  o.inertial.enabled = true;
  o.initial_deflection_m = {1e-8, 1e-8};
  RecordingRequest rq;
  rq.full_revolutions = {revolution_at_depth(o, 0.4e-3)};
  const SimulationResult r = simulate(o, rq);
  ASSERT_TRUE(r.summary.ok());
  const RevolutionRecord& rec = r.records[0];
  EXPECT_NEAR(rec.depth_m[0], 0.4e-3, 1e-3 / 1290);
  const Eigen::ArrayXd cut = (rec.Fx_N.array().square() + rec.Fy_N.array().square()).sqrt();
  const Eigen::ArrayXd cor =
      (rec.coriolis_x_N.array().square() + rec.coriolis_y_N.array().square()).sqrt();
  const double max_cut = cut.maxCoeff(), max_cor = cor.maxCoeff();
  const Eigen::Index cutting = (cut > 0.0).count();
  const Eigen::Index coriolis = (cor > 0.01 * max_cor).count();
  EXPECT_LT(cutting, rec.x_m.size() / 8);
  EXPECT_GT(coriolis, rec.x_m.size() / 2);
  EXPECT_GT(max_cor, 0.1 * max_cut);
  record("max_cutting_force_N", max_cut);
  record("max_coriolis_force_N", max_cor);
  record("steps_cutting", static_cast<double>(cutting));
  record("steps_coriolis_above_1pc", static_cast<double>(coriolis));
}

}  // namespace
}  // namespace milling
}  // namespace chatterlab
