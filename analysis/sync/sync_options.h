// Options of the cut-run signal processing (000 secs 3.1 and 5.1): tachometer angle, runout
// contour removal and the offset-angle search. docs/cut-processing.md explains every choice.
#pragma once

#include <optional>

namespace chatterlab {
namespace sync {

struct TachOptions {
  // Level of a rising tachometer edge, V. Unset: midway between the channel's low and high
  // levels (tach_angle.h: the medians of the samples below and above the mid-range), the
  // steepest point of a band-limited pulse whatever its logic levels. test.yaml's
  // channels.tach.threshold, when given, goes here.
  std::optional<double> threshold_V;
  // The edge detector re-arms only below threshold - hysteresis_fraction (high - low): 0.1 of
  // a 0/5 V pulse is 0.5 V, as for the dynamometer zero-count (DynoOptions). In [0, 0.5).
  double hysteresis_fraction = 0.1;
  // Every interval between consecutive edges must be within this relative tolerance of
  // 60 fs / spindle_rpm samples: a missed or spurious pulse, or a wrong nominal speed, fails
  // the run. In (0, 1).
  double rpm_tolerance = 0.05;
};

struct ContourOptions {
  // Points N of the phase grid phi_j = 2 pi j / N on which each air revolution is resampled
  // (linear interpolation between samples) and averaged. 0: the nominal samples per revolution
  // 60 fs / spindle_rpm rounded (400 at 100 kHz and 15,000 rpm), so the grid is as fine as the
  // data. Otherwise >= 8.
  int phase_points = 0;
  // Fewer whole tachometer revolutions inside the air window fail the step: with one
  // revolution the contour would be that revolution's noise. >= 2.
  int min_air_revolutions = 2;
};

struct OffsetSearchOptions {
  // Revolutions simulated from rest at the comparison depth; the last one is compared. The
  // free vibration of table 5.2's incline-1 mode decays with time constant 1 / (zeta omega_n)
  // = 2 m / c = 2.8 ms = 0.7 revolutions at 15,000 rpm, so 100 revolutions leave e^-140 of the
  // start transient; a cut near its stability limit decays slower, which the settle check
  // below reports. 100 revolutions of the traditional model take about 1 ms. >= 2.
  int simulated_revolutions = 100;
  // Candidate offsets every coarse_step_deg over [0, 360) (000 sec. 5.1: one-degree steps).
  // In (0, 10].
  double coarse_step_deg = 1.0;
  // Golden-section refinement of the best coarse candidate (and of the runner-up) on
  // +-coarse_step_deg until the bracket is narrower than this, deg. In (0, coarse_step_deg].
  double resolution_deg = 1e-3;
  // With n teeth the runner-up is the best fit of another tooth alignment, near
  // offset + k 360 / n (offset_search.h). When its error is within this
  // fraction of the best error, "the other half turn fits almost as well" and the result is
  // flagged ambiguous: the offset is then defined modulo 360 / n only. >= 0.
  double ambiguity_ratio = 0.10;
  // The simulated revolution counts as settled when the RMS difference of its last two
  // revolutions is below this fraction of the last revolution's RMS; otherwise a warning (the
  // simulation chatters or decays slowly, and "the steady revolution" does not exist). > 0.
  double settle_tolerance = 0.01;
};

// Throw InputError naming the first field that breaks its rule ("tach.rpm_tolerance = 2: must
// be in (0, 1)").
void validate(const TachOptions& o);
void validate(const ContourOptions& o);
void validate(const OffsetSearchOptions& o);

}  // namespace sync
}  // namespace chatterlab
