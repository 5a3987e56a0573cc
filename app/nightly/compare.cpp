#include "app/nightly/compare.h"

#include <fnmatch.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include "analysis/common/summary.h"
#include "app/core/format.h"
#include "app/core/yaml_load.h"
#include "app/core/yaml_reader.h"
#include "app/report/document.h"
#include "render/mustache_template.h"

namespace chatterlab::app {
namespace {

using nlohmann::json;

// Every leaf of the document by key (compare.h: "." between object keys, "[i]" for items).
void flatten(const json& j, const std::string& key, std::map<std::string, const json*>& out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      flatten(it.value(), key.empty() ? it.key() : key + "." + it.key(), out);
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      flatten(j[i], key + "[" + std::to_string(i) + "]", out);
    }
  } else {
    out.emplace(key, &j);
  }
}

bool matches(const std::string& pattern, const std::string& key) {
  return !pattern.empty() && fnmatch(pattern.c_str(), key.c_str(), 0) == 0;
}

const ToleranceRule& rule_for(const std::string& key, const CompareOptions& o) {
  for (const auto& r : o.rules) {
    if (matches(r.keys, key)) return r;
  }
  for (const auto& r : builtin_tolerance_rules()) {
    if (matches(r.keys, key)) return r;
  }
  return o.fallback;
}

// The last part of a key ("status" of tests.tap/x.status).
std::string leaf_name(const std::string& key) {
  const auto dot = key.find_last_of('.');
  return dot == std::string::npos ? key : key.substr(dot + 1);
}

std::string value_text(const json& v) {
  if (v.is_null()) return "";
  if (v.is_number_float()) {
    std::ostringstream s;
    s << std::setprecision(9) << v.get<double>();
    return s.str();
  }
  if (v.is_string()) return v.get<std::string>();
  return v.dump();
}

const char* kind_word(Change::Kind k) {
  switch (k) {
    case Change::Kind::kMoved:
      return "moved";
    case Change::Kind::kAdded:
      return "added";
    case Change::Kind::kRemoved:
      return "removed";
    case Change::Kind::kText:
      return "text";
  }
  return "";
}

std::string change_text(const Change& c) {
  if (c.kind != Change::Kind::kMoved) return kind_word(c.kind);
  std::ostringstream s;
  const double signed_change = c.b.get<double>() - c.a.get<double>();
  s << std::showpos << std::setprecision(3) << signed_change;
  if (c.rel_change > 0) s << std::noshowpos << " (" << fmt_sig(100 * c.rel_change, 3) << " %)";
  return s.str();
}

}  // namespace

const std::vector<ToleranceRule>& builtin_tolerance_rules() {
  // Every timing results.json holds: run times, filter speeds, the ERA's SVD time; and the
  // worker threads (--jobs), an option that changes no result (alone, or under a campaign's
  // name in compare --site).
  static const std::vector<ToleranceRule> rules = {{"*runtime_s", 0, 0, true},
                                                   {"*steps_per_s", 0, 0, true},
                                                   {"*svd_s", 0, 0, true},
                                                   {"settings.pipeline.jobs", 0, 0, true},
                                                   {"*.settings.pipeline.jobs", 0, 0, true}};
  return rules;
}

int Comparison::flags() const {
  return static_cast<int>(
      std::count_if(changes.begin(), changes.end(), [](const Change& c) { return c.flag; }));
}

CompareOptions load_tolerances(const std::filesystem::path& file) {
  const std::string label = file.string();
  const YAML::Node root = load_yaml_file_or_throw(file, label);
  YamlReader r(label);
  CompareOptions o;
  if (!root.IsMap()) {
    throw InputError(label + ": expected a mapping with `default` and `rules`");
  }
  r.check_keys(root, {"default", "rules"});
  const auto bounds = [&](const YAML::Node& m, const std::string& path, ToleranceRule& rule) {
    if (const auto v = r.optional_double(m, "rel", path)) {
      if (*v < 0) r.error(path + ".rel", "must be >= 0");
      rule.rel = *v;
    }
    if (const auto v = r.optional_double(m, "abs", path)) {
      if (*v < 0) r.error(path + ".abs", "must be >= 0");
      rule.abs = *v;
    }
  };
  if (const YAML::Node d = root["default"]) {
    if (!d.IsMap()) {
      r.error("default", "expected a mapping {rel, abs}");
    } else {
      r.check_keys(d, {"rel", "abs"}, "default");
      bounds(d, "default", o.fallback);
    }
  }
  if (const YAML::Node rules = root["rules"]) {
    if (!rules.IsSequence()) {
      r.error("rules", "expected a list of {keys, rel, abs, ignore}");
    } else {
      for (std::size_t i = 0; i < rules.size(); ++i) {
        const std::string path = "rules[" + std::to_string(i) + "]";
        const YAML::Node m = rules[i];
        if (!m.IsMap()) {
          r.error(path, "expected a mapping {keys, rel, abs, ignore}");
          continue;
        }
        r.check_keys(m, {"keys", "rel", "abs", "ignore"}, path);
        ToleranceRule rule;
        rule.keys = r.required_string(m, "keys", path);
        bounds(m, path, rule);
        if (const YAML::Node ig = m["ignore"]) {
          bool b = false;
          if (!ig.IsScalar() || !YAML::convert<bool>::decode(ig, b)) {
            r.error(path + ".ignore", "expected true or false");
          }
          rule.ignore = b;
        }
        o.rules.push_back(rule);
      }
    }
  }
  r.throw_if_errors();
  return o;
}

Comparison compare_results(const json& a, const json& b, const CompareOptions& options) {
  Comparison c;
  std::map<std::string, const json*> fa, fb;
  flatten(a, "", fa);
  flatten(b, "", fb);
  std::map<std::string, std::pair<const json*, const json*>> keys;
  for (const auto& [k, v] : fa) keys[k].first = v;
  for (const auto& [k, v] : fb) keys[k].second = v;
  static const json kNull;
  for (const auto& [key, pair] : keys) {
    const ToleranceRule& rule = rule_for(key, options);
    if (rule.ignore) continue;
    const json& va = pair.first ? *pair.first : kNull;
    const json& vb = pair.second ? *pair.second : kNull;
    const bool na = pair.first && va.is_number();
    const bool nb = pair.second && vb.is_number();
    Change ch;
    ch.key = key;
    ch.a = va;
    ch.b = vb;
    ch.rule = &rule == &options.fallback ? "default" : rule.keys;
    ch.rel_tolerance = rule.rel;
    ch.abs_tolerance = rule.abs;
    if (na && nb) {
      ++c.numbers_compared;
      const double x = va.get<double>(), y = vb.get<double>();
      const double d = std::abs(y - x);
      const double scale = std::max(std::abs(x), std::abs(y));
      if (d <= rule.abs + rule.rel * scale) {
        ++c.numbers_equal;
        continue;
      }
      ch.kind = Change::Kind::kMoved;
      ch.abs_change = d;
      ch.rel_change = scale > 0 ? d / scale : 0;
      ch.flag = true;
    } else if (na) {
      ch.kind = Change::Kind::kRemoved;  // gone, or no longer a number (null: not finite)
      ch.flag = true;
    } else if (nb) {
      ch.kind = Change::Kind::kAdded;
    } else if (va != vb) {
      ch.kind = Change::Kind::kText;
      ch.flag = leaf_name(key) == "status" && va == "ok";
    } else {
      continue;
    }
    c.changes.push_back(std::move(ch));
  }
  // Flags first, then by key.
  std::stable_sort(c.changes.begin(), c.changes.end(),
                   [](const Change& x, const Change& y) { return x.flag > y.flag; });
  return c;
}

json read_json_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot be read");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(file.string() + ": not JSON: " + e.what());
  }
}

std::string comparison_text(const Comparison& c) {
  std::ostringstream s;
  s << "compare: " << c.a_label << " -> " << c.b_label << "\n";
  s << c.numbers_compared << " numbers compared, " << c.numbers_equal << " within tolerance; "
    << c.changes.size() << " changes, " << c.flags() << " flagged\n";
  if (c.changes.empty()) return s.str();
  std::size_t w = 3;
  for (const auto& ch : c.changes) w = std::max(w, ch.key.size());
  w = std::min<std::size_t>(w, 72);
  s << std::left << std::setw(static_cast<int>(w)) << "key"
    << "  " << std::setw(16) << "a" << std::setw(16) << "b"
    << "change\n";
  for (const auto& ch : c.changes) {
    s << std::left << std::setw(static_cast<int>(w)) << ch.key << "  " << std::setw(16)
      << value_text(ch.a) << std::setw(16) << value_text(ch.b) << change_text(ch)
      << (ch.flag ? "  FLAG" : "") << "\n";
  }
  return s.str();
}

json comparison_json(const Comparison& c) {
  json changes = json::array();
  for (const auto& ch : c.changes) {
    json e = {{"key", ch.key},
              {"kind", kind_word(ch.kind)},
              {"a", ch.a},
              {"b", ch.b},
              {"rule", ch.rule},
              {"rel_tolerance", ch.rel_tolerance},
              {"abs_tolerance", ch.abs_tolerance},
              {"flag", ch.flag}};
    if (ch.kind == Change::Kind::kMoved) {
      e["abs_change"] = ch.abs_change;
      e["rel_change"] = ch.rel_change;
    }
    changes.push_back(std::move(e));
  }
  return {{"format", "chatterlab-compare/1"},
          {"a", c.a_label},
          {"b", c.b_label},
          {"numbers_compared", c.numbers_compared},
          {"numbers_within_tolerance", c.numbers_equal},
          {"flags", c.flags()},
          {"changes", changes}};
}

std::string comparison_html(const Comparison& c) {
  json rows = json::array();
  for (const auto& ch : c.changes) {
    rows.push_back({{"key", ch.key},
                    {"a", value_text(ch.a)},
                    {"b", value_text(ch.b)},
                    {"change", change_text(ch)},
                    {"rule", ch.rule},
                    {"tolerance", "rel " + fmt_sig(ch.rel_tolerance, 3) + ", abs " +
                                      fmt_sig(ch.abs_tolerance, 3)},
                    {"flag", ch.flag}});
  }
  const json ctx = {{"a", c.a_label},
                    {"b", c.b_label},
                    {"numbers_compared", c.numbers_compared},
                    {"numbers_equal", c.numbers_equal},
                    {"changes", c.changes.size()},
                    {"flags", c.flags()},
                    {"rows", rows},
                    {"has_rows", !rows.empty()},
                    {"version", CHATTERLAB_VERSION}};
  return render::render_template_file(templates_dir() / "compare.html", ctx);
}

}  // namespace chatterlab::app
