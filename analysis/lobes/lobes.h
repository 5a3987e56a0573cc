// Stability lobes of milling under the linearized regenerative model (issue 13, analysis core).
// No files, no YAML: the lobes kind of the app reads the spec and writes results.json
// (EXPERIMENT_FORMAT.md "Stability lobe specs"). docs/lobes.md explains the methods.
//
// Model (000 eqs 2.1-2.7 linearized about the chatter-free motion; conventions of
// milling/force_model.h: theta from +y towards +x, tip at (r sin, r cos), feed +x, forces on the
// tool). x = sum of the x modes' coordinates, y = sum of the y modes'; each mode
// m q'' + c q' + k q = F_x (or F_y). The dynamic chip of tooth p is
//   dw_p = [x(t) - x(t - tau)] sin(theta_p) + [y(t) - y(t - tau)] cos(theta_p),
// allowed negative while the tooth is in its engagement window (switching by angle only), so
//   [F_x; F_y] = b H(t) [x(t) - x(t - tau); y(t) - y(t - tau)],
//   H(t) = sum_p g_p [-(Kt_p cos + Kr_p sin); Kt_p sin - Kr_p cos] [sin, cos]   (theta_p(t)),
// tau = 60 / (N n) the tooth period, b the axial depth.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <optional>
#include <vector>

#include "analysis/common/modal_parameters.h"
#include "analysis/common/summary.h"
#include "analysis/milling/simulation_options.h"

namespace chatterlab {
namespace lobes {

struct LobesInput {
  int teeth = 2;                // N, equal pitch, 1..milling::kMaxTeeth
  double radius_m = 6.35e-3;    // tool radius r, m, > 0
  std::vector<double> Kt_N_m2;  // per tooth p = 1..N, Kt_p of 000 eq. 2.1, N/m^2, >= 0
  std::vector<double> Kr_N_m2;  // per tooth, Kr_p of 000 eq. 2.2, N/m^2, >= 0
  milling::Operation operation = milling::Operation::kUpMilling;
  double radial_immersion_m = 0.0;       // r_i, 0 < r_i <= 2 r (milling/engagement.h)
  std::vector<ModalParameters> x_modes;  // empty: rigid along x
  std::vector<ModalParameters> y_modes;  // empty: rigid along y (not both empty)
  std::vector<double> spindle_rpm;       // speeds to evaluate, each > 0
  double max_depth_m = 10e-3;            // depths searched: (0, max_depth_m]
};

// Largest delay state (steps_per_tooth x modes, plus the 2 d of the state) semi_discretization
// accepts: an InputError beyond it.
constexpr long long kMaxDelayStates = 8192;

// Options of the semi-discretization (Insperger-Stepan 2004).
struct SemiDiscretizationOptions {
  int steps_per_tooth = 30;  // m: intervals per delay tau (dt = tau / m), >= 2
  int coarse_depths = 16;    // coarse scan b_j = j max / coarse, j = 1..coarse, >= 1
  // Bisection between the last stable and the first unstable coarse depth stops when
  // hi - lo <= depth_rel_tol * hi; the limit reported is hi (unstable), so it lies within
  // depth_rel_tol above the boundary of the discretized model.
  double depth_rel_tol = 1e-3;
  // Principal period: the tooth period when all teeth have the same Kt, Kr, else the
  // revolution. true: always the revolution (a check of the tooth-period computation).
  bool force_revolution_period = false;
  int threads = 1;  // speeds split over this many std::threads, >= 1
};

// Boundary type from the critical Floquet multiplier mu over the principal period:
// flip (mu real, near -1: period doubling), Hopf (complex pair: secondary Hopf), fold (mu real,
// near +1; over a revolution of N = 2 teeth a tooth-pass flip shows up as mu = +1).
enum class BoundaryType { kFlip, kHopf, kFold };
const char* to_string(BoundaryType t);  // "flip", "hopf", "fold"

struct SpeedResult {
  double spindle_rpm = 0.0;
  std::optional<double> limit_depth_m;       // none: stable up to max_depth_m
  std::optional<BoundaryType> type;          // with limit_depth_m
  std::optional<double> chatter_hz;          // with limit_depth_m (docs/lobes.md: the rule)
  double critical_multiplier_abs = 0.0;      // |mu| at limit_depth_m (> 1), or at max depth
  std::complex<double> critical_multiplier;  // mu at limit_depth_m (semi-discretization only)
};

struct LobesResult {
  StepSummary summary;              // not run until the method finished
  bool revolution_period = false;   // semi-discretization: multipliers over the revolution
  std::vector<SpeedResult> speeds;  // one per LobesInput::spindle_rpm, same order
  double runtime_s = 0.0;           // wall time of the whole method
};

// Throws InputError naming the field ("lobes.Kt_N_m2[1] = -1: must be finite and >= 0").
void validate(const LobesInput& in);

// Method 1: first-order semi-discretization. Throws InputError for invalid input or options.
LobesResult semi_discretization(const LobesInput& in, const SemiDiscretizationOptions& o = {});

// The automatic number of semi-discretization intervals per tooth period: at least 30, and
// enough that the engaged arc holds at least kEngagedIntervals of them (low immersion),
// at most kMaxAutoStepsPerTooth (docs/lobes.md "Intervals per tooth period").
constexpr int kEngagedIntervals = 12;
constexpr int kMaxAutoStepsPerTooth = 240;
int automatic_steps_per_tooth(const LobesInput& in);

// Whether semi-discretization takes the revolution as the principal period (teeth with unequal
// Kt or Kr, or o.force_revolution_period), else the tooth period.
bool uses_revolution_period(const LobesInput& in, const SemiDiscretizationOptions& o);

// The stability chart as a grid: |mu| (the largest Floquet multiplier's modulus) at every
// speed of in.spindle_rpm (rows) and every depth of depths_m (columns, each >= 0), speeds split
// over o.threads threads. < 1: stable. Throws InputError for invalid input.
Eigen::MatrixXd sd_spectral_radius_grid(const LobesInput& in, const SemiDiscretizationOptions& o,
                                        const std::vector<double>& depths_m);

// Floquet multipliers' largest modulus at one speed and depth (the stability test of
// semi_discretization; exposed for checks). `revolution_period` as force_revolution_period.
double sd_spectral_radius(const LobesInput& in, const SemiDiscretizationOptions& o,
                          double spindle_rpm, double depth_m);

// Options of the zero-order approximation (Altintas-Budak 1995).
struct ZeroOrderOptions {
  int lobes = 30;                 // lobe numbers k = 0 .. lobes - 1, >= 1
  int frequencies = 4000;         // chatter frequencies scanned per lobe, >= 10
  double min_frequency_hz = 0.0;  // scan range; 0 and 0: 0.3 x lowest to 3 x highest mode fn
  double max_frequency_hz = 0.0;
};

// One lobe point of the zero-order solution.
struct ZeroOrderPoint {
  int lobe = 0;             // k
  double chatter_hz = 0.0;  // omega_c / (2 pi)
  double spindle_rpm = 0.0;
  double depth_m = 0.0;
};

struct ZeroOrderResult {
  LobesResult lobes;                // resampled on LobesInput::spindle_rpm (lower envelope)
  std::vector<ZeroOrderPoint> raw;  // every positive-depth lobe point, lobe by lobe
};

// Method 2: the zero-order approximation. Throws InputError for invalid input or options.
ZeroOrderResult zero_order(const LobesInput& in, const ZeroOrderOptions& o = {});

}  // namespace lobes
}  // namespace chatterlab
