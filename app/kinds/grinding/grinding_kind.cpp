#include "app/kinds/grinding/grinding_kind.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "analysis/common/summary.h"
#include "analysis/grinding/observability.h"
#include "app/core/archive_analysis.h"
#include "app/core/checked_write.h"
#include "app/core/format.h"
#include "app/core/input_boundary.h"
#include "app/core/parallel.h"
#include "app/core/signals.h"
#include "app/core/utf8.h"
#include "app/core/yaml_reader.h"
#include "app/pipeline/cached_result.h"
#include "app/report/results_json.h"
#include "app/report/truth.h"

namespace chatterlab::app {

using nlohmann::json;
namespace g = chatterlab::grinding;

namespace {

// Operating points of the observability rank per estimator, and the seed of their draw.
constexpr int kObservabilityPoints = 12;
constexpr std::uint64_t kObservabilitySeed = 2;

// The state keys of results.json (format section 7) in the order of X, and their 3sigma twins.
constexpr std::array<const char*, 4> kStateKeys = {"Vw_mm2", "v_mm_s", "ds_mm", "R0_um"};
constexpr std::array<const char*, 4> kSigmaKeys = {"Vw_3sigma_mm2", "v_3sigma_mm_s", "ds_3sigma_mm",
                                                   "R0_3sigma_um"};

std::string inspections_label(const TestSpec& t, const GrindingSpec& s) {
  return t.file_label(s.inspections_file);
}

// The inspections file of a test, through the input boundary (inside the campaign, a regular
// file; app/core/input_boundary.h).
InputFileCheck inspections_check(const TestSpec& t, const GrindingSpec& s) {
  return check_input_file(t.campaign_root, t.folder, s.inspections_file);
}

// The required mapping under `key` of `root` (a null node and an error when absent or not a
// mapping).
YAML::Node map_key(const YAML::Node& root, const std::string& key, YamlReader& r,
                   const std::string& shape) {
  const YAML::Node n = root[key];
  if (!n) {
    r.error(key, "is missing: it must be a mapping " + shape);
    return YAML::Node();
  }
  if (!n.IsMap()) {
    r.error(key, "must be a mapping " + shape);
    return YAML::Node();
  }
  return n;
}

// Reads `key` of `map` (path `path`) into `out`: required or optional (keeping the default),
// with a lower bound: > lo when strict, else >= lo.
void read_number(const YAML::Node& map, const std::string& path, const std::string& key,
                 bool required, double lo, bool strict, double* out, YamlReader& r) {
  const std::size_t errors_before = r.errors().size();
  const std::optional<double> v = required
                                      ? std::optional<double>(r.required_double(map, key, path))
                                      : r.optional_double(map, key, path);
  if (r.errors().size() != errors_before || !v) return;
  const bool ok = std::isfinite(*v) && (strict ? *v > lo : *v >= lo);
  if (!ok) {
    r.error(path.empty() ? key : path + "." + key,
            "= " + fmt_sig(*v, 6) + ": must be a number " + (strict ? "> " : ">= ") + fmt_sig(lo));
    return;
  }
  *out = *v;
}

void read_model(const YAML::Node& m, YamlReader& r, g::GrindingParameters& p) {
  r.check_keys(m,
               {"dw_mm", "ds0_mm", "vs_m_s", "vw_m_s", "tau_s", "Ks_W_s_mm", "s0", "s1_per_mm2",
                "delta", "gamma", "Rg_um", "R0_um", "V0_mm2", "rm_um", "r0", "G1", "g"},
               "model");
  const auto req = [&](const char* key, double lo, bool strict, double* out) {
    read_number(m, "model", key, true, lo, strict, out, r);
  };
  const auto opt = [&](const char* key, double lo, bool strict, double* out) {
    read_number(m, "model", key, false, lo, strict, out, r);
  };
  req("dw_mm", 0, true, &p.dw_mm);
  req("ds0_mm", 0, true, &p.ds0_mm);
  req("vs_m_s", 0, true, &p.vs_m_s);
  opt("vw_m_s", 0, true, &p.vw_m_s);
  req("tau_s", 0, true, &p.tau_s);
  req("Ks_W_s_mm", 0, false, &p.Ks_W_s_mm);
  req("s0", 0, false, &p.s0);
  req("s1_per_mm2", 0, false, &p.s1_per_mm2);
  p.delta = 1.0;
  opt("delta", 0, true, &p.delta);
  req("gamma", 0, false, &p.gamma);
  req("Rg_um", 0, false, &p.Rg_um);
  req("R0_um", 0, false, &p.R0_um);
  req("V0_mm2", 0, true, &p.V0_mm2);
  opt("rm_um", 0, false, &p.rm_um);
  opt("r0", 0, false, &p.r0);
  req("G1", 0, true, &p.G1);
  req("g", 0, false, &p.g);
}

void read_noise(const YAML::Node& n, YamlReader& r, GrindingSpec& s) {
  r.check_keys(n, {"power_sd", "Dw_sd_mm", "ds_sd_mm", "Ra_sd_um", "roundness_sd_um"}, "noise");
  read_number(n, "noise", "power_sd", true, 0, true, &s.filter.power_sd_W, r);
  read_number(n, "noise", "Dw_sd_mm", true, 0, true, &s.filter.Dw_sd_mm, r);
  read_number(n, "noise", "ds_sd_mm", true, 0, true, &s.filter.ds_sd_mm, r);
  read_number(n, "noise", "Ra_sd_um", true, 0, true, &s.filter.Ra_sd_um, r);
  double rsd = std::numeric_limits<double>::quiet_NaN();
  read_number(n, "noise", "roundness_sd_um", false, 0, true, &rsd, r);
  if (std::isfinite(rsd)) s.roundness_sd_um = rsd;
}

// filter.P0 or filter.Q: the four variances keyed by state.
void read_variances(const YAML::Node& filter, const std::string& key, bool strict,
                    std::array<double, 4>& out, YamlReader& r) {
  const std::string path = "filter." + key;
  const YAML::Node n = filter[key];
  if (!n || !n.IsMap()) {
    r.error(path, std::string(n ? "must be" : "is missing: it must be") +
                      " a mapping {Vw_mm2, v_mm_s, ds_mm, R0_um} of variances");
    return;
  }
  r.check_keys(n, std::set<std::string>(kStateKeys.begin(), kStateKeys.end()), path);
  for (std::size_t i = 0; i < kStateKeys.size(); ++i) {
    read_number(n, path, kStateKeys[i], true, 0, strict, &out[i], r);
  }
}

void read_filter(const YAML::Node& f, YamlReader& r, GrindingSpec& s) {
  r.check_keys(f, {"P0", "Q", "R0_cycle_var_um2"}, "filter");
  read_variances(f, "P0", false, s.filter.P0, r);  // 0: a state known exactly
  read_variances(f, "Q", false, s.filter.Q, r);
  s.filter.R0_cycle_var_um2 = 0.0;
  read_number(f, "filter", "R0_cycle_var_um2", false, 0, false, &s.filter.R0_cycle_var_um2, r);
}

void read_dressings(const YAML::Node& root, YamlReader& r, GrindingSpec& s) {
  const YAML::Node d = root["dressings"];
  if (!d || d.IsNull()) return;
  if (!d.IsSequence()) {
    r.error("dressings", "must be a list of {before_cycle, depth_mm}");
    return;
  }
  std::set<int> seen;
  for (std::size_t k = 0; k < d.size(); ++k) {
    const std::string path = "dressings[" + std::to_string(k) + "]";
    if (!d[k].IsMap()) {
      r.error(path, "must be a mapping {before_cycle, depth_mm}");
      continue;
    }
    r.check_keys(d[k], {"before_cycle", "depth_mm"}, path);
    g::Dressing x;
    double before = std::numeric_limits<double>::quiet_NaN();
    read_number(d[k], path, "before_cycle", true, 2, false, &before, r);
    read_number(d[k], path, "depth_mm", true, 0, false, &x.depth_mm, r);
    if (std::isnan(before)) continue;
    if (before != std::floor(before)) {
      r.error(path + ".before_cycle", "= " + fmt_sig(before, 6) + ": must be a whole number");
      continue;
    }
    x.before_cycle = static_cast<int>(before);
    if (!seen.insert(x.before_cycle).second) {
      r.error(path + ".before_cycle",
              "= " + std::to_string(x.before_cycle) + ": the wheel is dressed twice before it");
      continue;
    }
    s.dressings.push_back(x);
  }
  std::sort(s.dressings.begin(), s.dressings.end(), [](const g::Dressing& a, const g::Dressing& b) {
    return a.before_cycle < b.before_cycle;
  });
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\"");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t\r\"");
  return s.substr(a, b - a + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

// The fast record after calibration; cycle numbers must be whole.
g::FastRecord read_record(const TestSpec& t) {
  const std::string label = t.data_label();
  const SignalTable table = SignalTable::open(t.data, label);
  g::FastRecord rec;
  const Eigen::VectorXd cycle = table.channel("cycle", t.channel("cycle"));
  rec.cycle.resize(static_cast<std::size_t>(cycle.size()));
  for (Eigen::Index k = 0; k < cycle.size(); ++k) {
    const double c = cycle[k];
    if (!(std::abs(c) < 1e9) || c != std::round(c)) {
      throw InputError(label + ": row " + std::to_string(k + 1) + ": cycle " + fmt_sig(c, 8) +
                       " is not a whole number");
    }
    rec.cycle[static_cast<std::size_t>(k)] = static_cast<int>(std::lround(c));
  }
  rec.u_mm_s = table.channel("u_mm_s", t.channel("u_mm_s"));
  rec.power_W = table.channel("power", t.channel("power"));
  rec.Dw_mm = table.channel("Dw_mm", t.channel("Dw_mm"));
  return rec;
}

// check_series's message, naming the file or key it concerns.
std::string series_message(const TestSpec& t, const GrindingSpec& s, const std::string& what) {
  const auto strip = [&](const std::string& prefix) { return what.substr(prefix.size()); };
  if (what.rfind("inspections: ", 0) == 0) {
    return inspections_label(t, s) + ": " + strip("inspections: ");
  }
  if (what.rfind("dressings: ", 0) == 0) {
    return t.yaml_label + ": key 'dressings' " + strip("dressings: ");
  }
  return t.data_label() + ": " + what;
}

// truth.yaml tests.<id>.per_cycle as rows of (Vw, v, ds, R0) and R_a; false when absent.
bool read_truth(const CampaignSpec& c, const std::string& id, int cycles, GrindingResult& res,
                std::vector<std::string>& warnings) {
  if (!c.has_truth) return false;
  const YAML::Node root = load_truth(c);
  if (!root || !root["tests"] || !root["tests"][id]) return false;
  const YAML::Node pc = root["tests"][id]["per_cycle"];
  if (!pc || !pc.IsMap()) return false;
  try {
    const auto column = [&](const char* key, bool required) {
      std::vector<double> v;
      if (!pc[key]) {
        if (required) throw InputError(std::string("has no ") + key);
        return v;
      }
      for (const auto& x : pc[key]) v.push_back(x.as<double>());
      if (static_cast<int>(v.size()) != cycles) {
        throw InputError(std::string(key) + " has " + std::to_string(v.size()) +
                         " values, the record " + std::to_string(cycles) + " cycles");
      }
      return v;
    };
    const std::vector<double> cols[4] = {column("Vw_mm2", true), column("v_mm_s", true),
                                         column("ds_mm", true), column("R0_um", true)};
    res.truth.resize(cycles, 4);
    for (int i = 0; i < cycles; ++i) {
      for (int k = 0; k < 4; ++k) res.truth(i, k) = cols[k][static_cast<std::size_t>(i)];
    }
    res.truth_Ra_um = column("Ra_um", false);
  } catch (const std::exception& e) {
    warnings.push_back("truth.yaml: tests." + id + ".per_cycle: " + e.what() + " (no NEES)");
    return false;
  }
  return true;
}

GrindingObservabilityResult observability_of(const g::GrindingRun& run, const g::FastRecord& rec,
                                             const g::GrindingParameters& p) {
  GrindingObservabilityResult o;
  const auto n = static_cast<Eigen::Index>(run.trajectory.size());
  Eigen::MatrixX4d traj(n, 4);
  for (Eigen::Index k = 0; k < n; ++k) {
    traj.row(k) = run.trajectory[static_cast<std::size_t>(k)].x.transpose();
    if (run.states == 3) traj(k, g::kR0) = p.R0_um;
  }
  try {
    const g::ObservabilityCase oc = g::estimator_observability_case(run.id);
    const g::TrajectoryObservability t = g::observability_along_trajectory(
        traj, rec.u_mm_s, p, oc.states, oc.channels, kObservabilityPoints, kObservabilitySeed);
    o.ok = true;
    o.min_rank = t.min_rank;
    o.max_rank = t.max_rank;
    for (const auto& pt : t.points) o.full_rank_points += pt.result.observable();
    o.states = oc.states;
    o.points = static_cast<int>(t.points.size());
  } catch (const InputError& e) {
    o.message = e.what();
  }
  return o;
}

std::string sigma_key(std::size_t k) { return kSigmaKeys[k]; }

double last_finite(const std::vector<g::CycleEstimate>& pc, int state) {
  return pc.empty() ? std::nan("") : pc.back().posterior.x[state];
}

}  // namespace

std::vector<std::string> GrindingKind::keys() const {
  return {"inspections", "model", "noise", "filter", "dressings", "dress_sd_mm"};
}

std::shared_ptr<const KindSpec> GrindingKind::parse(const YAML::Node& root, YamlReader& r) const {
  auto spec = std::make_shared<GrindingSpec>();
  GrindingSpec& s = *spec;
  if (const YAML::Node i = root["inspections"]; i && !i.IsNull()) {
    if (!i.IsMap()) {
      r.error("inspections", "must be a mapping {file: inspections.csv}");
    } else {
      r.check_keys(i, {"file"}, "inspections");
      s.inspections_file = r.required_string(i, "file", "inspections");
    }
  }
  if (const YAML::Node m = map_key(root, "model", r, "of the 002 model parameters"); m.IsMap()) {
    read_model(m, r, s.model);
  }
  if (const YAML::Node n = map_key(root, "noise", r, "{power_sd, Dw_sd_mm, ds_sd_mm, Ra_sd_um}");
      n.IsMap()) {
    read_noise(n, r, s);
  }
  if (const YAML::Node f = map_key(root, "filter", r, "{P0, Q, R0_cycle_var_um2}"); f.IsMap()) {
    read_filter(f, r, s);
  }
  read_dressings(root, r, s);
  s.filter.dress_sd_mm = 0.0;
  read_number(root, "", "dress_sd_mm", false, 0, false, &s.filter.dress_sd_mm, r);
  return spec;
}

std::vector<std::filesystem::path> GrindingKind::input_files(const TestSpec& t) const {
  const auto* s = dynamic_cast<const GrindingSpec*>(t.params.get());
  if (!s || s->inspections_file.empty()) return {};
  const InputFileCheck f = inspections_check(t, *s);
  if (!f.ok()) return {};
  return {f.path};
}

std::vector<std::string> GrindingKind::check_campaign(const CampaignSpec&,
                                                      const TestSpec& t) const {
  const auto* s = dynamic_cast<const GrindingSpec*>(t.params.get());
  if (!s || s->inspections_file.empty()) return {};
  const InputFileCheck f = inspections_check(t, *s);
  if (f.ok()) return {};
  return {input_file_message(t.yaml_label, "inspections.file", f.problem)};
}

// An available_cycle at or beyond this is "never" (no series has so many cycles).
constexpr double kNeverAvailable = 1e9;

std::vector<g::Inspection> read_inspections(const std::filesystem::path& file,
                                            const std::string& label,
                                            std::vector<std::string>& warnings) {
  std::ifstream in(file);
  if (!in) throw InputError(label + ": cannot be read");
  std::string line;
  if (!std::getline(in, line)) throw InputError(label + ": empty file (needs a header row)");
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte-order mark
  const std::vector<std::string> header = split(line);
  std::map<std::string, std::size_t> col;
  std::vector<std::string> others;  // a lab's own columns (an operator's name): not read
  for (std::size_t k = 0; k < header.size(); ++k) {
    static const std::set<std::string> known = {"cycle", "available_cycle", "ds_mm", "Ra_um",
                                                "roundness_um"};
    if (!known.count(header[k])) {
      others.push_back(header[k]);
      continue;
    }
    if (!col.emplace(header[k], k).second) {
      throw InputError(label + ": column '" + header[k] + "' appears twice");
    }
  }
  // One warning, naming at most five of them: a header of a million cells is one line.
  if (!others.empty()) {
    std::string names;
    for (std::size_t k = 0; k < std::min<std::size_t>(others.size(), 5); ++k) {
      names += (k ? ", '" : "'") + utf8_replaced(others[k].substr(0, 64)) + "'";
    }
    if (others.size() > 5) names += " and " + std::to_string(others.size() - 5) + " more";
    warnings.push_back(label + (others.size() == 1 ? ": column " : ": columns ") + names +
                       (others.size() == 1 ? " is" : " are") +
                       " not one of cycle, available_cycle, ds_mm, Ra_um, roundness_um and " +
                       (others.size() == 1 ? "is" : "are") + " ignored");
  }
  if (!col.count("cycle")) throw InputError(label + ": the header has no column 'cycle'");
  std::vector<g::Inspection> out;
  int row = 1;
  while (std::getline(in, line)) {
    ++row;
    if (trim(line).empty()) continue;
    const std::vector<std::string> cells = split(line);
    if (cells.size() != header.size()) {
      throw InputError(label + ": line " + std::to_string(row) + " has " +
                       std::to_string(cells.size()) + " fields, the header " +
                       std::to_string(header.size()));
    }
    // A field: empty or nan (any case) is NaN; anything else must be a number.
    const auto number = [&](const char* name) {
      const auto it = col.find(name);
      if (it == col.end()) return std::nan("");
      const std::string& c = cells[it->second];
      std::string lower = c;
      std::transform(lower.begin(), lower.end(), lower.begin(),
                     [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
      if (c.empty() || lower == "nan") return std::nan("");
      std::size_t used = 0;
      double v = 0;
      try {
        v = std::stod(c, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != c.size() || !std::isfinite(v)) {
        throw InputError(label + ": line " + std::to_string(row) + ", column " + name + ": '" + c +
                         "' is not a number (empty or nan: not measured)");
      }
      return v;
    };
    const auto whole = [&](const char* name, double v) {
      if (!std::isfinite(v) || v != std::floor(v) || std::abs(v) > 1e9) {
        throw InputError(label + ": line " + std::to_string(row) + ", column " + name +
                         ": must be a whole cycle number");
      }
      return static_cast<int>(v);
    };
    g::Inspection i;
    i.cycle = whole("cycle", number("cycle"));
    // available_cycle: empty means on time; inf or a value beyond any series (a lab's "never"
    // sentinel) is a result that is never used (format section 7).
    const auto it = col.find("available_cycle");
    const std::string avail_text = it == col.end() ? "" : trim(cells[it->second]);
    const bool never = avail_text == "inf" || avail_text == "Inf" || avail_text == "INF";
    const double avail =
        never ? std::numeric_limits<double>::infinity() : number("available_cycle");
    if (std::isnan(avail)) {
      i.available_cycle = i.cycle;
    } else if (avail >= kNeverAvailable) {
      i.available_cycle = std::numeric_limits<int>::max();
    } else {
      i.available_cycle = whole("available_cycle", avail);
    }
    i.ds_mm = number("ds_mm");
    i.Ra_um = number("Ra_um");
    i.roundness_um = number("roundness_um");
    out.push_back(i);
  }
  std::sort(out.begin(), out.end(),
            [](const g::Inspection& a, const g::Inspection& b) { return a.cycle < b.cycle; });
  return out;
}

// The inspections table read as the step reads it: a table it would refuse.
std::vector<std::string> GrindingKind::check_files(const TestSpec& t) const {
  const auto* s = dynamic_cast<const GrindingSpec*>(t.params.get());
  if (!s || s->inspections_file.empty()) return {};
  std::vector<std::string> warnings;  // given again by the run
  try {
    (void)read_inspections(resolve_input_file(t, "inspections.file", s->inspections_file),
                           inspections_label(t, *s), warnings);
  } catch (const InputError& e) {
    return {e.what()};
  }
  return {};
}

void GrindingKind::run(const TestSpec& t, const CampaignValues&, const RunContext& ctx,
                       TestOutcome& out) const {
  const GrindingSpec& s = t.kind_spec<GrindingSpec>();
  auto res = std::make_unique<GrindingResult>();
  const g::FastRecord rec = read_record(t);
  if (!s.inspections_file.empty()) {
    res->inspections =
        read_inspections(resolve_input_file(t, "inspections.file", s.inspections_file),
                         inspections_label(t, s), out.warnings);
  }
  // A series still being acquired: inspections and dressings past the record's last cycle are
  // left for a later run, with a warning (the format is silent on them).
  const int last_cycle = rec.cycle.empty() ? 0 : rec.cycle.back();
  std::vector<g::Dressing> dressings;
  for (const auto& d : s.dressings) {
    if (d.before_cycle > last_cycle && last_cycle > 0) {
      out.warnings.push_back(t.yaml_label + ": key 'dressings': the dressing before cycle " +
                             std::to_string(d.before_cycle) +
                             " is after the record's last cycle (" + std::to_string(last_cycle) +
                             ") and is not used");
    } else {
      dressings.push_back(d);
    }
  }
  const auto past = std::remove_if(res->inspections.begin(), res->inspections.end(),
                                   [&](const g::Inspection& i) { return i.cycle > last_cycle; });
  if (past != res->inspections.end() && last_cycle > 0) {
    out.warnings.push_back(inspections_label(t, s) + ": " +
                           std::to_string(res->inspections.end() - past) +
                           " row(s) for cycles after the record's last cycle (" +
                           std::to_string(last_cycle) + ") are not used");
    res->inspections.erase(past, res->inspections.end());
  }
  try {
    g::check_series(rec, res->inspections, dressings);
  } catch (const InputError& e) {
    throw InputError(series_message(t, s, e.what()));
  }
  for (std::size_t k = 0; k < rec.cycle.size(); ++k) {
    if (k == 0 || rec.cycle[k] != rec.cycle[k - 1])
      res->n.push_back(0);
    else
      ++res->n.back();
  }
  res->cycles = static_cast<int>(res->n.size());
  g::GrindingFilterSettings fs = s.filter;
  fs.sample_period_s = 1.0 / t.sample_rate_hz;

  res->estimators.resize(g::kGrindingEstimators.size());
  parallel_for(g::kGrindingEstimators.size(), ctx.jobs, [&](std::size_t k) {
    GrindingEstimatorResult& e = res->estimators[k];
    const auto t0 = std::chrono::steady_clock::now();
    e.run = g::run_grinding_estimator(g::kGrindingEstimators[k].id, s.model, fs, rec,
                                      res->inspections, dressings);
    e.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (e.run.summary.ok()) e.observability = observability_of(e.run, rec, s.model);
  });

  if (ctx.campaign) {
    res->has_truth = read_truth(*ctx.campaign, t.id, res->cycles, *res, out.warnings);
  }
  int failed = 0;
  std::string why;
  for (std::size_t k = 0; k < res->estimators.size(); ++k) {
    GrindingEstimatorResult& e = res->estimators[k];
    if (!e.run.summary.ok()) {
      ++failed;
      const std::string m =
          std::string(g::kGrindingEstimators[k].name) + ": " + e.run.summary.message;
      why += (why.empty() ? "" : "; ") + m;
      out.warnings.push_back(m);
      continue;
    }
    if (res->has_truth) e.nees_per_dof = g::nees_per_dof(e.run, res->truth);
  }
  out.result = std::move(res);
  if (failed == static_cast<int>(g::kGrindingEstimators.size())) {
    out.status.fail(t.data_label() + ": every estimator failed: " + why);
  } else {
    out.status.succeed();
  }
}

std::string grinding_trajectory_path(const std::string& test_id, const std::string& estimator) {
  return (test_id.empty() ? std::string() : test_id + "/") + estimator + ".csv";
}

std::pair<double, int> prior_vs_inspection(const g::GrindingRun& run,
                                           const std::vector<g::Inspection>& ins) {
  double sum = 0;
  int n = 0;
  for (const auto& i : ins) {
    if (!std::isfinite(i.ds_mm)) continue;
    const auto& c = run.per_cycle.at(static_cast<std::size_t>(i.cycle - 1));
    const double e = (c.ds_prior_mm - i.ds_mm) * 1e3;
    sum += e * e;
    ++n;
  }
  return {n ? std::sqrt(sum / n) : std::nan(""), n};
}

namespace {

json inspections_json(const std::vector<g::Inspection>& ins) {
  json cycle = json::array(), avail = json::array(), ds = json::array(), ra = json::array(),
       rd = json::array();
  for (const auto& i : ins) {
    cycle.push_back(i.cycle);
    avail.push_back(i.available_cycle);
    ds.push_back(number_or_null(i.ds_mm));
    ra.push_back(number_or_null(i.Ra_um));
    rd.push_back(number_or_null(i.roundness_um));
  }
  return {{"cycle", cycle},
          {"available_cycle", avail},
          {"ds_mm", ds},
          {"Ra_um", ra},
          {"roundness_um", rd}};
}

// The RMS of d_s prior minus the inspection's d_s over the inspected cycles (the wheel
// diameter each estimator predicted before that cycle's end update); NaN without any.

json estimator_json(const std::string& test_id, const GrindingResult& res,
                    const GrindingEstimatorResult& e, const g::GrindingEstimatorInfo& info) {
  const g::GrindingRun& run = e.run;
  json j;
  if (!run.summary.ok()) {
    j["status"] = "failed";
    j["message"] = run.summary.message;
    return j;
  }
  const auto states = static_cast<std::size_t>(run.states);
  json names = json::array();
  for (std::size_t k = 0; k < states; ++k) names.push_back(kStateKeys[k]);
  j["states"] = names;
  json pc = json::object();
  json cycle = json::array();
  std::vector<json> value(states, json::array()), sigma(states, json::array());
  json prior = json::array(), prior_sigma = json::array(), ra = json::array();
  json nis_fast = json::array(), nis_insp = json::array();
  for (const auto& c : run.per_cycle) {
    nis_fast.push_back(number_or_null(c.nis_fast_per_dof));
    nis_insp.push_back(number_or_null(c.nis_inspection_per_dof));
    cycle.push_back(c.posterior.cycle);
    for (std::size_t k = 0; k < states; ++k) {
      value[k].push_back(number_or_null(c.posterior.x[static_cast<Eigen::Index>(k)]));
      sigma[k].push_back(number_or_null(c.posterior.three_sigma[static_cast<Eigen::Index>(k)]));
    }
    prior.push_back(number_or_null(c.ds_prior_mm));
    prior_sigma.push_back(number_or_null(c.ds_prior_3sigma_mm));
    ra.push_back(number_or_null(c.Ra_pred_um));
  }
  pc["cycle"] = cycle;
  for (std::size_t k = 0; k < states; ++k) {
    pc[kStateKeys[k]] = value[k];
    pc[sigma_key(k)] = sigma[k];
  }
  pc["ds_prior_mm"] = prior;
  pc["ds_prior_3sigma_mm"] = prior_sigma;
  if (info.estimates_R0) pc["Ra_pred_um"] = ra;
  // Innovation diagnostics per cycle (beyond the contract): the mean NIS per degree of freedom
  // of the updates without inspection values, and that of the update holding the cycle's
  // inspection values (null: none).
  pc["nis_fast_per_dof"] = nis_fast;
  pc["nis_inspection_per_dof"] = nis_insp;
  j["per_cycle"] = pc;
  j["trajectory_csv"] = grinding_trajectory_path(test_id, info.name);
  j["nis_fast_per_dof"] = number_or_null(run.nis_fast_per_dof());
  j["nis_end_per_dof"] = number_or_null(run.nis_end_per_dof());
  if (res.has_truth) j["nees_per_dof"] = number_or_null(e.nees_per_dof);
  j["steps"] = run.steps;
  j["replayed_steps_count"] = run.replayed_steps;
  j["runtime_s"] = e.runtime_s;
  j["steps_per_s"] =
      e.runtime_s > 0 ? json(static_cast<double>(run.steps) / e.runtime_s) : json(nullptr);
  const auto [rms, count] = prior_vs_inspection(run, res.inspections);
  j["ds_prior_rms_error_vs_inspection_um"] = number_or_null(rms);
  j["ds_inspection_count"] = count;
  if (res.has_truth) {
    const Eigen::Index last = res.truth.rows() - 1;
    j["ds_final_error_vs_truth_um"] =
        number_or_null((last_finite(run.per_cycle, g::kDs) - res.truth(last, g::kDs)) * 1e3);
    if (info.estimates_R0) {
      j["R0_final_error_vs_truth_um"] =
          number_or_null(last_finite(run.per_cycle, g::kR0) - res.truth(last, g::kR0));
    }
  }
  if (e.observability.ok) {
    j["observability_rank"] = e.observability.min_rank;
    j["observability_full_rank_count"] = e.observability.full_rank_points;
    j["observability_states"] = e.observability.states;
    j["observability_points_count"] = e.observability.points;
  } else if (!e.observability.message.empty()) {
    j["observability_message"] = e.observability.message;
  }
  return j;
}

}  // namespace

json GrindingKind::results(const TestOutcome& out) const {
  const GrindingResult& res = out.result_of<GrindingResult>();
  const GrindingSpec& s = out.spec->kind_spec<GrindingSpec>();
  json j;
  j["cycles"] = res.cycles;
  if (!s.inspections_file.empty()) j["inspections_file"] = s.inspections_file;
  j["inspections"] = inspections_json(res.inspections);
  json est = json::object();
  for (std::size_t k = 0; k < res.estimators.size(); ++k) {
    const auto& info = g::kGrindingEstimators[k];
    est[info.name] = estimator_json(out.spec->id, res, res.estimators[k], info);
  }
  j["estimators"] = est;
  return j;
}

void write_grinding_trajectory(const std::filesystem::path& file, const g::GrindingRun& run) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream o = open_for_writing(file);
  const auto states = static_cast<std::size_t>(run.states);
  o << "cycle,j";
  for (std::size_t k = 0; k < states; ++k) o << ',' << kStateKeys[k] << ',' << kSigmaKeys[k];
  o << '\n';
  char buf[32];
  const auto num = [&](double v) -> const char* {
    if (!std::isfinite(v)) return "nan";
    std::snprintf(buf, sizeof buf, "%.17g", v);  // the row j = n_i equals per_cycle
    return buf;
  };
  for (const auto& e : run.trajectory) {
    o << e.cycle << ',' << e.j;
    for (std::size_t k = 0; k < states; ++k) {
      const auto i = static_cast<Eigen::Index>(k);
      o << ',' << num(e.x[i]);
      o << ',' << num(e.three_sigma[i]);
    }
    o << '\n';
  }
  close_checked(o, file);
}

void GrindingKind::write_files(const TestOutcome& out,
                               const std::filesystem::path& report_dir) const {
  const GrindingResult& res = out.result_of<GrindingResult>();
  for (std::size_t k = 0; k < res.estimators.size(); ++k) {
    if (!res.estimators[k].run.summary.ok()) continue;
    write_grinding_trajectory(
        report_dir / grinding_trajectory_path(out.spec->id, g::kGrindingEstimators[k].name),
        res.estimators[k].run);
  }
}

json GrindingKind::settings(const CampaignSpec& c) const {
  json tests = json::object();
  for (const auto& t : c.tests) {
    if (t.kind != name() || !t.usable()) continue;
    const auto* s = dynamic_cast<const GrindingSpec*>(t.params.get());
    if (!s) continue;
    const auto& p = s->model;
    const auto& f = s->filter;
    json model = {{"dw_mm", p.dw_mm},
                  {"ds0_mm", p.ds0_mm},
                  {"vs_m_s", p.vs_m_s},
                  {"vw_m_s", number_or_null(p.vw_m_s)},
                  {"tau_s", p.tau_s},
                  {"Ks_W_s_mm", p.Ks_W_s_mm},
                  {"s0", p.s0},
                  {"s1_per_mm2", p.s1_per_mm2},
                  {"delta", p.delta},
                  {"gamma", p.gamma},
                  {"Rg_um", p.Rg_um},
                  {"R0_um", p.R0_um},
                  {"V0_mm2", p.V0_mm2},
                  {"rm_um", number_or_null(p.rm_um)},
                  {"r0", number_or_null(p.r0)},
                  {"G1", p.G1},
                  {"g", p.g}};
    json noise = {{"power_sd", f.power_sd_W},
                  {"Dw_sd_mm", f.Dw_sd_mm},
                  {"ds_sd_mm", f.ds_sd_mm},
                  {"Ra_sd_um", f.Ra_sd_um}};
    if (s->roundness_sd_um) noise["roundness_sd_um"] = *s->roundness_sd_um;
    json P0 = json::object(), Q = json::object();
    for (std::size_t k = 0; k < kStateKeys.size(); ++k) {
      P0[kStateKeys[k]] = f.P0[k];
      Q[kStateKeys[k]] = f.Q[k];
    }
    tests[t.id.empty() ? "." : t.id] = {
        {"model", model},
        {"noise", noise},
        {"filter", {{"P0", P0}, {"Q", Q}, {"R0_cycle_var_um2", f.R0_cycle_var_um2}}},
        {"dress_sd_mm", f.dress_sd_mm},
        {"sample_period_s", t.sample_rate_hz > 0 ? 1.0 / t.sample_rate_hz : 0.0},
        {"covariance_update", f.joseph ? "joseph" : "standard"},
        {"observability", {{"points", kObservabilityPoints}, {"seed", kObservabilitySeed}}}};
  }
  if (tests.empty()) return json::object();
  return {{"tests", tests}};
}

std::string GrindingKind::note(const TestOutcome& out) const {
  const GrindingResult& res = out.result_of<GrindingResult>();
  int inspected = 0;
  for (const auto& i : res.inspections)
    inspected += std::isfinite(i.ds_mm) || std::isfinite(i.Ra_um);
  return std::to_string(res.cycles) + " cycles, " + std::to_string(inspected) +
         " inspected, 4 multirate EKFs";
}

void GrindingKind::compare_truth(const TruthInput& in, const TestOutcome& out,
                                 TruthComparison& c) const {
  const GrindingResult& res = out.result_of<GrindingResult>();
  const YAML::Node pc = (*in.entry)["per_cycle"];
  if (!pc || !pc.IsMap()) return;
  const auto last_of = [&](const char* key) {
    const YAML::Node v = pc[key];
    if (!v || !v.IsSequence() || static_cast<int>(v.size()) != res.cycles || v.size() == 0) {
      return std::nan("");
    }
    try {
      return v[v.size() - 1].as<double>();
    } catch (const YAML::Exception&) {
      return std::nan("");
    }
  };
  const double ds = last_of("ds_mm"), R0 = last_of("R0_um");
  for (std::size_t k = 0; k < res.estimators.size(); ++k) {
    const auto& run = res.estimators[k].run;
    if (!run.summary.ok() || run.per_cycle.empty()) continue;
    const std::string prefix = std::string(g::kGrindingEstimators[k].name) + ".";
    add_truth_row(c, prefix + "ds_mm", out.spec->id, ds, last_finite(run.per_cycle, g::kDs));
    if (g::kGrindingEstimators[k].estimates_R0) {
      add_truth_row(c, prefix + "R0_um", out.spec->id, R0, last_finite(run.per_cycle, g::kR0));
    }
  }
}

// ---- the per-test cache (app/core/archive.h) -------------------------------------------------

template <class Ar>
void fields(Ar& ar, GrindingObservabilityResult& o) {
  LAYOUT_GUARD(GrindingObservabilityResult, 64);
  ar(o.ok, o.message, o.min_rank, o.max_rank, o.states, o.points, o.full_rank_points);
}

template <class Ar>
void fields(Ar& ar, GrindingEstimatorResult& e) {
  LAYOUT_GUARD(GrindingEstimatorResult, 288);
  ar(e.run, e.runtime_s, e.nees_per_dof, e.observability);
}

template <class Ar>
void fields(Ar& ar, GrindingResult& r) {
  LAYOUT_GUARD(GrindingResult, 136);
  ar(r.cycles, r.n, r.inspections, r.estimators, r.has_truth, r.truth, r.truth_Ra_um);
}

std::string GrindingKind::save(const TestOutcome& out) const {
  return save_result<GrindingResult>(out);
}

void GrindingKind::restore(const TestSpec&, const std::string& bytes, TestOutcome& out) const {
  restore_result<GrindingResult>(bytes, out);
}

}  // namespace chatterlab::app
