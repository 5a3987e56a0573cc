#include "app/kinds/common/hammer_hits.h"

#include <algorithm>
#include <cmath>

#include "app/core/format.h"
#include "app/kinds/common/conditions.h"

namespace chatterlab::app {

HammerHits read_hammer_hits(const YAML::Node& root, YamlReader& r) {
  HammerHits h;
  const YAML::Node hits = root["hits"];
  if (!hits) {
    r.error("hits", "is required: a list of [start_s, end_s] windows, or auto");
  } else if (hits.IsScalar() && hits.as<std::string>() == "auto") {
    h.automatic = true;
  } else if (!hits.IsSequence() || hits.size() == 0) {
    r.error("hits", "must be a list of [start_s, end_s] windows, or auto");
  } else {
    for (std::size_t i = 0; i < hits.size(); ++i) {
      const std::string key = "hits[" + std::to_string(i) + "]";
      try {
        const YAML::Node w = hits[i];
        if (!w.IsSequence() || w.size() != 2) throw YAML::Exception(YAML::Mark::null_mark(), "");
        const double a = w[0].as<double>(), b = w[1].as<double>();
        if (!(a >= 0 && b > a)) {
          r.error(key, "must be [start_s, end_s] with 0 <= start_s < end_s");
          continue;
        }
        h.windows_s.emplace_back(a, b);
      } catch (const YAML::Exception&) {
        r.error(key, "must be [start_s, end_s], two numbers");
      }
    }
  }
  return h;
}

std::vector<std::string> hammer_hits_outside(const TestSpec& t, const HammerHits& hits,
                                             double duration_s) {
  std::vector<std::string> e;
  for (std::size_t i = 0; i < hits.windows_s.size(); ++i) {
    if (auto m = window_outside(t, "hits[" + std::to_string(i) + "]", hits.windows_s[i].second,
                                duration_s)) {
      e.push_back(*m);
    }
  }
  return e;
}

std::vector<sifs::TapWindow> hammer_windows(const TestSpec& t, const HammerHits& hits,
                                            const Eigen::VectorXd& hammer_n,
                                            const std::string& label,
                                            std::vector<std::string>& warnings) {
  const double fs = t.sample_rate_hz;
  std::vector<sifs::TapWindow> windows;
  if (hits.automatic) {
    try {
      windows = sifs::auto_tap_windows(hammer_n, fs);
    } catch (const InputError& e) {
      throw InputError(label + ": hits: auto: " + e.what());
    }
  } else {
    // Equal lengths: the shortest window's sample count for all (they differ at most by
    // rounding).
    Eigen::Index len = -1;
    for (const auto& h : hits.windows_s) {
      const Eigen::Index n = static_cast<Eigen::Index>(std::llround((h.second - h.first) * fs));
      len = len < 0 ? n : std::min(len, n);
    }
    for (std::size_t i = 0; i < hits.windows_s.size(); ++i) {
      const Eigen::Index b = static_cast<Eigen::Index>(std::llround(hits.windows_s[i].first * fs));
      const Eigen::Index n = static_cast<Eigen::Index>(
          std::llround((hits.windows_s[i].second - hits.windows_s[i].first) * fs));
      if (n > len + 1) {
        throw InputError(t.yaml_label + ": key 'hits[" + std::to_string(i) +
                         "]': the windows must have equal lengths (this one is " +
                         fmt_sig(static_cast<double>(n) / fs, 6) + " s, the shortest " +
                         fmt_sig(static_cast<double>(len) / fs, 6) + " s)");
      }
      if (b + len > hammer_n.size()) {
        throw InputError(t.yaml_label + ": key 'hits[" + std::to_string(i) + "]': the window [" +
                         fmt_sig(hits.windows_s[i].first, 6) + ", " +
                         fmt_sig(hits.windows_s[i].first + static_cast<double>(len) / fs, 6) +
                         "] s runs past the end of the record (" +
                         fmt_sig(static_cast<double>(hammer_n.size()) / fs, 6) + " s)");
      }
      windows.push_back({b, b + len});
    }
  }
  // A window shorter than this resolves the FRF more coarsely than a tap test should (auto:
  // the closest pair of hits, or a hit near the record's end, sets every window's length).
  constexpr double kShortWindowS = 0.1;
  if (!windows.empty()) {
    const double w_s = static_cast<double>(windows.front().end - windows.front().begin) / fs;
    if (w_s < kShortWindowS) {
      warnings.push_back("hit windows are " + fmt_sig(w_s, 3) + " s long (frequency resolution " +
                         fmt_sig(1.0 / w_s, 3) + " Hz)" +
                         (hits.automatic
                              ? ": with hits: auto the closest pair of hits (or a hit near "
                                "the record's end) sets the length of every window; "
                                "give the windows as hits: [[start, end], ...]"
                              : ""));
    }
  }
  return windows;
}

}  // namespace chatterlab::app
