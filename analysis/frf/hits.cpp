#include "analysis/frf/hits.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "analysis/common/number_text.h"
#include "analysis/common/statistics.h"

namespace chatterlab {
namespace frf {
namespace {

constexpr double kMadToStd = 1.4826;  // std of a Gaussian = 1.4826 MAD

void check_inputs(const Eigen::Ref<const Eigen::VectorXd>& force,
                  const Eigen::Ref<const Eigen::VectorXd>& response, double fs_hz,
                  const HitOptions& o) {
  if (!(std::isfinite(fs_hz) && fs_hz > 0.0)) {
    throw InputError("tap sample_rate_hz = " + std::to_string(fs_hz) + ": must be > 0");
  }
  if (force.size() != response.size()) {
    throw InputError("tap force has " + std::to_string(force.size()) + " samples, response " +
                     std::to_string(response.size()) + ": must be equal");
  }
  if (force.size() < kMinTapRecordSamples) {
    throw InputError("tap record has " + std::to_string(force.size()) +
                     " samples: needs at least " + std::to_string(kMinTapRecordSamples));
  }
  for (Eigen::Index i = 0; i < force.size(); ++i) {
    if (!std::isfinite(force[i]) || !std::isfinite(response[i])) {
      throw InputError("tap sample " + std::to_string(i) + " (force " + std::to_string(force[i]) +
                       ", response " + std::to_string(response[i]) + "): must be finite");
    }
  }
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw InputError("hits." + what);
  };
  require(positive(o.threshold_fraction) && o.threshold_fraction < 1.0,
          "threshold_fraction = " + std::to_string(o.threshold_fraction) + ": must be in (0, 1)");
  require(o.noise_multiple >= 0.0,
          "noise_multiple = " + std::to_string(o.noise_multiple) + ": must be >= 0");
  require(o.pretrigger_s >= 0.0,
          "pretrigger_s = " + std::to_string(o.pretrigger_s) + ": must be >= 0");
  require(o.double_hit_window_s >= 0.0,
          "double_hit_window_s = " + std::to_string(o.double_hit_window_s) + ": must be >= 0");
  require(o.max_record_s >= 0.0,
          "max_record_s = " + std::to_string(o.max_record_s) + ": must be >= 0 (0 = no cap)");
  require(o.min_record_fraction >= 0.0 && o.min_record_fraction <= 1.0,
          "min_record_fraction = " + std::to_string(o.min_record_fraction) + ": must be in [0, 1]");
  require(o.clip_min_samples >= 2,
          "clip_min_samples = " + std::to_string(o.clip_min_samples) + ": must be >= 2");
  require(o.clip_tolerance >= 0.0,
          "clip_tolerance = " + std::to_string(o.clip_tolerance) + ": must be >= 0");
}

struct Pulse {
  Eigen::Index trigger = 0;
  Eigen::Index end = 0;  // first sample below threshold
  double peak = 0.0;
};

// Runs of force - baseline >= threshold in [from, to).
std::vector<Pulse> find_pulses(const Eigen::Ref<const Eigen::VectorXd>& force, double baseline,
                               double threshold, Eigen::Index from, Eigen::Index to) {
  std::vector<Pulse> pulses;
  Eigen::Index i = from;
  while (i < to) {
    if (force[i] - baseline < threshold) {
      ++i;
      continue;
    }
    Pulse p;
    p.trigger = i;
    while (i < to && force[i] - baseline >= threshold) {
      p.peak = std::max(p.peak, force[i] - baseline);
      ++i;
    }
    p.end = i;
    pulses.push_back(p);
  }
  return pulses;
}

// "clipped: ..." when [from, to) holds a run of >= clip_min_samples samples at one of the
// channel's extremes hi, lo (its global maximum and minimum).
std::string clipping(const Eigen::Ref<const Eigen::VectorXd>& x, double hi, double lo,
                     const char* channel, Eigen::Index from, Eigen::Index to, double fs_hz,
                     const HitOptions& o) {
  const double tol = o.clip_tolerance * (hi - lo);
  for (const double extreme : {hi, lo}) {
    Eigen::Index run = 0;
    for (Eigen::Index i = from; i < to; ++i) {
      run = (std::abs(x[i] - extreme) <= tol) ? run + 1 : 0;
      if (run == o.clip_min_samples) {
        Eigen::Index j = i;
        while (j + 1 < to && std::abs(x[j + 1] - extreme) <= tol) ++j;
        const Eigen::Index first = i - run + 1;
        return std::string("clipped: ") + channel + " flat at its extreme " +
               printf_text("%.6g", extreme) + " for " + std::to_string(j - first + 1) +
               " samples from t = " + printf_text("%.6f", static_cast<double>(first) / fs_hz) +
               " s";
      }
    }
  }
  return {};
}

HitSet baseline_and_threshold(const Eigen::Ref<const Eigen::VectorXd>& force,
                              const Eigen::Ref<const Eigen::VectorXd>& response, double fs_hz,
                              const HitOptions& o, double* largest_peak, double* largest_dip) {
  HitSet set;
  set.fs_hz = fs_hz;
  set.force_baseline_n = median(force);
  set.response_baseline = median(response);
  set.force_noise_n = kMadToStd * median((force.array() - set.force_baseline_n).abs().matrix());
  *largest_peak = force.maxCoeff() - set.force_baseline_n;
  *largest_dip = set.force_baseline_n - force.minCoeff();
  set.threshold_n = std::max(o.threshold_fraction * std::max(*largest_peak, 0.0),
                             o.noise_multiple * set.force_noise_n);
  return set;
}

// Rule 5 on every hit still accepted, then the summary.
void judge(const Eigen::Ref<const Eigen::VectorXd>& force,
           const Eigen::Ref<const Eigen::VectorXd>& response, const std::vector<Pulse>& pulses,
           const HitOptions& o, HitSet* set) {
  const double f_hi = force.maxCoeff();
  const double f_lo = force.minCoeff();
  const double x_hi = response.maxCoeff();
  const double x_lo = response.minCoeff();
  for (Hit& hit : set->hits) {
    if (!hit.rejection.empty()) continue;
    for (const Pulse& p : pulses) {
      if (p.trigger > hit.trigger && p.trigger < hit.end) {
        hit.rejection = "double hit at t = " +
                        printf_text("%.6f", static_cast<double>(p.trigger) / set->fs_hz) + " s";
        break;
      }
    }
    if (hit.rejection.empty())
      hit.rejection = clipping(force, f_hi, f_lo, "force", hit.start, hit.end, set->fs_hz, o);
    if (hit.rejection.empty())
      hit.rejection = clipping(response, x_hi, x_lo, "response", hit.start, hit.end, set->fs_hz, o);
    hit.accepted = hit.rejection.empty();
  }
  std::string reasons;
  for (size_t i = 0; i < set->hits.size(); ++i) {
    const Hit& hit = set->hits[i];
    if (hit.accepted) continue;
    const std::string line = "hit " + std::to_string(i + 1) +
                             " at t = " + printf_text("%.6f", hit.time_s) +
                             " s rejected: " + hit.rejection;
    set->summary.warnings.push_back(line);
    reasons += (reasons.empty() ? "" : "; ") + line;
  }
  if (set->accepted_count() == 0) {
    set->summary.fail("no accepted hit among " + std::to_string(set->hits.size()) + ": " + reasons);
  } else {
    set->summary.succeed();
  }
}

}  // namespace

int HitSet::accepted_count() const {
  return static_cast<int>(
      std::count_if(hits.begin(), hits.end(), [](const Hit& h) { return h.accepted; }));
}

HitSet detect_hits(const Eigen::Ref<const Eigen::VectorXd>& force,
                   const Eigen::Ref<const Eigen::VectorXd>& response, double fs_hz,
                   const HitOptions& o) {
  check_inputs(force, response, fs_hz, o);
  const Eigen::Index n = force.size();
  double largest_peak = 0.0;
  double largest_dip = 0.0;
  HitSet set = baseline_and_threshold(force, response, fs_hz, o, &largest_peak, &largest_dip);
  if (!(largest_peak >= set.threshold_n) || !(set.threshold_n > 0.0)) {
    std::string why = "no hit above threshold: largest force peak " +
                      printf_text("%.4g", largest_peak) + " N above the baseline " +
                      printf_text("%.4g", set.force_baseline_n) + " N is below the threshold " +
                      printf_text("%.4g", set.threshold_n) + " N (" +
                      printf_text("%g", o.noise_multiple) + " x noise std " +
                      printf_text("%.4g", set.force_noise_n) + " N)";
    if (largest_dip > 2.0 * std::max(largest_peak, 0.0) && largest_dip >= set.threshold_n) {
      why += "; the force has a negative pulse of -" + printf_text("%.4g", largest_dip) +
             " N: is the hammer channel's sign inverted?";
    }
    set.summary.fail(why);
    return set;
  }
  const std::vector<Pulse> pulses = find_pulses(force, set.force_baseline_n, set.threshold_n, 0, n);

  // Rule 3: primary pulses start hits.
  const auto bounce = static_cast<Eigen::Index>(std::llround(o.double_hit_window_s * fs_hz));
  const auto pre = static_cast<Eigen::Index>(std::llround(o.pretrigger_s * fs_hz));
  for (const Pulse& p : pulses) {
    if (!set.hits.empty() && p.trigger - set.hits.back().trigger < bounce) continue;
    Hit hit;
    hit.trigger = p.trigger;
    hit.pulse_end = p.end;
    hit.time_s = static_cast<double>(p.trigger) / fs_hz;
    hit.peak_force_n = p.peak;
    hit.start = std::max<Eigen::Index>(0, p.trigger - pre);
    set.hits.push_back(hit);
  }

  // Rule 4: one record length for all.
  std::vector<Eigen::Index> space(set.hits.size());
  for (size_t i = 0; i < set.hits.size(); ++i) {
    const Eigen::Index next = (i + 1 < set.hits.size()) ? set.hits[i + 1].start : n;
    space[i] = next - set.hits[i].start;
  }
  std::vector<Eigen::Index> sorted = space;
  std::sort(sorted.begin(), sorted.end());
  const double median_space = static_cast<double>(sorted[sorted.size() / 2]);
  Eigen::Index length = n;
  for (size_t i = 0; i < set.hits.size(); ++i) {
    if (static_cast<double>(space[i]) < o.min_record_fraction * median_space) {
      set.hits[i].rejection = "record too short: only " +
                              printf_text("%.4g", static_cast<double>(space[i]) / fs_hz) +
                              " s until the next hit or the end of the data (the median is " +
                              printf_text("%.4g", median_space / fs_hz) + " s)";
    } else {
      length = std::min(length, space[i]);
    }
  }
  if (o.max_record_s > 0.0) {
    length = std::min(length, static_cast<Eigen::Index>(std::llround(o.max_record_s * fs_hz)));
  }
  set.record_samples = length;
  for (Hit& hit : set.hits) hit.end = std::min(n, hit.start + length);
  judge(force, response, pulses, o, &set);
  return set;
}

HitSet hits_from_windows(const Eigen::Ref<const Eigen::VectorXd>& force,
                         const Eigen::Ref<const Eigen::VectorXd>& response, double fs_hz,
                         const std::vector<std::array<double, 2>>& windows_s, const HitOptions& o) {
  check_inputs(force, response, fs_hz, o);
  const Eigen::Index n = force.size();
  if (windows_s.empty()) throw InputError("hits: the list of windows is empty");
  double largest_peak = 0.0;
  double largest_dip = 0.0;
  HitSet set = baseline_and_threshold(force, response, fs_hz, o, &largest_peak, &largest_dip);
  Eigen::Index length = n;
  for (size_t i = 0; i < windows_s.size(); ++i) {
    const auto a = static_cast<Eigen::Index>(std::llround(windows_s[i][0] * fs_hz));
    const auto b = static_cast<Eigen::Index>(std::llround(windows_s[i][1] * fs_hz));
    if (a < 0 || b > n || b <= a) {
      throw InputError("hits[" + std::to_string(i) + "] = [" + printf_text("%g", windows_s[i][0]) +
                       ", " + printf_text("%g", windows_s[i][1]) +
                       "] s: must satisfy 0 <= start < end <= " +
                       printf_text("%g", static_cast<double>(n) / fs_hz) + " s (the data length)");
    }
    Hit hit;
    hit.start = a;
    length = std::min(length, b - a);
    set.hits.push_back(hit);
  }
  set.record_samples = length;
  std::vector<Pulse> all;
  for (Hit& hit : set.hits) {
    hit.end = hit.start + length;
    const std::vector<Pulse> in =
        find_pulses(force, set.force_baseline_n, set.threshold_n, hit.start, hit.end);
    if (in.empty() || !(set.threshold_n > 0.0)) {
      hit.trigger = hit.start;
      hit.pulse_end = hit.start;
      hit.time_s = static_cast<double>(hit.start) / fs_hz;
      hit.rejection = "no force above the threshold " + printf_text("%.4g", set.threshold_n) +
                      " N in the window";
      continue;
    }
    hit.trigger = in.front().trigger;
    hit.pulse_end = in.front().end;
    hit.peak_force_n = in.front().peak;
    hit.time_s = static_cast<double>(hit.trigger) / fs_hz;
    all.insert(all.end(), in.begin(), in.end());
  }
  judge(force, response, all, o, &set);
  return set;
}

}  // namespace frf
}  // namespace chatterlab
