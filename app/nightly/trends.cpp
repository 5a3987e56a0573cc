#include "app/nightly/trends.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "app/core/checked_write.h"
#include "app/core/format.h"
#include "app/nightly/site_db.h"
#include "app/report/document.h"
#include "app/report/figure_jobs.h"
#include "app/report/html_pages.h"
#include "render/gnuplot_script.h"
#include "render/mustache_template.h"

namespace chatterlab::app {

namespace fs = std::filesystem;
using nlohmann::json;

std::string tool_series_name(int teeth, double radius_mm) {
  return std::to_string(teeth) + (teeth == 1 ? " tooth" : " teeth") + ", r " +
         fmt_sig(radius_mm, 6) + " mm";
}

EstimatorKey split_estimator_key(const std::string& key) {
  const auto last = key.rfind('/');
  if (last == std::string::npos || last == 0) return {};
  const auto mid = key.rfind('/', last - 1);
  if (mid == std::string::npos || mid == 0) return {};
  return {key.substr(0, mid), key.substr(mid + 1, last - mid - 1), key.substr(last + 1)};
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Run {
  std::string started_utc;
  std::string version;
};

struct Row {
  std::int64_t run = 0;
  double value = kNaN;
  std::optional<double> lo, hi;
};

// Whether `a` to `b` moved beyond the site's tolerance, the number's key in results.json being
// `path` joined by '.': the rule matching and tolerance test of `compare` itself, on two
// documents holding that number alone.
bool moved(const std::vector<std::string>& path, double a, double b, const CompareOptions& tol) {
  const auto nest = [&path](double v) {
    json doc = v;
    for (auto it = path.rbegin(); it != path.rend(); ++it) doc = json{{*it, doc}};
    return doc;
  };
  const Comparison c = compare_results(nest(a), nest(b), tol);
  return std::any_of(c.changes.begin(), c.changes.end(),
                     [](const Change& ch) { return ch.flag && ch.kind == Change::Kind::kMoved; });
}

std::string interval_text(const Row& r) {
  if (!r.lo && !r.hi) return "";
  return "[" + (r.lo ? fmt_sig(*r.lo, 5) : std::string("n/a")) + ", " +
         (r.hi ? fmt_sig(*r.hi, 5) : std::string("n/a")) + "]";
}

// The stem of a figure of series `s` (1-based): figures/<prefix>-<s>-<key>, the key's
// characters outside [A-Za-z0-9_-] as '-'.
std::string stem_of(const std::string& prefix, std::size_t s, const std::string& key) {
  std::string k = key;
  for (char& ch : k) {
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-') ch = '-';
  }
  return "figures/" + prefix + "-" + std::to_string(s) + (k.empty() ? "" : "-" + k);
}

// The x range of a figure over whole numbers first..last, half a step wider on each side.
render::Range integer_range(double first, double last) { return {first - 0.5, last + 0.5}; }

void write_page(const fs::path& stage, const std::string& name, const json& ctx) {
  const std::string html = render::render_template_file(templates_dir() / name, ctx);
  write_file_checked(stage / name, screen_page(html, stage));
}

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : sep) + s;
  return out;
}

// The series of the run, in name order, each with its campaigns in name order.
std::map<std::string, std::vector<const TrendCampaign*>> series_of(
    const std::vector<TrendCampaign>& campaigns) {
  std::map<std::string, std::vector<const TrendCampaign*>> out;
  for (const auto& c : campaigns) out[c.series].push_back(&c);
  for (auto& [s, cs] : out) {
    std::sort(cs.begin(), cs.end(),
              [](const TrendCampaign* a, const TrendCampaign* b) { return a->name < b->name; });
  }
  return out;
}

// trends.html: per series and identified key, a figure and a table of every run.
json trend_context(SiteDb& db, std::int64_t run_id, const std::vector<TrendCampaign>& campaigns,
                   const CompareOptions& tol, FigureJobs& jobs) {
  std::map<std::int64_t, Run> runs;  // the finished runs and this one
  {
    SiteDb::Statement s(db,
                        "SELECT id, started_utc, version FROM runs WHERE status = 'done' OR id = ? "
                        "ORDER BY id");
    s.bind(1, run_id);
    while (s.step()) runs[s.integer(0)] = {s.text(1), s.text(2)};
  }
  // campaign -> identified key -> rows in run order
  std::map<std::string, std::map<std::string, std::vector<Row>>> values;
  {
    SiteDb::Statement s(db,
                        "SELECT run_id, campaign, key, value, lo, hi FROM trend_values ORDER BY "
                        "run_id");
    while (s.step()) {
      if (!runs.count(s.integer(0)) || s.is_null(3)) continue;
      const std::string key = s.text(2);
      if (key.find('/') != std::string::npos) continue;  // an estimator final
      Row r;
      r.run = s.integer(0);
      r.value = s.real(3);
      if (!s.is_null(4)) r.lo = s.real(4);
      if (!s.is_null(5)) r.hi = s.real(5);
      values[s.text(1)][key].push_back(r);
    }
  }
  json series = json::array();
  json moved_now = json::array();
  std::size_t index = 0;
  for (const auto& [name, members] : series_of(campaigns)) {
    ++index;
    std::set<std::string> keys;
    std::vector<std::string> member_names;
    for (const auto* c : members) {
      member_names.push_back(c->name);
      if (const auto it = values.find(c->name); it != values.end()) {
        for (const auto& [k, rows] : it->second) keys.insert(k);
      }
    }
    json key_rows = json::array();
    for (const auto& key : keys) {
      render::Figure fig;
      fig.height_in = 2.8;
      render::Axes& ax = fig.panels.emplace_back();
      ax.title = key + ": " + name;
      ax.x_label = "run";
      ax.y_label = key;
      ax.legend = render::LegendPosition::kOutsideRight;
      double first = kNaN, last = kNaN;
      json rows = json::array();
      for (std::size_t ci = 0; ci < members.size(); ++ci) {
        const auto* c = members[ci];
        const auto vit = values.find(c->name);
        if (vit == values.end() || !vit->second.count(key)) continue;
        const std::vector<Row>& rs = vit->second.at(key);
        const std::string colour = render::palette_colour(ci);
        std::vector<double> x, y, lo, hi;
        bool any_interval = false;
        for (std::size_t i = 0; i < rs.size(); ++i) {
          const Row& r = rs[i];
          x.push_back(static_cast<double>(r.run));
          y.push_back(r.value);
          lo.push_back(r.lo.value_or(kNaN));
          hi.push_back(r.hi.value_or(kNaN));
          any_interval = any_interval || r.lo || r.hi;
          first = std::isnan(first) ? x.back() : std::min(first, x.back());
          last = std::isnan(last) ? x.back() : std::max(last, x.back());
          std::vector<std::string> flags;
          if (i > 0) {
            if (moved({"identified", key}, rs[i - 1].value, r.value, tol)) flags.push_back("moved");
            if (runs.at(rs[i - 1].run).version != runs.at(r.run).version) {
              flags.push_back("program changed");
            }
          }
          if (r.run == run_id && !flags.empty()) {
            moved_now.push_back({{"series", name},
                                 {"campaign", c->name},
                                 {"key", key},
                                 {"flags", join(flags, ", ")}});
          }
          rows.push_back({{"run", r.run},
                          {"date", runs.at(r.run).started_utc},
                          {"campaign", c->name},
                          {"value", fmt_sig(r.value, 6)},
                          {"interval", interval_text(r)},
                          {"flags", join(flags, ", ")},
                          {"flagged", !flags.empty()}});
        }
        ax.series.push_back({x, y, c->name, render::SeriesStyle::kLinePoints, colour});
        if (any_interval) {
          ax.series.push_back({x, lo, c->name + " 95 %", render::SeriesStyle::kDashedLine, colour});
          ax.series.push_back({x, hi, "", render::SeriesStyle::kDashedLine, colour});
        }
      }
      if (!std::isnan(first)) ax.x_range = integer_range(first, last);
      const std::string stem = stem_of("trend", index, key);
      jobs.add(name, key, stem, fig);
      key_rows.push_back({{"key", key}, {"stem", stem}, {"rows", rows}});
    }
    series.push_back({{"name", name},
                      {"anchor", "series-" + std::to_string(index)},
                      {"campaigns", join(member_names, ", ")},
                      {"keys", key_rows}});
  }
  json run_rows = json::array();
  for (const auto& [id, r] : runs) {
    run_rows.push_back({{"run", id}, {"date", r.started_utc}, {"version", r.version}});
  }
  return {{"series", series}, {"moved_now", moved_now}, {"runs", run_rows}};
}

std::string estimates_text(const json& estimates) {
  std::vector<std::string> parts;
  for (auto it = estimates.begin(); it != estimates.end(); ++it) {
    parts.push_back(it.key() + " = " + (it->is_number() ? fmt_sig(it->get<double>(), 6) : "n/a"));
  }
  return join(parts, ", ");
}

std::string spread_text(const json& v) {
  const auto rep = v.find("repeatability");
  if (rep == v.end() || !rep->is_object()) return "no repeat runs";
  if (rep->value("status", "") == "failed") return "failed: " + rep->value("message", "");
  std::vector<std::string> parts;
  for (auto it = rep->begin(); it != rep->end(); ++it) {
    if (!it->is_object()) continue;
    const auto pct = it->find("std_dev_pct");
    if (pct == it->end() || !pct->is_number()) continue;
    parts.push_back(it.key() + " " + fmt_sig(pct->get<double>(), 3) + " %");
  }
  std::string text = join(parts, ", ");
  if (rep->contains("runs") && (*rep)["runs"].is_number()) {
    text += " (" + std::to_string((*rep)["runs"].get<long>()) + " runs)";
  }
  return text;
}

std::string nis_text(const json& v) {
  const auto nis = v.find("nis");
  if (nis == v.end() || !nis->is_object()) return "";
  std::string text;
  if (const auto m = nis->find("mean"); m != nis->end() && m->is_number()) {
    text = "mean " + fmt_sig(m->get<double>(), 4);
  }
  if (const auto b = nis->find("mean_band"); b != nis->end() && b->is_array() && b->size() == 2 &&
                                             (*b)[0].is_number() && (*b)[1].is_number()) {
    text += " in [" + fmt_sig((*b)[0].get<double>(), 4) + ", " + fmt_sig((*b)[1].get<double>(), 4) +
            "]";
  }
  if (const auto in = nis->find("mean_inside_band"); in != nis->end() && in->is_boolean()) {
    text += in->get<bool>() ? ": inside" : ": outside";
  }
  if (const auto f = nis->find("fraction_inside"); f != nis->end() && f->is_number()) {
    text += "; " + fmt_sig(100.0 * f->get<double>(), 3) + " % of updates inside";
  }
  return text;
}

// estimators.html: per series, every variant of every cut of its campaigns as of this run.
json estimator_context(const std::vector<TrendCampaign>& campaigns, FigureJobs& jobs) {
  json series = json::array();
  std::size_t index = 0;
  for (const auto& [name, members] : series_of(campaigns)) {
    ++index;
    json rows = json::array();
    json cuts = json::array();
    // cut number -> variant -> its final estimates
    std::vector<std::map<std::string, json>> finals;
    std::map<std::string, int> key_count;
    for (const auto* c : members) {
      if (!c->results.is_object()) continue;
      const auto tests = c->results.find("tests");
      if (tests == c->results.end() || !tests->is_object()) continue;
      for (auto t = tests->begin(); t != tests->end(); ++t) {
        if (!t->is_object()) continue;
        const auto est = t->find("estimators");
        if (est == t->end() || !est->is_object() || est->empty()) continue;
        const int cut = static_cast<int>(finals.size()) + 1;
        finals.emplace_back();
        cuts.push_back({{"cut", cut}, {"campaign", c->name}, {"test", t.key()}});
        for (auto v = est->begin(); v != est->end(); ++v) {
          if (!v->is_object()) continue;
          json row = {{"cut", cut}, {"campaign", c->name}, {"test", t.key()}, {"variant", v.key()}};
          const auto e = v->find("estimates");
          if (e != v->end() && e->is_object()) {
            row["estimates"] = estimates_text(*e);
            finals.back()[v.key()] = *e;
            for (auto k = e->begin(); k != e->end(); ++k) ++key_count[k.key()];
          } else {
            row["estimates"] = v->value("status", "no estimates") + ": " + v->value("message", "");
          }
          row["spread"] = spread_text(*v);
          row["consistency"] = nis_text(*v);
          const auto rt = v->find("runtime_s");
          row["runtime"] = rt != v->end() && rt->is_number() ? fmt_sig(rt->get<double>(), 3) : "";
          rows.push_back(row);
        }
      }
    }
    json entry = {{"name", name},
                  {"anchor", "series-" + std::to_string(index)},
                  {"rows", rows},
                  {"cuts", cuts}};
    if (!finals.empty()) {
      // The figure's key: the modal mass, which every modal variant estimates; else the key
      // most variants estimate.
      std::string key = "m_kg";
      if (!key_count.count(key)) {
        key =
            std::max_element(key_count.begin(), key_count.end(), [](const auto& a, const auto& b) {
              return a.second < b.second;
            })->first;
      }
      std::set<std::string> variants;
      for (const auto& f : finals) {
        for (const auto& [v, e] : f) {
          if (e.contains(key)) variants.insert(v);
        }
      }
      render::Figure fig;
      fig.height_in = 3.2;
      render::Axes& ax = fig.panels.emplace_back();
      ax.title = key + " per variant: " + name;
      ax.x_label = "cut (numbered as in the table)";
      ax.y_label = key;
      ax.legend = render::LegendPosition::kOutsideRight;
      ax.x_range = integer_range(1, static_cast<double>(finals.size()));
      std::size_t colour = 0;
      for (const auto& v : variants) {
        std::vector<double> x, y;
        for (std::size_t i = 0; i < finals.size(); ++i) {
          const auto it = finals[i].find(v);
          if (it == finals[i].end() || !it->second.contains(key) || !it->second[key].is_number()) {
            continue;
          }
          x.push_back(static_cast<double>(i + 1));
          y.push_back(it->second[key].get<double>());
        }
        ax.series.push_back(
            {x, y, v, render::SeriesStyle::kPoints, render::palette_colour(colour++)});
      }
      const std::string stem = stem_of("estimators", index, "");
      jobs.add(name, "estimators", stem, fig);
      entry["stem"] = stem;
      entry["figure_key"] = key;
    }
    series.push_back(entry);
  }
  return {{"series", series}};
}

}  // namespace

TrendPages write_trend_pages(const fs::path& stage, SiteDb& db, std::int64_t run_id,
                             const std::vector<TrendCampaign>& campaigns,
                             const CompareOptions& tolerances, const json& title, int jobs) {
  FigureJobs figures;
  json trends = trend_context(db, run_id, campaigns, tolerances, figures);
  json estimators = estimator_context(campaigns, figures);
  fs::create_directories(stage / "figures");
  const FigureSet drawn = figures.draw(stage, jobs);
  // A figure that could not be drawn is left out of its page (its table stays).
  for (auto& s : trends["series"]) {
    for (auto& k : s["keys"]) {
      if (drawn.of(s["name"].get<std::string>(), k["key"].get<std::string>()).empty()) {
        k.erase("stem");
      }
    }
  }
  for (auto& s : estimators["series"]) {
    if (s.contains("stem") && drawn.of(s["name"].get<std::string>(), "estimators").empty()) {
      s.erase("stem");
    }
  }
  for (auto it = title.begin(); it != title.end(); ++it) {
    trends[it.key()] = *it;
    estimators[it.key()] = *it;
  }
  trends["run"] = run_id;
  estimators["run"] = run_id;
  write_page(stage, "trends.html", trends);
  write_page(stage, "estimators.html", estimators);
  TrendPages out;
  for (const auto& [owner, stems] : drawn.stems) out.figures += stems.size();
  out.errors = drawn.errors;
  return out;
}

}  // namespace chatterlab::app
