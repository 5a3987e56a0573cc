// fields() of the analysis structs that kinds' results hold (app/core/archive.h), each in its
// struct's namespace. A kind's own structs list theirs beside the kind.
#pragma once

#include "analysis/common/cutting_coefficients.h"
#include "analysis/common/modal_parameters.h"
#include "analysis/cutting/dyno_slot.h"
#include "analysis/cutting/slot_fit.h"
#include "analysis/dynamics/bifurcation.h"
#include "analysis/dynamics/poincare.h"
#include "analysis/estimate/ekf_variants.h"
#include "analysis/estimate/estimation_window.h"
#include "analysis/estimate/identification.h"
#include "analysis/estimate/joint_identification.h"
#include "analysis/estimate/observability.h"
#include "analysis/estimate/repeatability.h"
#include "analysis/frf/modal_fit.h"
#include "analysis/frf/mode.h"
#include "analysis/kalman/chi_square.h"
#include "analysis/kalman/consistency.h"
#include "analysis/lobes/lobes.h"
#include "analysis/sync/offset_angle.h"
#include "analysis/sync/offset_search.h"
#include "analysis/sync/revolution_mean.h"
#include "analysis/sync/tach_angle.h"
#include "app/core/archive.h"

namespace chatterlab {

template <class Ar>
void fields(Ar& ar, ModalParameters& p) {
  LAYOUT_GUARD(ModalParameters, 24);
  ar(p.m_kg, p.c_kg_s, p.k_N_m);
}

template <class Ar>
void fields(Ar& ar, CuttingCoefficients& k) {
  LAYOUT_GUARD(CuttingCoefficients, 32);
  ar(k.Kt_N_m2, k.Kr_N_m2, k.Kte_N_m, k.Kre_N_m);
}

namespace cutting {

template <class Ar>
void fields(Ar& ar, SlotRecordResult& r) {
  LAYOUT_GUARD(SlotRecordResult, 224);
  ar(r.summary, r.theta_dyn_rad, r.mean_Ft_N, r.mean_Fr_N, r.revolutions, r.measured_rpm,
     r.offset_x_N, r.offset_y_N, r.switching_contrast, r.per_revolution_Ft_N, r.per_revolution_Fr_N,
     r.spread_Ft_N, r.spread_Fr_N);
}

template <class Ar>
void fields(Ar& ar, FittedLine& l) {
  LAYOUT_GUARD(FittedLine, 32);
  ar(l.slope_N_per_m2, l.intercept_N_per_m, l.rms_residual_N, l.r_squared);
}

template <class Ar>
void fields(Ar& ar, SlotCoefficients& c) {
  LAYOUT_GUARD(SlotCoefficients, 208);
  ar(c.summary, c.coefficients, c.tangential, c.radial, c.mean_force_model, c.records,
     c.distinct_feeds);
}

}  // namespace cutting

namespace sync {

template <class Ar>
void fields(Ar& ar, TachAngle& t) {
  LAYOUT_GUARD(TachAngle, 216);
  ar(t.summary, t.fs_hz, t.edges, t.phase_rad, t.revolutions, t.measured_rpm, t.min_rpm, t.max_rpm,
     t.expected_rpm, t.low_V, t.high_V, t.threshold_V, t.hysteresis_V);
}

template <class Ar>
void fields(Ar& ar, RevolutionRange& r) {
  LAYOUT_GUARD(RevolutionRange, 8);
  ar(r.first, r.count);
}

template <class Ar>
void fields(Ar& ar, RevolutionMean& m) {
  LAYOUT_GUARD(RevolutionMean, 104);
  ar(m.phase_rad, m.x_m, m.y_m, m.std_x_m, m.std_y_m, m.revolutions, m.start_s, m.end_s);
}

template <class Ar>
void fields(Ar& ar, OffsetSearch& s) {
  LAYOUT_GUARD(OffsetSearch, 80);
  ar(s.offset_angle_deg, s.rms_error_m, s.candidate_deg, s.error_m, s.runner_up_deg,
     s.runner_up_error_m, s.runner_up_ratio, s.ambiguous);
}

template <class Ar>
void fields(Ar& ar, OffsetAngleResult& o) {
  LAYOUT_GUARD(OffsetAngleResult, 320);
  ar(o.summary, o.search, o.model_teeth_alike, o.relative_error, o.depth_m, o.measured_revolutions,
     o.theta1_deg, o.simulated_x_m, o.simulated_y_m, o.measured_x_m, o.measured_y_m,
     o.settle_change, o.simulated_revolutions, o.simulation_runtime_s, o.search_runtime_s);
}

}  // namespace sync

namespace dynamics {

template <class Ar>
void fields(Ar& ar, Transition& t) {
  LAYOUT_GUARD(Transition, 24);
  ar(t.revolution, t.depth_m, t.kind);
}

template <class Ar>
void fields(Ar& ar, ChatterIsland& i) {
  LAYOUT_GUARD(ChatterIsland, 32);
  ar(i.onset_revolution, i.end_revolution, i.onset_depth_m, i.end_depth_m);
}

template <class Ar>
void fields(Ar& ar, BifurcationResult& b) {
  LAYOUT_GUARD(BifurcationResult, 248);
  ar(b.summary, b.profile, b.verdict, b.bifurcation_depth_m, b.transitions, b.islands, b.state,
     b.spread_m, b.noise_floor_m, b.noise_floor_source, b.enter_threshold_m, b.exit_threshold_m,
     b.chatter_fraction);
}

template <class Ar>
void fields(Ar& ar, PoincareMap& p) {
  LAYOUT_GUARD(PoincareMap, 56);
  ar(p.requested_depth_m, p.centre_revolution, p.first_revolution, p.first_depth_m, p.last_depth_m,
     p.points_m);
}

template <class Ar>
void fields(Ar& ar, OrbitClass& o) {
  LAYOUT_GUARD(OrbitClass, 24);
  ar(o.shape, o.period, o.spread_m, o.phase_dispersion);
}

}  // namespace dynamics

namespace kalman {

template <class Ar>
void fields(Ar& ar, ChiSquareBand& b) {
  LAYOUT_GUARD(ChiSquareBand, 32);
  ar(b.lower, b.upper, b.dof, b.confidence);
}

template <class Ar>
void fields(Ar& ar, NisSummary& n) {
  LAYOUT_GUARD(NisSummary, 72);
  ar(n.updates, n.dof, n.mean, n.mean_band, n.fraction_inside, n.confidence);
}

}  // namespace kalman

namespace estimate {

template <class Ar>
void fields(Ar& ar, EstimationWindow& w) {
  LAYOUT_GUARD(EstimationWindow, 88);
  ar(w.start_s, w.end_s, w.depth_start_m, w.depth_end_m, w.rule, w.warnings);
}

template <class Ar>
void fields(Ar& ar, IdentificationPass& p) {
  LAYOUT_GUARD(IdentificationPass, 72);
  ar(p.offset_deg, p.coefficients, p.modal, p.offset_after_deg, p.offset_relative_error);
}

template <class Ar>
void fields(Ar& ar, IntervalValue& v) {
  LAYOUT_GUARD(IntervalValue, 40);
  ar(v.value, v.sd, v.lo, v.hi, v.identifiable);
}

template <class Ar>
void fields(Ar& ar, JointIdentificationResult& j) {
  LAYOUT_GUARD(JointIdentificationResult, 552);
  ar(j.summary, j.converged, j.termination, j.iterations, j.simulations, j.runtime_s, j.residuals,
     j.parameters, j.rms_error_m, j.start_rms_error_m, j.relative_error, j.residual_sd_m,
     j.residual_correlation_lag1, j.correlation_lags, j.variance_inflation, j.condition,
     j.singular_directions, j.offset_deg, j.fn_hz, j.zeta, j.m_kg, j.c_kg_s, j.k_N_m, j.Kt_N_m2,
     j.Kr_N_m2, j.Kt_over_k_per_m, j.Kr_over_k_per_m);
}

template <class Ar>
void fields(Ar& ar, ObservabilityResult& o) {
  LAYOUT_GUARD(ObservabilityResult, 32);
  ar(o.rank, o.states, o.singular_values, o.relative_tolerance);
}

template <class Ar>
void fields(Ar& ar, Estimate& e) {
  LAYOUT_GUARD(Estimate, 48);
  ar(e.key, e.value, e.variance);
}

template <class Ar>
void fields(Ar& ar, EstimateHistory& h) {
  LAYOUT_GUARD(EstimateHistory, 64);
  ar(h.columns, h.time_s, h.values);
}

template <class Ar>
void fields(Ar& ar, EkfResult& r) {
  LAYOUT_GUARD(EkfResult, 384);
  ar(r.summary, r.id, r.estimator, r.estimates, r.final_state, r.covariance_diagonal, r.history,
     r.steps, r.runtime_s, r.time_step_s, r.filters, r.nis, r.nis_per_filter);
}

template <class Ar>
void fields(Ar& ar, RepeatabilityResult& r) {
  LAYOUT_GUARD(RepeatabilityResult, 272);
  ar(r.summary, r.keys, r.initial, r.finals, r.mean, r.std_dev, r.min, r.max, r.range, r.runs);
}

}  // namespace estimate

namespace lobes {

template <class Ar>
void fields(Ar& ar, LobesInput& i) {
  LAYOUT_GUARD(LobesInput, 160);
  ar(i.teeth, i.radius_m, i.Kt_N_m2, i.Kr_N_m2, i.operation, i.radial_immersion_m, i.x_modes,
     i.y_modes, i.spindle_rpm, i.max_depth_m);
}

template <class Ar>
void fields(Ar& ar, SpeedResult& r) {
  LAYOUT_GUARD(SpeedResult, 72);
  ar(r.spindle_rpm, r.limit_depth_m, r.type, r.chatter_hz, r.critical_multiplier_abs,
     r.critical_multiplier);
}

template <class Ar>
void fields(Ar& ar, LobesResult& r) {
  LAYOUT_GUARD(LobesResult, 136);
  ar(r.summary, r.revolution_period, r.speeds, r.runtime_s);
}

template <class Ar>
void fields(Ar& ar, ZeroOrderPoint& p) {
  LAYOUT_GUARD(ZeroOrderPoint, 32);
  ar(p.lobe, p.chatter_hz, p.spindle_rpm, p.depth_m);
}

template <class Ar>
void fields(Ar& ar, ZeroOrderResult& r) {
  LAYOUT_GUARD(ZeroOrderResult, 160);
  ar(r.lobes, r.raw);
}

}  // namespace lobes

namespace frf {

template <class Ar>
void fields(Ar& ar, Mode& m) {
  LAYOUT_GUARD(Mode, 40);
  fields(ar, static_cast<ModalParameters&>(m));
  ar(m.fn_hz, m.zeta);
}

template <class Ar>
void fields(Ar& ar, ModeQuality& q) {
  LAYOUT_GUARD(ModeQuality, 24);
  ar(q.resolution_limited, q.half_power_bins, q.negative_constant, q.at_bound, q.from_residual);
}

}  // namespace frf
}  // namespace chatterlab

// ---- forcerec, sysid (dyno-frf, force-record, frf, sweep-frf, spindle-current) --------------
#include "analysis/forcerec/akf.h"
#include "analysis/forcerec/deconvolution.h"
#include "analysis/forcerec/force_metrics.h"
#include "analysis/forcerec/model.h"
#include "analysis/forcerec/smo.h"
#include "analysis/forcerec/transfer_fit.h"
#include "analysis/sifs/sensor_model.h"
#include "analysis/sysid/era.h"
#include "analysis/sysid/state_space.h"
#include "analysis/sysid/torque_observer.h"

namespace chatterlab::sifs {

template <class Ar>
void fields(Ar& ar, TapFrf& f) {
  LAYOUT_GUARD(TapFrf, 192);
  ar(f.summary, f.f_hz, f.h1, f.coherence, f.hits, f.df_hz, f.impact, f.r_tap_n);
}

}  // namespace chatterlab::sifs

namespace chatterlab::forcerec {

template <class Ar>
void fields(Ar& ar, RootPair& p) {
  LAYOUT_GUARD(RootPair, 32);
  ar(p.s, p.fn_hz, p.zeta);
}

template <class Ar>
void fields(Ar& ar, TransferModel& m) {
  LAYOUT_GUARD(TransferModel, 104);
  ar(m.pole_pairs, m.real_poles_rad_s, m.zero_pairs, m.real_zeros_rad_s, m.b1);
}

template <class Ar>
void fields(Ar& ar, ContinuousModel& m) {
  LAYOUT_GUARD(ContinuousModel, 56);
  ar(m.A, m.B, m.C);
}

template <class Ar>
void fields(Ar& ar, TransferFit& f) {
  LAYOUT_GUARD(TransferFit, 400);
  ar(f.summary, f.model, f.num, f.den, f.dc_gain, f.fit_pct, f.vf_fit_pct, f.vf_iterations,
     f.refine_iterations, f.poles_flipped, f.zeros_mirrored, f.realization, f.realization_cond_A,
     f.band_lo_hz, f.band_hi_hz, f.f_hz, f.H, f.G);
}

template <class Ar>
void fields(Ar& ar, IndexWindow& w) {
  LAYOUT_GUARD(IndexWindow, 16);
  ar(w.begin, w.end);
}

template <class Ar>
void fields(Ar& ar, Harmonics& h) {
  LAYOUT_GUARD(Harmonics, 32);
  ar(h.mean_N, h.amplitudes_N);
}

template <class Ar>
void fields(Ar& ar, ReferenceError& e) {
  LAYOUT_GUARD(ReferenceError, 24);
  ar(e.nrmse_pct, e.fit_pct, e.lag_samples);
}

template <class Ar>
void fields(Ar& ar, SampleWindow& w) {
  LAYOUT_GUARD(SampleWindow, 16);
  ar(w.begin, w.end);
}

template <class Ar>
void fields(Ar& ar, AkfResult& r) {
  LAYOUT_GUARD(AkfResult, 216);
  ar(r.summary, r.S_N2, r.R_N2, r.S_from_knee, r.S_grid_N2, r.E, r.knee_index, r.tuning_window,
     r.tuning_skip, r.spectral_radius, r.modal, r.force);
}

template <class Ar>
void fields(Ar& ar, SmoResult& r) {
  LAYOUT_GUARD(SmoResult, 224);
  ar(r.summary, r.B2_1_s, r.zeros_rad_s, r.sampled_zeros, r.max_sampled_zero_modulus, r.corner_hz,
     r.effective_corner_hz, r.reach_ratio, r.delay_samples, r.amplitude_error, r.bandwidth_warning,
     r.force, r.output_error_N);
}

template <class Ar>
void fields(Ar& ar, LCurvePoint& p) {
  LAYOUT_GUARD(LCurvePoint, 24);
  ar(p.alpha, p.residual_norm_N, p.solution_norm_N);
}

template <class Ar>
void fields(Ar& ar, DeconvolutionResult& r) {
  LAYOUT_GUARD(DeconvolutionResult, 272);
  ar(r.force_N, r.alpha, r.rule, r.alpha_discrepancy, r.alpha_gcv, r.alpha_lcurve,
     r.discrepancy_satisfied, r.discrepancy_target_N2, r.lcurve, r.exact, r.residual_norm_N,
     r.solution_norm_N, r.relative_residual, r.refinements, r.fft_size, r.tail_length,
     r.decay_length, r.summary);
}

}  // namespace chatterlab::forcerec

namespace chatterlab::sysid {

template <class Ar>
void fields(Ar& ar, DiscreteStateSpace& m) {
  LAYOUT_GUARD(DiscreteStateSpace, 72);
  ar(m.A, m.B, m.C, m.D, m.sample_rate_hz);
}

template <class Ar>
void fields(Ar& ar, DiscreteMode& m) {
  LAYOUT_GUARD(DiscreteMode, 32);
  ar(m.z, m.fn_hz, m.zeta);
}

template <class Ar>
void fields(Ar& ar, EraRealization& r) {
  LAYOUT_GUARD(EraRealization, 208);
  ar(r.summary, r.model, r.singular_values, r.threshold, r.order_by_threshold, r.hankel_size,
     r.svd_s);
}

template <class Ar>
void fields(Ar& ar, EraResult& r) {
  LAYOUT_GUARD(EraResult, 512);
  ar(r.summary, r.realization, r.model, r.unstable_removed, r.decoupling_residual, r.poles, r.modes,
     r.dc_gain, r.fit_pct, r.fit_f_hz, r.fit_G, r.fit_G_model, r.markov_length, r.runtime_s);
}

template <class Ar>
void fields(Ar& ar, TorqueObserver& o) {
  LAYOUT_GUARD(TorqueObserver, 352);
  ar(o.summary, o.model, o.A_e, o.C_e, o.K, o.Q_Nm2, o.R_A2, o.dare_residual, o.spectral_radius,
     o.modal, o.block_size, o.Lambda, o.b_modal, o.c_modal, o.modal_residual);
}

}  // namespace chatterlab::sysid

// ---- sifs, grinding (sifs-static, sifs-tap, sifs-cut, grinding) ------------------------------
#include "analysis/grinding/multirate_ekf.h"
#include "analysis/sifs/calibration.h"
#include "analysis/sifs/compensator.h"
#include "analysis/sifs/sensor_model.h"
#include "analysis/signal/harmonic_fit.h"

namespace chatterlab::sifs {

template <class Ar>
void fields(Ar& ar, LoadWindow& w) {
  LAYOUT_GUARD(LoadWindow, 24);
  ar(w.start_s, w.end_s, w.load_n);
}

template <class Ar>
void fields(Ar& ar, StaticReduction& r) {
  LAYOUT_GUARD(StaticReduction, 288);
  ar(r.summary, r.axis, r.drift_offset, r.drift_per_s, r.windows, r.s, r.f);
}

template <class Ar>
void fields(Ar& ar, CalibrationFit& f) {
  LAYOUT_GUARD(CalibrationFit, 320);
  ar(f.summary, f.S, f.C, f.cond_S, f.residuals_n, f.residual_rms_n, f.residual_max_pct, f.windows,
     f.linearity_pct);
}

template <class Ar>
void fields(Ar& ar, TapWindow& w) {
  LAYOUT_GUARD(TapWindow, 16);
  ar(w.begin, w.end);
}

template <class Ar>
void fields(Ar& ar, SensorMode& m) {
  LAYOUT_GUARD(SensorMode, 24);
  ar(m.fn_hz, m.zeta, m.alpha);
}

template <class Ar>
void fields(Ar& ar, SensorModel& m) {
  LAYOUT_GUARD(SensorModel, 144);
  ar(m.summary, m.modes, m.static_gain, m.fit_nrmse_pct, m.iterations);
}

template <class Ar>
void fields(Ar& ar, ScaledModal& r) {
  LAYOUT_GUARD(ScaledModal, 64);
  ar(r.A, r.B, r.C, r.cond_A);
}

template <class Ar>
void fields(Ar& ar, FrfConfidence& c) {
  LAYOUT_GUARD(FrfConfidence, 32);
  ar(c.magnitude_sigma, c.phase_sigma_rad);
}

template <class Ar>
void fields(Ar& ar, SweepCurve& c) {
  LAYOUT_GUARD(SweepCurve, 176);
  ar(c.summary, c.exponents, c.rmse_n, c.best_exponent, c.q_opt, c.harmonics);
}

template <class Ar>
void fields(Ar& ar, TapMap& m) {
  LAYOUT_GUARD(TapMap, 96);
  ar(m.rpm, m.exponents, m.rmse_n, m.best_exponent);
}

}  // namespace chatterlab::sifs

namespace chatterlab::signal {

template <class Ar>
void fields(Ar& ar, HarmonicFit& h) {
  LAYOUT_GUARD(HarmonicFit, 168);
  ar(h.summary, h.fundamental_hz, h.harmonics, h.c0, h.c, h.residual_rms, h.samples);
}

}  // namespace chatterlab::signal

namespace chatterlab::grinding {

template <class Ar>
void fields(Ar& ar, Inspection& i) {
  LAYOUT_GUARD(Inspection, 32);
  ar(i.cycle, i.available_cycle, i.ds_mm, i.Ra_um, i.roundness_um);
}

template <class Ar>
void fields(Ar& ar, GrindingEstimate& e) {
  LAYOUT_GUARD(GrindingEstimate, 80);
  ar(e.cycle, e.j, e.x, e.three_sigma);
}

template <class Ar>
void fields(Ar& ar, CycleEstimate& c) {
  LAYOUT_GUARD(CycleEstimate, 272);
  ar(c.posterior, c.ds_prior_mm, c.ds_prior_3sigma_mm, c.Ra_pred_um, c.inspected,
     c.nis_fast_per_dof, c.nis_inspection_per_dof, c.nis_fast_dof, c.nis_inspection_dof,
     c.covariance);
}

template <class Ar>
void fields(Ar& ar, GrindingRun& r) {
  LAYOUT_GUARD(GrindingRun, 208);
  ar(r.id, r.summary, r.states, r.per_cycle, r.trajectory, r.nis_fast_sum, r.nis_fast_dof,
     r.nis_end_sum, r.nis_end_dof, r.steps, r.replayed_steps);
}

}  // namespace chatterlab::grinding
