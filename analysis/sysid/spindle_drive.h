// A spindle drive with its speed and current loops as one discrete-time LTI system at the
// controller rate fs: the synthetic truth of 001 sec. 3.1 (notes/001.md sec. 7.1 A). It
// synthesizes sweep and cutting records (simulate) and gives the exact FRFs those records
// should produce: the three sweep FRFs of 001 eqs 3.4-3.6 and the torque-to-current FRF
// G_dtau = I_nom / tau_d of 001 eq. 3.9.
//
// Mechanics (two inertias; 001 eq. 3.2 is its rigid one-inertia limit), states th1 - th2, w1,
// w2:
//   J1 w1' = Kt I_act - B w1 - k (th1 - th2) - c (w1 - w2) - tau_d
//   J2 w2' =                    k (th1 - th2) + c (w1 - w2)
// with tau_d at the motor torque node (001's assumption, notes/001.md sec. 6 item 23), or with
// `disturbance_at_tool` on J2 instead (a known model error for eq. 3.9). The encoder measures
// w1; speeds are in rpm at the interface and rad/s inside.
//
// Current loop (G_m of 001 eqs 3.4-3.5): I_act = wc / (s + wc) acting on I_nom delayed by
// d = current_delay_s fs samples (an integer). Two discrete forms (CurrentLoopForm):
//   kSampledCurrent (default): the current loop is a discrete block, its first-order filter
//     discretized by zero-order hold, I_act[k+1] = a I_act[k] + (1 - a) I_nom[k-d],
//     a = exp(-wc Ts); the motor torque Kt I_act[k] is held over [k Ts, (k+1) Ts). The held
//     current is the sampled current, so speed / I_act (G_s) is exactly Kt times the speed per
//     motor-node torque, and 001 eq. 3.9 holds exactly in its discrete form;
//   kContinuousFilter: the filter state is a state of the continuous plant, driven by the held
//     I_nom[k-d]; the whole plant is discretized by zero-order hold. The sampled I_act is then
//     not the current that acted over the sample, and eq. 3.9 holds only approximately: a
//     sampling model error, as from a skew of about 58 us (about half a sample) between the
//     sampled I_act and the acting current, 3.6 % at 100 Hz and 68 % at 2 kHz at the defaults.
// Both plants are exact zero-order-hold discretizations (matrix exponential of the augmented
// [[A, B], [0, 0]] Ts, Eigen's MatrixFunctions), with I_nom[k-d] and tau_d[k] held over each
// sample.
//
// Speed controller (G_Omega of 001 eq. 3.7): a digital PI at fs with a forward-Euler
// integral, e[k] = speed_ref[k] - w1[k] (rad/s),
//   I_nom[k] = Kp e[k] + (Kp / Ti) q[k],   q[k+1] = q[k] + Ts e[k]
// (the integral is updated after the output), i.e. C(z) = Kp + (Kp / Ti) Ts / (z - 1).
//
// Closed loop: states [th1 - th2, w1, w2, I_act, the d delayed I_nom samples, q]; inputs
// [speed_ref_rpm, tau_d_Nm]; outputs [speed_rpm (w1), current_nom_A (I_nom), current_act_A
// (I_act)]; a direct feedthrough only from speed_ref to I_nom (Kp).
//
// Sweep FRFs as 001 defines them (discrete, z = exp(j 2 pi f / fs), f > 0), each the ratio a
// speed-reference sweep of the closed loop would measure (the tests check both forms):
//   G_o    = speed / error = C(z) z^-d P_w(z)            (001 eq. 3.4, dimensionless; the loop
//            gain, notes/001.md sec. 6 item 2)
//   G_loop = speed / I_nom = z^-d P_w(z)                  (001 eq. 3.5, rpm per A)
//   G_s    = speed / I_act = P_w(z) / P_i(z)              (001 eq. 3.6, rpm per A)
// where P_w, P_i are the plant FRFs from the held current command to w1 (in rpm) and I_act.
// G_dtau = I_nom / tau_d (A per N m, the truth of 001 eq. 3.9), and 001 eq. 3.9 reads
//   G_dtau = G_s (G_o / G_loop) / (Kt (1 + G_o)).
#pragma once

#include <Eigen/Core>
#include <complex>

#include "analysis/common/constants.h"
#include "analysis/sysid/state_space.h"

namespace chatterlab {
namespace sysid {

enum class CurrentLoopForm {
  kSampledCurrent,    // discrete current loop, torque Kt I_act[k] held (eq. 3.9 exact)
  kContinuousFilter,  // filter state in the continuous plant (eq. 3.9 approximate)
};

// Defaults: notes/001.md sec. 7.1 A.
struct SpindleDriveParams {
  double j1_kg_m2 = 0.008;                           // motor inertia J1, > 0
  double j2_kg_m2 = 0.002;                           // tool-side inertia J2, > 0
  double k_nm_per_rad = 5e4;                         // shaft stiffness k, > 0
  double c_nm_s_per_rad = 2.0;                       // shaft damping c, >= 0
  double b_nm_s_per_rad = 0.002;                     // motor viscous damping B, >= 0
  double kt_nm_per_a = 0.8;                          // torque constant Kt, > 0
  double current_bandwidth_rad_s = kTwoPi * 1500.0;  // wc, > 0
  // >= 0, a multiple of 1 / sample_rate_hz within 1e-9 s, at most 1000 samples
  double current_delay_s = 100e-6;
  double kp_a_s_per_rad = (0.008 + 0.002) * kTwoPi * 100.0 / 0.8;  // Kp (A per rad/s), > 0
  double ti_s = 4.0 / (kTwoPi * 100.0);                            // Ti, > 0
  double sample_rate_hz = 10000.0;                                 // fs, > 0
  bool disturbance_at_tool = false;
  CurrentLoopForm current_loop = CurrentLoopForm::kSampledCurrent;
};

// @throws InputError naming the first field that breaks its rule.
void validate(const SpindleDriveParams& params);

// A discrete multi-input multi-output state-space system x[k+1] = A x + B u, y = C x + D u.
struct DiscreteMimoSystem {
  Eigen::MatrixXd A;
  Eigen::MatrixXd B;
  Eigen::MatrixXd C;
  Eigen::MatrixXd D;
  double sample_rate_hz = 0.0;
};

// H(f) = C (zI - A)^-1 B + D at one frequency (rows: outputs, columns: inputs).
Eigen::MatrixXcd frequency_response(const DiscreteMimoSystem& system, double f_hz);

struct SpindleDriveRecord {
  Eigen::VectorXd speed_rpm;      // measured motor speed w1
  Eigen::VectorXd current_nom_a;  // I_nom, the speed controller output
  Eigen::VectorXd current_act_a;  // I_act, the sampled motor current
};

// The crossover, phase margin and modulus margin of G_o (001 eq. 3.4).
struct SpeedLoopMargins {
  double crossover_hz = 0.0;           // first f with |G_o| = 1
  double phase_margin_deg = 0.0;       // 180 + arg G_o there
  double min_return_difference = 0.0;  // min |1 + G_o| over 0 < f < fs/2 (modulus margin)
  double min_return_difference_hz = 0.0;
};

class SpindleDrive {
 public:
  // @throws InputError for invalid params (validate) or an unstable closed loop.
  explicit SpindleDrive(const SpindleDriveParams& params = {});

  const SpindleDriveParams& params() const { return params_; }
  int delay_samples() const { return delay_samples_; }

  // Open-loop pieces. The plant: states [th1 - th2, w1, w2, I_act], inputs [held current
  // command I_nom[k-d] (A), tau_d (N m)], outputs [w1 (rad/s), I_act (A)].
  const DiscreteMimoSystem& plant() const { return plant_; }
  // The discrete PI gains: I_nom = Kp e + ki q, q[k+1] = q[k] + Ts e[k] (e in rad/s).
  double kp_a_s_per_rad() const { return params_.kp_a_s_per_rad; }
  double ki_a_per_rad() const { return params_.kp_a_s_per_rad / params_.ti_s; }
  // The closed loop (see the header comment for its states, inputs and outputs).
  const DiscreteMimoSystem& closed_loop() const { return closed_loop_; }
  // tau_d -> I_nom of the closed loop as a single-input single-output model (A per N m).
  DiscreteStateSpace torque_to_current_model() const;
  Eigen::VectorXcd closed_loop_poles() const;

  // Closed-loop FRFs at f_hz (>= 0).
  Eigen::VectorXcd torque_to_current(const Eigen::Ref<const Eigen::VectorXd>& f_hz) const;
  Eigen::VectorXcd speed_tracking(const Eigen::Ref<const Eigen::VectorXd>& f_hz) const;
  // The sweep FRFs from the open-loop pieces, at 0 < f_hz: G_o, G_loop (rpm/A), G_s (rpm/A),
  // and G_m = G_loop / G_s (the current loop with its delay), G_Omega = G_o / G_loop (A/rpm).
  Eigen::VectorXcd open_loop_gain(const Eigen::Ref<const Eigen::VectorXd>& f_hz) const;
  Eigen::VectorXcd velocity_plant(const Eigen::Ref<const Eigen::VectorXd>& f_hz) const;
  Eigen::VectorXcd mechanical(const Eigen::Ref<const Eigen::VectorXd>& f_hz) const;
  Eigen::VectorXcd current_loop(const Eigen::Ref<const Eigen::VectorXd>& f_hz) const;
  Eigen::VectorXcd speed_controller(const Eigen::Ref<const Eigen::VectorXd>& f_hz) const;

  // I_nom / tau_d at z = 1: 1 / Kt with the integral action.
  double dc_gain_torque_to_current() const;
  // Crossover by a 0.5 Hz scan and bisection; modulus margin on a 0.5 Hz grid.
  SpeedLoopMargins speed_loop_margins() const;
  // The undamped torsional mode of the free mechanics, sqrt(k (J1 + J2) / (J1 J2)) / (2 pi),
  // and its antiresonance seen at the motor, sqrt(k / J2) / (2 pi).
  double torsional_frequency_hz() const;
  double antiresonance_frequency_hz() const;

  // The closed-loop response to speed_ref_rpm and tau_d_Nm (equal lengths, finite), from the
  // steady state of speed_ref_rpm[0] with zero torque (a constant reference gives no
  // transient). Sample k of each output is y[k] = C x[k] + D u[k]. No heap allocation in the
  // time loop. @throws InputError for unequal lengths or non-finite samples.
  SpindleDriveRecord simulate(const Eigen::VectorXd& speed_ref_rpm,
                              const Eigen::VectorXd& tau_d_Nm) const;

 private:
  struct PlantFrf {
    std::complex<double> w_rpm;       // P_w: held current command -> w1 (rpm per A)
    std::complex<double> i;           // P_i: held current command -> I_act
    std::complex<double> delay;       // z^-d
    std::complex<double> controller;  // C(z) in A per rpm
  };
  PlantFrf plant_frf(double f_hz) const;

  SpindleDriveParams params_;
  int delay_samples_ = 0;
  DiscreteMimoSystem plant_;
  DiscreteMimoSystem closed_loop_;
};

}  // namespace sysid
}  // namespace chatterlab
