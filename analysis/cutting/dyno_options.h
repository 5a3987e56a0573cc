// Options of the rotating-dynamometer slot method (000 sec. 3.2): per-record analysis and
// group fit of the cutting-force coefficients. See docs/dyno-coefficients.md.
#pragma once

namespace chatterlab {
namespace cutting {

// How the mean force magnitude over a revolution relates to the feed per tooth h in a
// two-tooth slot (000 eqs 3.5-3.6), hence how the fitted slopes give Ktc and Krc.
enum class SlotMeanForceModel {
  // One tooth cuts at a time with chip h sin(theta) (000 eqs 3.3-3.4 and 2.7):
  //   mean|F_t| = (2/pi) b Ktc h + b Kte   ->   Ktc = pi * slope / (2 b).
  // Agrees with the force model the simulator uses (analysis/milling/force_model.h).
  kSingleToothChip,
  // 000 eqs 3.5-3.6 as printed (chip doubled to 2h sin(theta)):
  //   mean|F_t| = (4/pi) b Ktc h + b Kte   ->   Ktc = pi * slope / (4 b)   (eqs 3.9, 3.11).
  // Gives half the Ktc, Krc of kSingleToothChip on the same data; edge terms are identical.
  kDissertationEq3_5,
};

struct DynoOptions {
  // Zero-count channel: a rising crossing of this level (V) starts a revolution. Midway in
  // a 0/5 V pulse, where a band-limited edge is steepest.
  double zero_threshold_V = 2.5;
  // The zero-count detector re-arms only below zero_threshold_V - zero_hysteresis_V (V), so
  // noise on the pulse plateau or edges cannot start two revolutions.
  double zero_hysteresis_V = 0.5;
  // Every zero-count interval must be within this relative tolerance of 60 / spindle_rpm
  // (a missed or spurious pulse, or a wrong nominal speed, fails the record).
  double rpm_tolerance = 0.05;
  // Records with fewer whole revolutions (between the first and last zero-count) fail.
  // 2 is the least with which the revolution spread means anything.
  int min_revolutions = 2;
  // Records sampled with fewer samples per nominal revolution (fs * 60 / rpm) fail: at
  // 36 samples (10 deg per sample) the mean of |sin| sampled at any phase is within 0.26 % of
  // its integral 2/pi (1 % at 18 samples); below it the fold on the revolution phase that
  // locates the tooth change becomes coarse.
  double min_samples_per_revolution = 36.0;
  // Switching-phase search for theta_dyn: a grid of this step (deg) over [0, 180), then a
  // refinement grid of theta_resolution_deg over +-1 coarse step around the best point.
  // The demodulated magnitude is unimodal in the switching phase, so a 1 deg grid cannot
  // miss the peak; 0.01 deg is ten times finer than the accuracy asked of theta_dyn.
  double theta_coarse_step_deg = 1.0;
  double theta_resolution_deg = 0.01;
  // Warn when the switching contrast |D(theta_dyn)| / mean|F| falls below this (D: the
  // demodulated mean force, dyno_slot.h). A clean one-tooth-at-a-time slot gives ~0.99 (the
  // force direction in the dynamometer frame only turns between the edge and cutting
  // directions); an air cut gives ~0 and runout or chatter lower it: theta_dyn is then weak.
  double switching_contrast_warning = 0.8;
  // Relation between mean force and feed used to turn the slopes into Ktc, Krc.
  SlotMeanForceModel mean_force_model = SlotMeanForceModel::kSingleToothChip;
  // Warn when a fitted line's R^2 falls below this: the mean forces are not linear in feed.
  double fit_r_squared_warning = 0.95;
};

// Throws InputError naming the first field that breaks its rule ("dyno.rpm_tolerance = -1:
// must be in (0, 1)").
void validate(const DynoOptions& options);

}  // namespace cutting
}  // namespace chatterlab
