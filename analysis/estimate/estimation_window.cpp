#include "analysis/estimate/estimation_window.h"

#include <algorithm>
#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/number_text.h"
#include "analysis/common/require.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace estimate {

EstimationWindow choose_estimation_window(const sync::CutSchedule& s, double spindle_rpm, int teeth,
                                          const std::optional<std::pair<double, double>>& given_s,
                                          const dynamics::BifurcationResult* bif,
                                          const EstimationWindowOptions& o) {
  require_rule(spindle_rpm > 0 && std::isfinite(spindle_rpm), "cut.spindle_rpm", spindle_rpm,
               "must be finite and > 0");
  require_rule(teeth >= 1, "tool.teeth", teeth, "must be >= 1");
  require_rule(o.window_s > 0 && std::isfinite(o.window_s), "estimation.window_s", o.window_s,
               "must be > 0");
  require_rule(o.settle_revolutions >= 0 && std::isfinite(o.settle_revolutions),
               "estimation.settle_revolutions", o.settle_revolutions, "must be >= 0");
  const double rev_s = kSecondsPerMinute / spindle_rpm;
  const double tau_s = rev_s / teeth;  // the chip delay: the filters start this much later
  const double first = s.cut_start_s + o.settle_revolutions * rev_s;
  const double last = s.cut_end_s - rev_s;
  EstimationWindow w;
  if (given_s) {
    w.start_s = given_s->first;
    w.end_s = given_s->second;
    w.rule = "test.yaml estimation_window_s";
  } else {
    const double length = o.window_s + tau_s;
    if (s.depth_start_m == s.depth_end_m) {
      w.end_s = last;
      w.rule = "the last " + significant_text(o.window_s, 4) + " s of the constant-depth cut";
    } else {
      const double lo = std::min(s.depth_start_m, s.depth_end_m);
      const double hi = std::max(s.depth_start_m, s.depth_end_m);
      double target = 0.75 * hi;
      if (bif && bif->summary.ok() && bif->bifurcation_depth_m) {
        target = 0.75 * *bif->bifurcation_depth_m;
        w.rule = "centred at 3/4 of the measured bifurcation depth";
      } else if (bif && bif->summary.ok() && bif->verdict == dynamics::RunVerdict::kAllChatter) {
        target = lo + 0.25 * (hi - lo);
        w.rule = "centred near the shallow end (the run chatters throughout)";
        w.warnings.push_back(
            "estimation: the bifurcation detector finds chatter over the whole run; the filters' "
            "model assumes chatter-free cutting");
      } else {
        w.rule = "centred at 3/4 of the deepest depth (no bifurcation measured)";
      }
      target = std::clamp(target, lo, hi);
      const double frac = (target - s.depth_start_m) / (s.depth_end_m - s.depth_start_m);
      const double centre = s.cut_start_s + frac * (s.cut_end_s - s.cut_start_s);
      w.end_s = centre + 0.5 * length;
    }
    w.end_s = std::min(w.end_s, last);
    w.start_s = std::max(first, w.end_s - length);
    w.end_s = std::min(last, w.start_s + length);
    if (w.end_s - w.start_s < 0.999 * length) {
      w.warnings.push_back("estimation: the cut holds " +
                           significant_text(std::max(0.0, w.end_s - w.start_s - tau_s), 3) +
                           " s of settled cutting, less than estimation.window_s = " +
                           significant_text(o.window_s, 4) + " s");
    }
  }
  if (!(w.end_s - w.start_s > 4 * rev_s)) {
    throw InputError("estimation window " + significant_text(w.start_s, 6) + " to " +
                     significant_text(w.end_s, 6) +
                     " s: the filters need at least four revolutions of settled cutting (after " +
                     significant_text(o.settle_revolutions, 4) + " settling revolutions)");
  }
  w.depth_start_m = s.depth_at_m(w.start_s);
  w.depth_end_m = s.depth_at_m(w.end_s);
  return w;
}

MeasuredCut window_samples(const Eigen::Ref<const Eigen::VectorXd>& x_m,
                           const Eigen::Ref<const Eigen::VectorXd>& y_m,
                           const Eigen::Ref<const Eigen::VectorXd>& theta1_rad, double fs,
                           const sync::CutSchedule& s, const EstimationWindow& w) {
  require_rule(fs > 0 && std::isfinite(fs), "record.sample_rate_hz", fs, "must be finite and > 0");
  require_rule(y_m.size() == x_m.size(), "record.y_m size", y_m.size(),
               "must equal record.x_m size " + std::to_string(x_m.size()));
  require_rule(theta1_rad.size() == x_m.size(), "record.theta1_rad size", theta1_rad.size(),
               "must equal record.x_m size " + std::to_string(x_m.size()));
  const auto i0 = static_cast<Eigen::Index>(std::ceil(w.start_s * fs));
  const auto i1 =
      std::min<Eigen::Index>(static_cast<Eigen::Index>(std::floor(w.end_s * fs)), x_m.size() - 1);
  if (i1 - i0 < 8) {
    throw InputError("estimation window " + significant_text(w.start_s, 6) + " to " +
                     significant_text(w.end_s, 6) + " s lies outside the record");
  }
  const Eigen::Index n = i1 - i0 + 1;
  MeasuredCut raw;
  raw.time_step_s = 1.0 / fs;
  raw.x_m = x_m.segment(i0, n);
  raw.y_m = y_m.segment(i0, n);
  raw.theta1_rad = theta1_rad.segment(i0, n);
  if (s.depth_start_m == s.depth_end_m) {
    raw.depth_m = Eigen::VectorXd::Constant(1, s.depth_start_m);
  } else {
    raw.depth_m.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      raw.depth_m[i] = s.depth_at_m(static_cast<double>(i0 + i) / fs);
    }
  }
  return raw;
}

}  // namespace estimate
}  // namespace chatterlab
