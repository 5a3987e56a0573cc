// Hit detection in impact-hammer records (several hits in one force/response record).
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace frf {

// The shortest tap record the hit detection takes (samples of force and response).
inline constexpr int kMinTapRecordSamples = 16;

// Rules, in the order they apply (docs/tap-tests.md explains each default):
//  1. Baselines: each channel's median is its offset (hits are a tiny part of a record).
//     Force noise std = 1.4826 * median |f - median(f)| (MAD, blind to the pulses).
//  2. Threshold on the force above its baseline:
//       threshold = max(threshold_fraction * largest peak, noise_multiple * noise std).
//     A pulse is a run of samples at or above the threshold.
//  3. A pulse starting less than double_hit_window_s after the trigger of the current hit is
//     a bounce of that hit (a double hit); any other pulse starts a new hit.
//  4. Records: each starts pretrigger_s before its trigger (or at sample 0) and all have the
//     same length L = the smallest space from one record start to the next (or to the end
//     of the data), capped by max_record_s, so every FRF has the same bins. A hit whose
//     space is below min_record_fraction * the median space is rejected instead of
//     shortening every record.
//  5. Rejections: a bounce inside the record ("double hit at t = ... s"); a run of at least
//     clip_min_samples samples within clip_tolerance * range of a channel's extreme
//     ("clipped: ...").
struct HitOptions {
  double threshold_fraction = 0.05;  // of the largest force peak; low enough for weak hits
  double noise_multiple = 10.0;      // of the force noise std: no false trigger on noise
  double pretrigger_s = 1e-3;        // record start before the trigger sample
  double double_hit_window_s = 0.1;  // hammer bounces come within ms; taps are > 0.1 s apart
  double max_record_s = 0.0;         // cap on the record length; 0 = no cap
  double min_record_fraction = 0.5;  // of the median hit spacing (rule 4)
  int clip_min_samples = 3;          // flat run length that counts as clipping
  double clip_tolerance = 1e-6;      // of the channel's range (max - min)
};

struct Hit {
  Eigen::Index start = 0;      // first sample of the analysis record
  Eigen::Index end = 0;        // one past its last sample; end - start is the same for all
  Eigen::Index trigger = 0;    // first sample with force - baseline >= threshold
  Eigen::Index pulse_end = 0;  // first sample after trigger below the threshold
  double time_s = 0.0;         // trigger / fs
  double peak_force_n = 0.0;   // largest force - baseline in the pulse
  bool accepted = false;
  // Why not accepted ("double hit at t = ... s", "clipped: ...", "record too short: ...");
  // empty when accepted.
  std::string rejection;
};

struct HitSet {
  StepSummary summary;  // fails when no hit is above the threshold or none is accepted
  std::vector<Hit> hits;
  Eigen::Index record_samples = 0;  // L, common to every hit
  double fs_hz = 0.0;
  double threshold_n = 0.0;        // above the force baseline
  double force_noise_n = 0.0;      // MAD noise std of the force
  double force_baseline_n = 0.0;   // median of the force channel
  double response_baseline = 0.0;  // median of the response channel

  int accepted_count() const;
};

// Detects hits automatically (rules above).
// @param force_n   hammer force (N), n samples
// @param response  response (any unit), n samples
// @param fs_hz     sample rate, > 0
// @throws InputError on mismatched lengths, fewer than 16 samples, non-finite samples,
//         fs_hz <= 0 or invalid options
HitSet detect_hits(const Eigen::Ref<const Eigen::VectorXd>& force_n,
                   const Eigen::Ref<const Eigen::VectorXd>& response, double fs_hz,
                   const HitOptions& options = {});

// Hits in given windows [start_s, end_s) (EXPERIMENT_FORMAT.md `hits: [[start_s, end_s], ...]`).
// Every record has the length of the shortest window; the trigger is the first sample at
// or above the threshold of rule 2 in the window; rule 5 applies, and a window without
// such a sample is rejected.
// @throws InputError as detect_hits, and for a window outside the data or with end <= start
HitSet hits_from_windows(const Eigen::Ref<const Eigen::VectorXd>& force_n,
                         const Eigen::Ref<const Eigen::VectorXd>& response, double fs_hz,
                         const std::vector<std::array<double, 2>>& windows_s,
                         const HitOptions& options = {});

}  // namespace frf
}  // namespace chatterlab
