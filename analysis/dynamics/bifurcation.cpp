#include "analysis/dynamics/bifurcation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>

#include "analysis/dynamics/local_spread.h"

namespace chatterlab {
namespace dynamics {

namespace {

constexpr double kMadToSigma = 1.482602218505602;  // 1 / Phi^-1(3/4)
// Asymptotic relative std of 1.4826 median|e| over M normal values: 1.166 / sqrt(M)
// (sqrt(p (1 - p)) / (2 phi(q) q) / sqrt(M) with p = 1/2 and q = 0.6745 the median of |N(0,1)|).
constexpr double kMedianScaleRelStd = 1.166;
// Warn when the quietest block's residuals correlate this strongly with themselves at a lag
// of 1..4 revolutions: white noise over a 200-revolution block gives |rho| ~ 0.07, a period
// two or four or a quasi-periodic orbit |rho| near 1 at one of these lags.
constexpr double kStructuredRho = 0.5;
constexpr int kMaxStructureLag = 4;

void check_finite(const Eigen::Ref<const Eigen::VectorXd>& v, const char* name) {
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) {
      std::ostringstream m;
      m << "bifurcation: " << name << "[" << i << "] = " << v[i] << ": must be finite";
      throw InputError(m.str());
    }
  }
}

std::string mm(double metres) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f mm", metres * 1e3);
  return buf;
}

std::string metres(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g m", value);
  return buf;
}

// Phi^-1(p) for 0 < p < 1, by bisection on the normal CDF (to 1e-12).
double normal_quantile(double p) {
  double lo = -40.0;
  double hi = 40.0;
  while (hi - lo > 1e-12) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

struct BlockFloor {
  double value = 0.0;
  double max_abs_rho = 0.0;  // serial structure of the block the value came from
};

// noise_quantile quantile of the robust std of e_n over blocks of B revolutions (the last
// block takes the remainder), with the lag-1..4 autocorrelation of that block. The picked order
// statistic j of K block values sits low by z sigma_b on noise alone, sigma_b = 1.166 / sqrt(B)
// the relative std of a median-based scale over B values and z = Phi^-1((j + 0.625) / (K + 0.25))
// (Blom's approximation to the expected normal order statistic); the value is divided by
// 1 + z sigma_b so that a run of noise alone gives its sigma (measured: docs sec. 3).
BlockFloor quietest_blocks(const Eigen::VectorXd& e, int block, double quantile) {
  const Eigen::Index n = e.size();
  const Eigen::Index count = std::max<Eigen::Index>(1, n / block);
  std::vector<std::pair<double, Eigen::Index>> scale;  // (value, block)
  std::vector<double> a;
  for (Eigen::Index b = 0; b < count; ++b) {
    const Eigen::Index begin = b * block;
    const Eigen::Index end = b + 1 == count ? n : begin + block;
    a.clear();
    for (Eigen::Index i = begin; i < end; ++i) a.push_back(std::abs(e[i]));
    const auto mid = a.begin() + static_cast<std::ptrdiff_t>(a.size() / 2);
    std::nth_element(a.begin(), mid, a.end());
    scale.emplace_back(kMadToSigma * *mid, b);
  }
  std::sort(scale.begin(), scale.end());
  const auto pick = static_cast<std::size_t>(std::floor(quantile * static_cast<double>(count - 1)));
  BlockFloor out;
  const double z =
      normal_quantile((static_cast<double>(pick) + 0.625) / (static_cast<double>(count) + 0.25));
  out.value =
      scale[pick].first / (1.0 + z * kMedianScaleRelStd / std::sqrt(static_cast<double>(block)));

  const Eigen::Index begin = scale[pick].second * block;
  const Eigen::Index end = scale[pick].second + 1 == count ? n : begin + block;
  const auto seg = e.segment(begin, end - begin);
  const double energy = seg.squaredNorm();
  if (energy > 0.0) {
    for (int lag = 1; lag <= kMaxStructureLag && lag < seg.size(); ++lag) {
      const double rho = seg.tail(seg.size() - lag).dot(seg.head(seg.size() - lag)) / energy;
      out.max_abs_rho = std::max(out.max_abs_rho, std::abs(rho));
    }
  }
  return out;
}

// Chatter episodes [start, end) by the hysteresis rule (bifurcation.h, step 3).
std::vector<std::pair<Eigen::Index, Eigen::Index>> chatter_episodes(const Eigen::VectorXd& s,
                                                                    double high, double low,
                                                                    int min_chatter, int min_stable,
                                                                    bool ends_unbounded) {
  const Eigen::Index n = s.size();
  std::vector<std::pair<Eigen::Index, Eigen::Index>> episodes;
  Eigen::Index previous_end = 0;
  Eigen::Index i = 0;
  while (i < n) {
    if (s[i] <= high) {
      ++i;
      continue;
    }
    Eigen::Index core_end = i;  // a run above the entry level: long enough to confirm?
    while (core_end < n && s[core_end] > high) ++core_end;
    // A final stretch of a run that ended unbounded needs no confirmation (ends_unbounded).
    if (core_end - i < min_chatter && !(ends_unbounded && core_end == n)) {
      i = core_end;
      continue;
    }
    Eigen::Index start = i;  // date the onset back to the exit level
    while (start > previous_end && s[start - 1] > low) --start;
    Eigen::Index end = n;
    Eigen::Index m = core_end;
    while (m < n) {
      if (s[m] > low) {
        ++m;
        continue;
      }
      Eigen::Index q = m;
      while (q < n && s[q] <= low) ++q;
      if (q - m >= min_stable || q == n) {
        end = m;
        break;
      }
      m = q;  // a short quiet stretch: chatter goes on
    }
    episodes.emplace_back(start, end);
    previous_end = end;
    i = end;
  }
  return episodes;
}

}  // namespace

const char* to_string(DepthProfile profile) {
  switch (profile) {
    case DepthProfile::kIncline:
      return "incline";
    case DepthProfile::kDecline:
      return "decline";
    case DepthProfile::kConstant:
      return "constant";
  }
  return "?";
}

const char* to_string(RunVerdict verdict) {
  switch (verdict) {
    case RunVerdict::kAllStable:
      return "chatter-free throughout";
    case RunVerdict::kAllChatter:
      return "chatter throughout";
    case RunVerdict::kChanges:
      return "changes state";
  }
  return "?";
}

const char* to_string(NoiseFloorSource source) {
  switch (source) {
    case NoiseFloorSource::kStated:
      return "stated measurement noise";
    case NoiseFloorSource::kQuietestBlocks:
      return "quietest blocks of the run";
    case NoiseFloorSource::kMinimum:
      return "minimum floor";
  }
  return "?";
}

const char* to_string(TransitionKind kind) {
  return kind == TransitionKind::kOnset ? "onset" : "end";
}

BifurcationResult detect_bifurcation(const Eigen::Ref<const Eigen::VectorXd>& depth_m,
                                     const Eigen::Ref<const Eigen::VectorXd>& x_m,
                                     const BifurcationOptions& options) {
  validate(options);
  if (depth_m.size() != x_m.size()) {
    std::ostringstream m;
    m << "bifurcation: depth_m has " << depth_m.size() << " revolutions, x_m " << x_m.size()
      << ": must be equal";
    throw InputError(m.str());
  }
  check_finite(depth_m, "depth_m");
  check_finite(x_m, "x_m");

  BifurcationResult result;
  const Eigen::Index n = x_m.size();
  const int w = options.window_revolutions;
  if (n < w) {
    std::ostringstream m;
    m << "run has " << n << " revolutions: at least window_revolutions = " << w << " needed";
    result.summary.fail(m.str());
    return result;
  }

  // Depth profile.
  const double change = depth_m[n - 1] - depth_m[0];
  const double tol = options.constant_depth_tolerance_m;
  result.profile = std::abs(change) <= tol ? DepthProfile::kConstant
                   : change > 0.0          ? DepthProfile::kIncline
                                           : DepthProfile::kDecline;
  const double sign = result.profile == DepthProfile::kDecline ? -1.0 : 1.0;
  double against = 0.0;  // largest step against the run's direction
  for (Eigen::Index i = 1; i < n; ++i) {
    const double step = sign * (depth_m[i] - depth_m[i - 1]);
    if (result.profile == DepthProfile::kConstant) {
      against = std::max(against, std::abs(depth_m[i] - depth_m[0]));
    } else {
      against = std::max(against, -step);
    }
  }
  if (against > tol) {
    result.summary.warnings.push_back(std::string("depth is not monotonic over the run (") +
                                      to_string(result.profile) + " by its ends, a departure of " +
                                      mm(against) +
                                      "): transitions are reported in revolution order");
  }

  // Statistic and noise floor.
  const LocalSpread spread = local_spread(x_m, w);
  result.spread_m = spread.spread;
  const BlockFloor blocks = quietest_blocks(
      spread.central_residual, options.noise_block_revolutions, options.noise_quantile);
  if (options.measurement_noise_m > 0.0) {
    result.noise_floor_m = options.measurement_noise_m;
    result.noise_floor_source = NoiseFloorSource::kStated;
    if (blocks.value > options.enter_factor * options.measurement_noise_m) {
      result.summary.warnings.push_back(
          "the quietest part of the run spreads by " + metres(blocks.value) + ", more than " +
          "enter_factor times the stated noise " + metres(options.measurement_noise_m) +
          ": the run chatters throughout, or the stated noise is too low");
    }
  } else {
    result.noise_floor_m = blocks.value;
    result.noise_floor_source = NoiseFloorSource::kQuietestBlocks;
    if (blocks.max_abs_rho > kStructuredRho && blocks.value > options.min_noise_floor_m) {
      char buf[48];
      std::snprintf(buf, sizeof buf, "%.2f", blocks.max_abs_rho);
      result.summary.warnings.push_back(
          std::string("the quietest part of the run is not white noise (autocorrelation ") + buf +
          " at a lag of 1-4 revolutions): it may be chatter, which would hide chatter " +
          "elsewhere; state measurement_noise_m to decide");
    }
  }
  if (!(result.noise_floor_m >= options.min_noise_floor_m)) {
    result.noise_floor_m = options.min_noise_floor_m;
    result.noise_floor_source = NoiseFloorSource::kMinimum;
  }
  result.enter_threshold_m = options.enter_factor * result.noise_floor_m;
  result.exit_threshold_m = options.exit_factor * result.noise_floor_m;

  // States and transitions.
  const auto episodes = chatter_episodes(spread.spread, result.enter_threshold_m,
                                         result.exit_threshold_m, options.min_chatter_revolutions,
                                         options.min_stable_revolutions, options.ends_unbounded);
  result.state.assign(static_cast<std::size_t>(n), RevolutionState::kStable);
  Eigen::Index chattering = 0;
  for (const auto& [start, end] : episodes) {
    for (Eigen::Index i = start; i < end; ++i) {
      result.state[static_cast<std::size_t>(i)] = RevolutionState::kChatter;
    }
    chattering += end - start;
    if (start > 0) result.transitions.push_back({start, depth_m[start], TransitionKind::kOnset});
    if (end < n) result.transitions.push_back({end, depth_m[end], TransitionKind::kEnd});
    if (start > 0 && end < n) {
      result.islands.push_back({start, end, depth_m[start], depth_m[end]});
      result.summary.warnings.push_back("chatter island from " + mm(depth_m[start]) + " to " +
                                        mm(depth_m[end]) + " (revolutions " +
                                        std::to_string(start) + " to " + std::to_string(end) + ")");
    }
  }
  result.chatter_fraction = static_cast<double>(chattering) / static_cast<double>(n);
  if (!result.transitions.empty()) {
    result.verdict = RunVerdict::kChanges;
  } else {
    result.verdict = chattering > 0 ? RunVerdict::kAllChatter : RunVerdict::kAllStable;
  }

  // Bifurcation depth by the format's rule.
  if (result.verdict == RunVerdict::kChanges && result.profile != DepthProfile::kConstant) {
    const bool incline = result.profile == DepthProfile::kIncline;
    const TransitionKind wanted = incline ? TransitionKind::kOnset : TransitionKind::kEnd;
    const Transition* pick = nullptr;
    for (const Transition& t : result.transitions) {
      if (t.kind != wanted) continue;
      if (pick == nullptr || !incline) pick = &t;  // incline: first onset; decline: last end
    }
    if (pick != nullptr) {
      result.bifurcation_depth_m = pick->depth_m;
    } else {
      result.summary.warnings.push_back(std::string("the ") + to_string(result.profile) +
                                        " changes state but has no " +
                                        (incline ? "onset of chatter (it chatters from its start)"
                                                 : "end of chatter (it chatters at its end)") +
                                        ": no bifurcation depth");
    }
  }
  result.summary.succeed();
  return result;
}

std::string full_report(const BifurcationResult& r) {
  std::ostringstream o;
  o << "bifurcation: " << r.summary.message << "\n";
  if (!r.summary.ok()) return o.str();
  o << "  run: " << to_string(r.profile) << ", " << r.state.size() << " revolutions, "
    << to_string(r.verdict);
  char buf[64];
  std::snprintf(buf, sizeof buf, " (%.1f %% chatter)", 100.0 * r.chatter_fraction);
  o << buf << "\n";
  o << "  noise floor " << metres(r.noise_floor_m) << " (" << to_string(r.noise_floor_source)
    << "), thresholds enter " << metres(r.enter_threshold_m) << ", exit "
    << metres(r.exit_threshold_m) << "\n";
  for (const Transition& t : r.transitions) {
    o << "  " << to_string(t.kind) << " at revolution " << t.revolution << ", depth "
      << mm(t.depth_m) << "\n";
  }
  o << "  bifurcation depth: ";
  if (r.profile == DepthProfile::kConstant) {
    o << "none (constant depth)\n";
  } else if (r.bifurcation_depth_m) {
    o << mm(*r.bifurcation_depth_m) << "\n";
  } else {
    o << "none\n";
  }
  for (const std::string& w : r.summary.warnings) o << "  warning: " << w << "\n";
  return o.str();
}

}  // namespace dynamics
}  // namespace chatterlab
