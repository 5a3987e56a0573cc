#include "app/core/yaml_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "analysis/common/summary.h"
#include "app/core/yaml_load.h"

namespace chatterlab::app {

void YamlReader::throw_if_errors() const {
  if (errors_.empty()) return;
  std::string msg;
  for (const auto& e : errors_) msg += (msg.empty() ? "" : "\n") + e;
  // The warnings too: a misspelt key is often why a key is missing.
  for (const auto& w : warnings_) msg += "\nwarning: " + w;
  throw InputError(msg);
}
namespace {

// A number in *out (possibly not finite: .inf, .nan, or 1e400 read as infinity).
bool as_double(const YAML::Node& n, double* out) {
  if (!n.IsScalar()) return false;
  try {
    *out = n.as<double>();
  } catch (const YAML::Exception&) {
    // libstdc++ fails on an out-of-range value such as 1e400: read it as an infinity so that it
    // is refused as non-finite rather than as "not a number".
    const std::string& t = n.Scalar();
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (t.empty() || end == nullptr || *end != '\0' || std::isfinite(v)) return false;
    *out = v;
  }
  return true;
}

std::string describe(const YAML::Node& n) {
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a mapping";
  return "null";
}

}  // namespace

int edit_distance(const std::string& a, const std::string& b) {
  std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int sub = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

bool within_edits(const std::string& a, const std::string& b, int edits) {
  // The length difference bounds the distance from below: long strings (a fuzzed key of a
  // megabyte) are not compared cell by cell against every known key.
  const auto diff = a.size() > b.size() ? a.size() - b.size() : b.size() - a.size();
  return diff <= static_cast<std::size_t>(edits) && edit_distance(a, b) <= edits;
}

bool looks_like(const std::string& written, const std::string& wanted) {
  if (written == wanted) return false;
  if (within_edits(written, wanted, 2)) return true;
  const auto& shorter = written.size() < wanted.size() ? written : wanted;
  const auto& longer = written.size() < wanted.size() ? wanted : written;
  return shorter.size() >= 4 && longer.compare(0, shorter.size(), shorter) == 0 &&
         longer[shorter.size()] == '_';
}

std::string YamlReader::key_path(const std::string& path, const std::string& key) const {
  return path.empty() ? key : path + "." + key;
}

void YamlReader::error(const std::string& key_path, const std::string& what) {
  errors_.push_back(file_ + ": key '" + key_path + "' " + what);
}

void YamlReader::warn(const std::string& key_path, const std::string& what) {
  warnings_.push_back(file_ + ": key '" + key_path + "' " + what);
}

std::string YamlReader::missing_message(const YAML::Node& map, const std::string& key) const {
  std::string msg = "is missing";
  if (map.IsMap()) {
    std::string best;
    int best_d = 1 << 20;
    for (const auto& kv : map) {
      if (!is_name_key(kv.first)) continue;
      const auto k = kv.first.Scalar();
      if (!looks_like(k, key)) continue;
      const int d = edit_distance(k, key);
      if (d < best_d) {
        best_d = d;
        best = k;
      }
    }
    if (!best.empty()) msg += " (found '" + best + "': misspelt?)";
  }
  return msg;
}

double YamlReader::required_double(const YAML::Node& map, const std::string& key,
                                   const std::string& path) {
  const YAML::Node n = map.IsMap() ? map[key] : YAML::Node();
  if (!n) {
    error(key_path(path, key), missing_message(map, key));
    return std::nan("");
  }
  double v = 0;
  if (!number(n, key_path(path, key), "a number", &v)) return std::nan("");
  return v;
}

std::string YamlReader::required_string(const YAML::Node& map, const std::string& key,
                                        const std::string& path) {
  const YAML::Node n = map.IsMap() ? map[key] : YAML::Node();
  if (!n) {
    error(key_path(path, key), missing_message(map, key));
    return {};
  }
  if (!n.IsScalar()) {
    error(key_path(path, key), "must be a string, got " + describe(n));
    return {};
  }
  return n.Scalar();
}

std::optional<double> YamlReader::optional_double(const YAML::Node& map, const std::string& key,
                                                  const std::string& path) {
  const YAML::Node n = map.IsMap() ? map[key] : YAML::Node();
  if (!n) return std::nullopt;
  double v = 0;
  if (!number(n, key_path(path, key), "a number", &v)) return std::nullopt;
  return v;
}

bool YamlReader::number(const YAML::Node& n, const std::string& kp, const std::string& expected,
                        double* out) {
  if (!as_double(n, out)) {
    error(kp, "must be " + expected + ", got " + describe(n));
    return false;
  }
  if (!std::isfinite(*out)) {
    error(kp, "must be a finite number, got " + describe(n));
    return false;
  }
  return true;
}

std::optional<long> YamlReader::whole_in_range(const YAML::Node& n, const std::string& kp, long min,
                                               long max) {
  const std::string range =
      "a whole number from " + std::to_string(min) + " to " + std::to_string(max);
  double v = 0;
  if (!number(n, kp, range, &v)) return std::nullopt;
  if (v != std::floor(v) || v < static_cast<double>(min) || v > static_cast<double>(max)) {
    error(kp, "must be " + range + ", got " + describe(n));
    return std::nullopt;
  }
  return static_cast<long>(v);
}

std::optional<long> YamlReader::optional_int(const YAML::Node& map, const std::string& key,
                                             const std::string& path, long min, long max) {
  const YAML::Node n = map.IsMap() ? map[key] : YAML::Node();
  if (!n) return std::nullopt;
  return whole_in_range(n, key_path(path, key), min, max);
}

std::optional<long> YamlReader::required_int(const YAML::Node& map, const std::string& key,
                                             const std::string& path, long min, long max) {
  const YAML::Node n = map.IsMap() ? map[key] : YAML::Node();
  if (!n) {
    error(key_path(path, key), missing_message(map, key));
    return std::nullopt;
  }
  return whole_in_range(n, key_path(path, key), min, max);
}

std::optional<std::string> YamlReader::optional_string(const YAML::Node& map,
                                                       const std::string& key,
                                                       const std::string& path) {
  const YAML::Node n = map.IsMap() ? map[key] : YAML::Node();
  if (!n) return std::nullopt;
  if (!n.IsScalar()) {
    error(key_path(path, key), "must be a string, got " + describe(n));
    return std::nullopt;
  }
  return n.Scalar();
}

std::optional<std::pair<double, double>> YamlReader::optional_pair(const YAML::Node& map,
                                                                   const std::string& key,
                                                                   const std::string& path) {
  const YAML::Node n = map.IsMap() ? map[key] : YAML::Node();
  if (!n) return std::nullopt;
  double a = 0, b = 0;
  if (!n.IsSequence() || n.size() != 2 || !as_double(n[0], &a) || !as_double(n[1], &b)) {
    error(key_path(path, key), "must be a list of two numbers [a, b], got " + describe(n));
    return std::nullopt;
  }
  if (!std::isfinite(a) || !std::isfinite(b)) {
    // Worded as the cut kind's windows always were (%g: nan, inf, 1e+300).
    const auto g = [](double v) {
      char buf[32];
      std::snprintf(buf, sizeof(buf), "%g", v);
      return std::string(buf);
    };
    error(key_path(path, key),
          "must be two finite numbers [start, end], got [" + g(a) + ", " + g(b) + "]");
    return std::nullopt;
  }
  return std::make_pair(a, b);
}

std::optional<std::pair<double, double>> YamlReader::optional_number_or_pair(
    const YAML::Node& map, const std::string& key, const std::string& path) {
  const YAML::Node n = map.IsMap() ? map[key] : YAML::Node();
  if (!n) return std::nullopt;
  double a = 0;
  if (n.IsScalar()) {
    if (!number(n, key_path(path, key), "a number or a list [start, end]", &a)) {
      return std::nullopt;
    }
    return std::make_pair(a, a);
  }
  return optional_pair(map, key, path);
}

std::vector<std::string> YamlReader::string_list(const YAML::Node& map, const std::string& key,
                                                 bool required, const std::string& path) {
  std::vector<std::string> out;
  const YAML::Node n = map.IsMap() ? map[key] : YAML::Node();
  if (!n) {
    if (required) error(key_path(path, key), missing_message(map, key));
    return out;
  }
  if (!n.IsSequence()) {
    error(key_path(path, key), "must be a list of names, got " + describe(n));
    return out;
  }
  for (const auto& e : n) {
    if (!e.IsScalar()) {
      error(key_path(path, key), "must be a list of names, got an element " + describe(e));
      return {};
    }
    out.push_back(e.Scalar());
  }
  return out;
}

void YamlReader::check_keys(const YAML::Node& map, const std::set<std::string>& known,
                            const std::string& path) {
  if (!map.IsMap()) return;
  for (const auto& kv : map) {
    if (!is_name_key(kv.first)) {
      // load_yaml_file refuses such a file; a tree built otherwise is flagged, not thrown on.
      error(path.empty() ? "(top level)" : path, "has a key that is not a name (line " +
                                                     std::to_string(kv.first.Mark().line + 1) +
                                                     "): every key must be a plain scalar");
      continue;
    }
    const auto k = kv.first.Scalar();
    if (known.count(k)) continue;
    // The closest known key that looks like it (fewest edits; the first in order on a tie).
    std::string hint;
    int best = std::numeric_limits<int>::max();
    for (const auto& cand : known) {
      if (!looks_like(k, cand)) continue;
      const int d = edit_distance(k, cand);
      if (d < best) {
        best = d;
        hint = " (did you mean '" + cand + "'?)";
      }
    }
    warn(key_path(path, k), "is not part of the format and is ignored" + hint);
  }
}

}  // namespace chatterlab::app
