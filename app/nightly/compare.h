// `chatterlab compare <a> <b>` (docs/nightly.md#compare): every number of two results.json
// documents, paired by key, with a table of those that moved beyond their tolerance, like a
// metrics diff. A key is the path of the value in the document: object keys joined by ".",
// array items as "[i]" (tests.cuts/incline.identification.joint.c_kg_s).
//
// Tolerances come in families: rules matched in order against the key by a shell pattern (`*`
// any text, `?` one character); the first that matches decides, else the default. A number
// moved when |b - a| > abs + rel * max(|a|, |b|) (both bounds together, as numpy's isclose
// but symmetric). Timings (keys ending in runtime_s, steps_per_s or svd_s) and the worker
// threads (settings.pipeline.jobs) are ignored by built-in rules that a user's rule can
// override.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace chatterlab::app {

struct ToleranceRule {
  std::string keys;  // shell pattern over the key; "" matches nothing
  double rel = 0;
  double abs = 0;
  bool ignore = false;  // the family is not compared (timings)
};

struct CompareOptions {
  ToleranceRule fallback{"*", 1e-9, 0.0, false};  // the default (keys "*")
  std::vector<ToleranceRule> rules;               // the user's, tried before the built-in ones
};

// The built-in rules, tried after the user's: timings and settings.pipeline.jobs are ignored.
const std::vector<ToleranceRule>& builtin_tolerance_rules();

// Reads a tolerances file (docs/nightly.md#tolerances):
//   default: {rel: 1.0e-6, abs: 0}
//   rules:
//     - {keys: "*_ci95*", rel: 0.05}
//     - {keys: "tests.*.variants*", ignore: true}
// @throws InputError naming the file and key of every problem
CompareOptions load_tolerances(const std::filesystem::path& file);

struct Change {
  enum class Kind { kMoved, kAdded, kRemoved, kText };
  std::string key;
  Kind kind = Kind::kMoved;
  nlohmann::json a, b;  // the values (null when absent)
  double abs_change = 0;
  double rel_change = 0;  // |b - a| / max(|a|, |b|); 0 when both are 0
  std::string rule;       // the pattern that decided the tolerance ("default" for the fallback)
  double rel_tolerance = 0, abs_tolerance = 0;
  // A regression flag: a number moved beyond its tolerance or vanished, or a status that was
  // "ok" is no longer. Added numbers and other changed text are listed, not flagged.
  bool flag = false;
};

struct Comparison {
  std::string a_label, b_label;
  long numbers_compared = 0;  // numbers present in both, not ignored
  long numbers_equal = 0;     // of those, within tolerance
  std::vector<Change> changes;
  int flags() const;
};

// Compares two results.json documents (any JSON: nightly.json as well).
Comparison compare_results(const nlohmann::json& a, const nlohmann::json& b,
                           const CompareOptions& options = {});

// Reads a JSON file. @throws InputError naming the file (missing, unreadable, not JSON)
nlohmann::json read_json_file(const std::filesystem::path& file);

// The three forms: a text table for the terminal, JSON and a standalone HTML page.
std::string comparison_text(const Comparison& c);
nlohmann::json comparison_json(const Comparison& c);
std::string comparison_html(const Comparison& c);

}  // namespace chatterlab::app
