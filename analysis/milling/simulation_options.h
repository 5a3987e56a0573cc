// Options of the time-domain milling simulator (000 ch. 2, sec. 5.2, ch. 7), their validation
// and the step/time bookkeeping derived from them. docs/simulator.md explains every choice.
//
// Conventions (000 ch. 2, EXPERIMENT_FORMAT.md sec. 1): teeth p = 1..n at
// theta_p = theta_1 + (p - 1) 2 pi / n, measured from +y towards +x (clockwise in the x-y
// plane), tooth tip at (r sin theta, r cos theta) from the tool centre, theta_1 = 0 at t = 0 and
// increasing; feed along +x; x, y are the tool-centre deflections from the rotation axis.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "analysis/common/modal_parameters.h"
#include "analysis/milling/force_model.h"

namespace chatterlab {
namespace milling {

// Up-milling: workpiece on +y, chip grows from 0 at entry (000 eqs 2.8-2.9). Down-milling:
// workpiece on -y (same rotation and feed), chip shrinks to 0 at exit (engagement.h).
enum class Operation { kUpMilling, kDownMilling };

// Traditional: 000 eq. 2.7 with a fixed engagement window. Numerical: 000 sec. 2.3 (eqs
// 2.10-2.14), intersections with previous tooth paths.
enum class ChipModel { kTraditional, kNumerical };

// How the switching function g_p of 000 eqs 2.3-2.4 is set (traditional model only; the
// numerical model always cuts exactly when it finds a positive chip).
//   kContact:   g_p = 1 inside the engagement window and w_p > 0: a tooth whose chip is gone
//               leaves the cut (no force).
//   kAngleOnly: g_p = 1 inside the window whatever w_p, as 000 sec. 2.2 literally defines it; a
//               negative chip then gives a negative (pulling) force.
enum class SwitchingRule { kContact, kAngleOnly };

// Order of the two updates of a symplectic Euler step of size h (000 sec. 5.2), with
// a(x, v) = (F(x, theta) - c v - k (x - x_ref)) / m:
//   kVelocityFirst: v += h a(x_k, v_k); x += h v     (force at the step's own state)
//   kPositionFirst: x += h v; v += h a(x_{k+1}, v_k)
// Both evaluate the force of step j at (x_j, theta_j); see euler_order below.
enum class EulerOrder { kVelocityFirst, kPositionFirst };

// Modal parameters of one axis, 000 eqs 2.5-2.6 (common/modal_parameters.h). No defaults:
// never silently made up.
using AxisModal = ModalParameters;

// Axial depth b over the run. Depth at step k (time k h) is linear in k.
struct DepthProfile {
  enum class Kind { kRamp, kConstant };
  Kind kind = Kind::kRamp;
  double start_m = 0.0;                // kRamp: depth at t = 0; kConstant: the depth. m, >= 0
  double end_m = 6.0e-3;               // kRamp: depth at the end, m, >= 0, != start_m
                                       // (incline if above start_m, decline if below)
  double revolutions_per_mm = 1290.0;  // kRamp: revolutions per mm of depth change, > 0
                                       // (000 sec. 5.2: 1 mm per 1,290 revolutions)
  int revolutions = 0;                 // kConstant: run length in revolutions, >= 1

  static DepthProfile ramp(double start_m, double end_m, double revolutions_per_mm);
  static DepthProfile constant(double depth_m, int revolutions);
};

// Inertial forces of 000 ch. 7.
struct InertialOptions {
  // Centrifugal m R omega^2 and Coriolis 2 m Rdot omega forces (000 eqs 7.1-7.7; eq. 7.3 as
  // printed lacks the mass, see docs/simulator.md). Requires modal_x.m_kg == modal_y.m_kg.
  bool enabled = false;
  // Eccentric spring reference (000 eqs 7.8-7.9): the springs pull towards
  // r0 (sin(theta_1 - theta0), cos(theta_1 - theta0)) instead of the rotation axis. Applies
  // whether or not `enabled` is set; 0 = no eccentricity. m, >= 0.
  double eccentricity_m = 0.0;
  double eccentricity_angle_rad = 0.0;  // theta0 of eqs 7.8-7.9, rad, finite
};

// Search of the numerical chip model (000 sec. 2.3). Window lengths in revolutions.
struct NumericalChipOptions {
  // Before this many revolutions every stored path is searched, including the undeflected paths
  // assumed before t = 0 (long_window_revolutions of them).
  double all_history_until_revolutions = 5.0;
  // From then until long_until_revolutions: the last long_window_revolutions.
  double long_window_revolutions = 2.05;
  double long_until_revolutions = 10.0;
  // Afterwards: one tooth pass plus this margin (1/n + 0.05 = 0.55 revolutions for n = 2),
  // re-expanded to the long window while the deflection changes "sharply" (below).
  double short_window_margin_revolutions = 0.05;
  // "Sharply": |d(t) - d(t - one revolution)| > this fraction of the feed per tooth, with d the
  // deflection vector; the long window then stays on for one revolution after the last such
  // step. > 0.
  double sharp_change_fraction_of_feed = 0.1;
  // Angle-banded search (docs/simulator.md): the same candidates and chip as the plain search
  // over whole tooth paths, evaluated only near the tooth's angle. false: the plain search.
  bool fast_search = true;
};

// Largest number of teeth (per-step buffers of the simulator are fixed-size).
constexpr int kMaxTeeth = 32;

struct SimulationOptions {
  int teeth = 2;                     // n, 1..kMaxTeeth (000 sec. 5.2: two teeth)
  double radius_m = 6.35e-3;         // tool radius r, m, > 0 (000 sec. 5.2)
  AxisModal modal_x;                 // x axis: required
  std::optional<AxisModal> modal_y;  // y axis; unset: same as modal_x (000 sec. 5.1)
  // One entry per tooth p = 1..n: Kt_N_m2/Kr_N_m2 are Kt_p/Kr_p of 000 eqs 2.1-2.2 (Ktc, Krc of
  // eqs 3.3-3.4; N/m^2, finite, >= 0), Kte_N_m/Kre_N_m the edge terms of 000 eqs 3.3-3.4 (N/m,
  // finite, >= 0; 0 by default: no edge force).
  std::vector<CuttingCoefficients> coefficients;
  Operation operation = Operation::kUpMilling;
  double spindle_rpm = 15000.0;          // > 0 (000 sec. 5.2)
  double feed_per_tooth_m = 0.0635e-3;   // h, m, >= 0 (000 sec. 5.2)
  double radial_immersion_m = 0.382e-3;  // r_i, m, 0 < r_i <= 2 r (000 sec. 5.2)
  DepthProfile depth;                    // default: the 0 to 6 mm incline of 000 sec. 5.2
  ChipModel chip_model = ChipModel::kTraditional;
  int steps_per_tooth = 800;  // time steps per tooth pass, >= 8 (000 sec. 5.2: 800); the delay
                              // tau of 000 eq. 2.7 is exactly this many steps
  SwitchingRule switching = SwitchingRule::kContact;  // kAngleOnly: traditional model only
  // Both orders follow the same position recursion x_{k+1} - 2 x_k + x_{k-1} =
  // h^2 a(x_k, (x_k - x_{k-1}) / h) and differ only in the first step (x_1 - x_0 = h v_0 + h^2 a_0
  // or h v_0), so from rest without force (the default start) their positions are the same
  // (docs/simulator.md). They report different velocities: velocity first (the default,
  // Euler-Cromer) v_k = (x_k - x_{k-1}) / h, fixed by the past, so a recorded step
  // (x_k, v_k, forces) is the state its force was computed from; position first
  // v_k = (x_{k+1} - x_k) / h.
  EulerOrder euler_order = EulerOrder::kVelocityFirst;
  InertialOptions inertial;
  // theta_1 at which the once-per-revolution samples x_n, y_n are taken, rad, finite; wrapped to
  // [0, 2 pi) and rounded to the step grid (2 pi / (n steps_per_tooth)). 0: revolution start.
  double sample_angle_rad = 0.0;
  // Deflection at t = 0 (velocity 0); the past (t < 0) is taken at rest at this deflection.
  // 000 sec. 7.2 uses 1e-8 m on both axes with inertial forces. m, finite.
  Eigen::Vector2d initial_deflection_m = Eigen::Vector2d::Zero();
  NumericalChipOptions numerical;
};

// Kt, Kr of one tooth with edge terms 0 unless given (000 eqs 2.1-2.2, 3.3-3.4).
CuttingCoefficients cutting_coefficients(double Kt_N_m2, double Kr_N_m2, double Kte_N_m = 0.0,
                                         double Kre_N_m = 0.0);

// Throws InputError naming the first field that breaks its rule ("simulation.<field> = value:
// rule").
void validate(const SimulationOptions& o);

// Step bookkeeping derived from valid options.
struct SimulationGrid {
  int teeth = 0;
  int steps_per_tooth = 0;        // T
  int steps_per_revolution = 0;   // S = n T
  double time_step_s = 0.0;       // h = 60 / (rpm S)
  double angle_step_rad = 0.0;    // 2 pi / S
  int revolutions = 0;            // run length R
  std::int64_t steps = 0;         // R S
  double depth_start_m = 0.0;     // depth at step 0
  double depth_per_step_m = 0.0;  // signed depth change per step
  double depth_end_m = 0.0;       // depth limit of a ramp (the depth is clamped there)
  double depth_at_step(std::int64_t k) const;
};

// Throws InputError unless `o` is valid. A ramp runs ceil(|end - start| [mm] * rate) revolutions
// (7,740 for 0 to 6 mm at 1,290 per mm).
SimulationGrid simulation_grid(const SimulationOptions& o);

// The revolution (0-based) whose depth range contains depth_m, clamped to the run: for picking
// "the revolution nearest 1 mm" (000 figs 5.2, 7.3-7.4). A constant depth gives the last
// revolution (the most settled). Throws InputError unless `o` is valid.
int revolution_at_depth(const SimulationOptions& o, double depth_m);

}  // namespace milling
}  // namespace chatterlab
