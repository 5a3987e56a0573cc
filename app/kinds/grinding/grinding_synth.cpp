#include "app/kinds/grinding/grinding_synth.h"

#include <cmath>
#include <fstream>
#include <set>

#include "analysis/common/summary.h"
#include "app/core/checked_write.h"
#include "app/core/signals.h"
#include "app/kinds/grinding/grinding_kind.h"

namespace chatterlab::app {
namespace {

namespace g = chatterlab::grinding;

// Calibration of the written channels: power in transducer volts, D_w in gauge counts (um), as
// the format's example (section 7).
constexpr double kPowerScale = 1000.0, kPowerOffset = -850.0, kDwScale = 0.001;

constexpr std::array<const char*, 4> kStates = {"Vw_mm2", "v_mm_s", "ds_mm", "R0_um"};

struct ModelKey {
  const char* key;
  double g::GrindingParameters::*field;
};
const std::array<ModelKey, 17> kModelKeys = {{{"dw_mm", &g::GrindingParameters::dw_mm},
                                              {"ds0_mm", &g::GrindingParameters::ds0_mm},
                                              {"vs_m_s", &g::GrindingParameters::vs_m_s},
                                              {"vw_m_s", &g::GrindingParameters::vw_m_s},
                                              {"tau_s", &g::GrindingParameters::tau_s},
                                              {"Ks_W_s_mm", &g::GrindingParameters::Ks_W_s_mm},
                                              {"s0", &g::GrindingParameters::s0},
                                              {"s1_per_mm2", &g::GrindingParameters::s1_per_mm2},
                                              {"delta", &g::GrindingParameters::delta},
                                              {"gamma", &g::GrindingParameters::gamma},
                                              {"Rg_um", &g::GrindingParameters::Rg_um},
                                              {"R0_um", &g::GrindingParameters::R0_um},
                                              {"V0_mm2", &g::GrindingParameters::V0_mm2},
                                              {"rm_um", &g::GrindingParameters::rm_um},
                                              {"r0", &g::GrindingParameters::r0},
                                              {"G1", &g::GrindingParameters::G1},
                                              {"g", &g::GrindingParameters::g}}};

// The format's example model (section 7, 002 table II), with the roundness terms.
g::GrindingParameters default_model() {
  g::GrindingParameters p;
  p.vw_m_s = 0.533;
  p.rm_um = 2.4;
  p.r0 = 1.0;
  return p;
}

std::vector<int> int_list(const YAML::Node& n, const std::string& key, const std::string& path,
                          YamlReader& r) {
  std::vector<int> out;
  const YAML::Node v = n[key];
  if (!v) return out;
  if (!v.IsSequence()) {
    r.error(path + "." + key, "must be a list of cycle numbers");
    return out;
  }
  for (const auto& x : v) {
    try {
      out.push_back(x.as<int>());
    } catch (const YAML::Exception&) {
      r.error(path + "." + key, "must be a list of cycle numbers");
      return {};
    }
  }
  return out;
}

void read_variances(const YAML::Node& n, const std::string& path, std::array<double, 4>& out,
                    YamlReader& r) {
  if (!n) return;
  if (!n.IsMap()) {
    r.error(path, "must be a mapping {Vw_mm2, v_mm_s, ds_mm, R0_um}");
    return;
  }
  r.check_keys(n, std::set<std::string>(kStates.begin(), kStates.end()), path);
  for (std::size_t k = 0; k < 4; ++k) {
    out[k] = r.optional_double(n, kStates[k], path).value_or(out[k]);
    if (!(out[k] >= 0)) r.error(path + "." + kStates[k], "must be >= 0");
  }
}

GrindingTestSynth read_test(const YAML::Node& t, const std::string& path, YamlReader& r) {
  GrindingTestSynth s;
  r.check_keys(
      t,
      {"name", "cycles", "G1", "ds_start_mm", "R0_start_um", "R0_walk_var_um2", "R0_cycle_var_um2",
       "uninspected", "ds_unmeasured", "Ra_unmeasured", "late", "dressings"},
      path);
  s.name = r.required_string(t, "name", path);
  if (s.name.empty() || s.name.find_first_of("/\\") != std::string::npos || s.name == "." ||
      s.name == "..") {
    r.error(path + ".name", "must be a folder name (no '/')");
  }
  const double cycles = r.optional_double(t, "cycles", path).value_or(s.cycles);
  if (!(cycles >= 1) || cycles != std::floor(cycles) || cycles > 100000) {
    r.error(path + ".cycles", "must be a whole number >= 1");
  } else {
    s.cycles = static_cast<int>(cycles);
  }
  s.G1 = r.optional_double(t, "G1", path);
  if (s.G1 && !(*s.G1 > 0)) r.error(path + ".G1", "must be > 0");
  s.ds_start = r.optional_double(t, "ds_start_mm", path);
  if (s.ds_start && !(*s.ds_start > 0)) r.error(path + ".ds_start_mm", "must be > 0");
  s.R0_start_um = r.optional_double(t, "R0_start_um", path);
  s.R0_walk_var_um2 = r.optional_double(t, "R0_walk_var_um2", path).value_or(s.R0_walk_var_um2);
  s.R0_cycle_var_um2 = r.optional_double(t, "R0_cycle_var_um2", path).value_or(s.R0_cycle_var_um2);
  if (!(s.R0_walk_var_um2 >= 0)) r.error(path + ".R0_walk_var_um2", "must be >= 0");
  if (!(s.R0_cycle_var_um2 >= 0)) r.error(path + ".R0_cycle_var_um2", "must be >= 0");
  s.uninspected = int_list(t, "uninspected", path, r);
  s.ds_unmeasured = int_list(t, "ds_unmeasured", path, r);
  s.Ra_unmeasured = int_list(t, "Ra_unmeasured", path, r);
  if (const YAML::Node late = t["late"]) {
    bool ok = late.IsSequence();
    if (ok) {
      for (const auto& p : late) {
        if (!p.IsSequence() || p.size() != 2) {
          ok = false;
          break;
        }
        try {
          s.late.emplace_back(p[0].as<int>(), p[1].as<int>());
        } catch (const YAML::Exception&) {
          ok = false;
          break;
        }
      }
    }
    if (!ok) r.error(path + ".late", "must be a list of [cycle, available_cycle]");
  }
  if (const YAML::Node d = t["dressings"]) {
    if (!d.IsSequence()) {
      r.error(path + ".dressings", "must be a list of {before_cycle, depth_mm[, true_depth_mm]}");
    } else {
      for (std::size_t k = 0; k < d.size(); ++k) {
        const std::string dp = path + ".dressings[" + std::to_string(k) + "]";
        r.check_keys(d[k], {"before_cycle", "depth_mm", "true_depth_mm"}, dp);
        GrindingDressingSynth x;
        const double before = r.required_double(d[k], "before_cycle", dp);
        if (before != std::floor(before)) r.error(dp + ".before_cycle", "must be a whole cycle");
        // Out of int range (1e300) or missing (NaN): -1, refused below as outside 2..cycles.
        x.before_cycle =
            std::isfinite(before) && std::abs(before) <= 1e6 ? static_cast<int>(before) : -1;
        x.depth_mm = r.required_double(d[k], "depth_mm", dp);
        x.true_depth_mm = r.optional_double(d[k], "true_depth_mm", dp).value_or(x.depth_mm);
        if (x.before_cycle < 2 || x.before_cycle > s.cycles) {
          r.error(dp + ".before_cycle", "must be in 2.." + std::to_string(s.cycles));
        }
        if (!(x.depth_mm >= 0) || !(x.true_depth_mm >= 0)) {
          r.error(dp, "depth_mm and true_depth_mm must be >= 0");
        }
        s.dressings.push_back(x);
      }
    }
  }
  for (const auto& [c, a] : s.late) {
    if (c < 1 || c > s.cycles || a < c) {
      r.error(path + ".late", "[" + std::to_string(c) + ", " + std::to_string(a) +
                                  "]: needs 1 <= cycle <= cycles and available_cycle >= cycle");
    }
  }
  for (const auto* list : {&s.uninspected, &s.ds_unmeasured, &s.Ra_unmeasured}) {
    for (int c : *list) {
      if (c < 1 || c > s.cycles) {
        r.error(path, "cycle " + std::to_string(c) + " is not in 1.." + std::to_string(s.cycles));
      }
    }
  }
  return s;
}

void emit_variances(YAML::Emitter& y, const char* key, const std::array<double, 4>& v) {
  y << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap;
  for (std::size_t k = 0; k < 4; ++k) y << YAML::Key << kStates[k] << YAML::Value << v[k];
  y << YAML::EndMap;
}

void write_test_yaml(const std::filesystem::path& file, const GrindingSynthSpec& s,
                     const GrindingTestSynth& t) {
  YAML::Emitter y;
  configure_synth_emitter(y);
  y << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "grinding";
  y << YAML::Key << "sample_rate_hz" << YAML::Value << s.fs_hz;
  y << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "file"
    << YAML::Value << "fast.csv" << YAML::EndMap;
  y << YAML::Key << "channels" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "power" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "scale"
    << YAML::Value << kPowerScale << YAML::Key << "offset" << YAML::Value << kPowerOffset
    << YAML::EndMap;
  y << YAML::Key << "Dw_mm" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "scale"
    << YAML::Value << kDwScale << YAML::EndMap;
  y << YAML::EndMap;
  y << YAML::Key << "inspections" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
    << "file" << YAML::Value << "inspections.csv" << YAML::EndMap;
  y << YAML::Key << "model" << YAML::Value << YAML::BeginMap;
  for (const auto& k : kModelKeys) {
    const double v = s.model.*(k.field);
    if (std::isfinite(v)) y << YAML::Key << k.key << YAML::Value << v;
  }
  y << YAML::EndMap;
  y << YAML::Key << "noise" << YAML::Value << YAML::Flow << YAML::BeginMap;
  y << YAML::Key << "power_sd" << YAML::Value << s.power_sd_W;
  y << YAML::Key << "Dw_sd_mm" << YAML::Value << s.Dw_sd_mm;
  y << YAML::Key << "ds_sd_mm" << YAML::Value << s.ds_sd_mm;
  y << YAML::Key << "Ra_sd_um" << YAML::Value << s.Ra_sd_um;
  y << YAML::Key << "roundness_sd_um" << YAML::Value << s.roundness_sd_um << YAML::EndMap;
  y << YAML::Key << "filter" << YAML::Value << YAML::BeginMap;
  emit_variances(y, "P0", s.P0);
  emit_variances(y, "Q", s.Q);
  y << YAML::Key << "R0_cycle_var_um2" << YAML::Value << t.R0_cycle_var_um2 << YAML::EndMap;
  if (!t.dressings.empty()) {
    y << YAML::Key << "dressings" << YAML::Value << YAML::BeginSeq;
    for (const auto& d : t.dressings) {
      y << YAML::Flow << YAML::BeginMap << YAML::Key << "before_cycle" << YAML::Value
        << d.before_cycle << YAML::Key << "depth_mm" << YAML::Value << d.depth_mm << YAML::EndMap;
    }
    y << YAML::EndSeq;
    y << YAML::Key << "dress_sd_mm" << YAML::Value << s.dress_sd_mm;
  }
  y << YAML::EndMap;
  write_synth_yaml(file, y);
}

std::string field(double v) { return std::isfinite(v) ? synth_number(v) : ""; }

void write_inspections(const std::filesystem::path& file, const std::vector<g::Inspection>& ins) {
  std::ofstream o = open_for_writing(file);
  o << "cycle,available_cycle,ds_mm,Ra_um,roundness_um\n";
  for (const auto& i : ins) {
    o << i.cycle << ',' << i.available_cycle << ',' << field(i.ds_mm) << ',' << field(i.Ra_um)
      << ',' << field(i.roundness_um) << '\n';
  }
  close_checked(o, file);
}

// cycle,j,Vw_mm2,v_mm_s,ds_mm,R0_um at j = 0, 10, 20, ... and n_i of every cycle.
void write_truth_trajectory(const std::filesystem::path& file, const g::GrindingSeries& series) {
  std::ofstream o = open_for_writing(file);
  o << "cycle,j,Vw_mm2,v_mm_s,ds_mm,R0_um\n";
  Eigen::Index row = 0;
  for (std::size_t c = 0; c < series.n.size(); ++c) {
    const int n = series.n[c];
    for (int j = 0; j <= n; ++j, ++row) {
      if (j % 10 != 0 && j != n) continue;
      o << c + 1 << ',' << j;
      for (int k = 0; k < 4; ++k) o << ',' << synth_number(series.truth_trajectory(row, k));
      o << '\n';
    }
  }
  close_checked(o, file);
}

}  // namespace

GrindingSynthSpec read_grinding_synth(const YAML::Node& n, YamlReader& r) {
  GrindingSynthSpec s;
  s.model = default_model();
  if (!n.IsMap()) {
    r.error("grinding", "must be a mapping (docs/format/synth-spec.md)");
    return s;
  }
  r.check_keys(n,
               {"sample_rate_hz", "model", "noise", "filter", "process_var", "dress_sd_mm",
                "schedule", "tests"},
               "grinding");
  s.fs_hz = r.optional_double(n, "sample_rate_hz", "grinding").value_or(s.fs_hz);
  if (!(s.fs_hz > 0)) r.error("grinding.sample_rate_hz", "must be > 0");
  if (const YAML::Node m = n["model"]) {
    std::set<std::string> keys;
    for (const auto& k : kModelKeys) keys.insert(k.key);
    r.check_keys(m, keys, "grinding.model");
    for (const auto& k : kModelKeys) {
      s.model.*(k.field) =
          r.optional_double(m, k.key, "grinding.model").value_or(s.model.*(k.field));
    }
  }
  for (const char* k : {"dw_mm", "ds0_mm", "vs_m_s", "tau_s", "V0_mm2", "G1"}) {
    for (const auto& mk : kModelKeys) {
      if (std::string(mk.key) == k && !(s.model.*(mk.field) > 0)) {
        r.error(std::string("grinding.model.") + k, "must be > 0");
      }
    }
  }
  if (const YAML::Node no = n["noise"]) {
    r.check_keys(no, {"power_sd", "Dw_sd_mm", "ds_sd_mm", "Ra_sd_um", "roundness_sd_um"},
                 "grinding.noise");
    s.power_sd_W = r.optional_double(no, "power_sd", "grinding.noise").value_or(s.power_sd_W);
    s.Dw_sd_mm = r.optional_double(no, "Dw_sd_mm", "grinding.noise").value_or(s.Dw_sd_mm);
    s.ds_sd_mm = r.optional_double(no, "ds_sd_mm", "grinding.noise").value_or(s.ds_sd_mm);
    s.Ra_sd_um = r.optional_double(no, "Ra_sd_um", "grinding.noise").value_or(s.Ra_sd_um);
    s.roundness_sd_um =
        r.optional_double(no, "roundness_sd_um", "grinding.noise").value_or(s.roundness_sd_um);
    for (double v : {s.power_sd_W, s.Dw_sd_mm, s.ds_sd_mm, s.Ra_sd_um, s.roundness_sd_um}) {
      if (!(v > 0)) {
        r.error("grinding.noise", "every standard deviation must be > 0");
        break;
      }
    }
  }
  if (const YAML::Node f = n["filter"]) {
    r.check_keys(f, {"P0", "Q"}, "grinding.filter");
    read_variances(f["P0"], "grinding.filter.P0", s.P0, r);
    read_variances(f["Q"], "grinding.filter.Q", s.Q, r);
  }
  if (const YAML::Node pv = n["process_var"]) {
    bool ok = pv.IsSequence() && pv.size() == 3;
    std::array<double, 3> v{};
    for (std::size_t k = 0; ok && k < 3; ++k) {
      try {
        v[k] = pv[k].as<double>();
        ok = v[k] >= 0;
      } catch (const YAML::Exception&) {
        ok = false;
      }
    }
    if (ok) {
      s.process_var = v;
    } else {
      r.error("grinding.process_var", "must be [Vw_mm2, v_mm_s, ds_mm] variances >= 0");
    }
  }
  s.dress_sd_mm = r.optional_double(n, "dress_sd_mm", "grinding").value_or(s.dress_sd_mm);
  if (!(s.dress_sd_mm >= 0)) r.error("grinding.dress_sd_mm", "must be >= 0");
  if (const YAML::Node sc = n["schedule"]) {
    s.schedule.clear();
    if (!sc.IsSequence() || sc.size() == 0) {
      r.error("grinding.schedule", "must be a non-empty list of {u_mm_s, rows}");
    } else {
      for (std::size_t k = 0; k < sc.size(); ++k) {
        const std::string p = "grinding.schedule[" + std::to_string(k) + "]";
        r.check_keys(sc[k], {"u_mm_s", "rows"}, p);
        g::InfeedStage st;
        st.u_mm_s = r.required_double(sc[k], "u_mm_s", p);
        const double rows = r.required_double(sc[k], "rows", p);
        if (!(rows >= 1) || rows != std::floor(rows) || rows > 1e6) {
          r.error(p + ".rows", "must be a whole number >= 1 (at most 1000000)");
        } else {
          st.rows = static_cast<int>(rows);
        }
        s.schedule.push_back(st);
      }
    }
  }
  const YAML::Node tests = n["tests"];
  if (!tests || !tests.IsSequence() || tests.size() == 0) {
    r.error("grinding.tests", "must be a non-empty list of {name, cycles, ...}");
    return s;
  }
  if (tests.size() > 100) {  // one test folder each (docs/format/synth-spec.md)
    r.error("grinding.tests", "has " + std::to_string(tests.size()) + " tests: at most 100");
    return s;
  }
  std::set<std::string> names;
  for (std::size_t k = 0; k < tests.size(); ++k) {
    const std::string path = "grinding.tests[" + std::to_string(k) + "]";
    if (!tests[k].IsMap()) {
      r.error(path, "must be a mapping {name, cycles, ...}");
      continue;
    }
    s.tests.push_back(read_test(tests[k], path, r));
    if (!names.insert(s.tests.back().name).second) {
      r.error(path + ".name", "'" + s.tests.back().name + "' is used twice");
    }
  }
  return s;
}

int write_grinding_tests(const GrindingSynthSpec& s, SynthContext& ctx) {
  int written = 0;
  for (std::size_t k = 0; k < s.tests.size(); ++k) {
    const GrindingTestSynth& t = s.tests[k];
    g::GrindingSeriesSpec spec;
    spec.truth = s.model;
    if (t.G1) spec.truth.G1 = *t.G1;
    spec.sample_period_s = 1.0 / s.fs_hz;
    spec.cycles = t.cycles;
    spec.schedule = s.schedule;
    spec.ds_start_mm = t.ds_start.value_or(s.model.ds0_mm);
    spec.R0_start_um = t.R0_start_um.value_or(s.model.R0_um);
    spec.R0_walk_var_um2 = t.R0_walk_var_um2;
    spec.R0_cycle_var_um2 = t.R0_cycle_var_um2;
    spec.process_var = s.process_var.value_or(std::array<double, 3>{s.Q[0], s.Q[1], s.Q[2]});
    spec.power_sd_W = s.power_sd_W;
    spec.Dw_sd_mm = s.Dw_sd_mm;
    spec.ds_sd_mm = s.ds_sd_mm;
    spec.Ra_sd_um = s.Ra_sd_um;
    spec.roundness_sd_um = s.roundness_sd_um;
    spec.uninspected_cycles = t.uninspected;
    spec.ds_unmeasured_cycles = t.ds_unmeasured;
    spec.Ra_unmeasured_cycles = t.Ra_unmeasured;
    spec.late = t.late;
    for (const auto& d : t.dressings) spec.dressings.push_back({d.before_cycle, d.true_depth_mm});
    spec.seed = ctx.stream_seed("synth.grinding", k);
    const g::GrindingSeries series = g::synthesize_grinding_series(spec);

    const std::string id = "grinding/" + t.name;
    const auto dir = ctx.out / "grinding" / t.name;
    std::filesystem::create_directories(dir);
    const Eigen::Index rows = static_cast<Eigen::Index>(series.record.cycle.size());
    Eigen::VectorXd cycle(rows), volts(rows), counts(rows);
    for (Eigen::Index i = 0; i < rows; ++i) {
      cycle[i] = series.record.cycle[static_cast<std::size_t>(i)];
      volts[i] = (series.record.power_W[i] - kPowerOffset) / kPowerScale;
      counts[i] = series.record.Dw_mm[i] / kDwScale;
    }
    write_signals(dir / "fast.csv", {"cycle", "u_mm_s", "power", "Dw_mm"},
                  {&cycle, &series.record.u_mm_s, &volts, &counts});
    write_inspections(dir / "inspections.csv", series.inspections);
    write_test_yaml(dir / "test.yaml", s, t);
    const std::string traj = "truth-grinding-" + t.name + ".csv";
    write_truth_trajectory(ctx.out / traj, series);
    ++written;

    YAML::Node e(YAML::NodeType::Map);
    e["kind"] = "grinding";
    e["cycles"] = t.cycles;
    e["G1"] = synth_number(spec.truth.G1);
    e["ds_start_mm"] = synth_number(spec.ds_start_mm);
    e["R0_start_um"] = synth_number(spec.R0_start_um);
    YAML::Node pc(YAML::NodeType::Map);
    std::vector<double> cyc, n;
    for (std::size_t i = 0; i < series.n.size(); ++i) {
      cyc.push_back(static_cast<double>(i + 1));
      n.push_back(series.n[i]);
    }
    pc["cycle"] = synth_number_list(cyc);
    pc["n"] = synth_number_list(n);
    for (int c = 0; c < 4; ++c) {
      const Eigen::VectorXd col = series.truth_at_cycle_end.col(c);
      pc[kStates[static_cast<std::size_t>(c)]] =
          synth_number_list(std::vector<double>(col.data(), col.data() + col.size()));
    }
    pc["Ra_um"] = synth_number_list(std::vector<double>(
        series.Ra_true_um.data(), series.Ra_true_um.data() + series.Ra_true_um.size()));
    if (series.roundness_true_um.size() > 0 && series.roundness_true_um.allFinite()) {
      pc["roundness_um"] = synth_number_list(
          std::vector<double>(series.roundness_true_um.data(),
                              series.roundness_true_um.data() + series.roundness_true_um.size()));
    }
    e["per_cycle"] = pc;
    YAML::Node tf(YAML::NodeType::Map);
    tf["file"] = traj;
    tf.SetStyle(YAML::EmitterStyle::Flow);
    e["trajectory"] = tf;
    if (!t.dressings.empty()) {
      YAML::Node ds(YAML::NodeType::Sequence);
      for (const auto& d : t.dressings) {
        ds.push_back(
            synth_numbers({{"before_cycle", d.before_cycle}, {"depth_mm", d.true_depth_mm}}));
      }
      e["dressings"] = ds;
    }
    ctx.truth.tests[id] = e;
  }
  return written;
}

std::shared_ptr<const KindSpec> GrindingKind::parse_synth(const YAML::Node& section,
                                                          const SynthContext&,
                                                          YamlReader& r) const {
  return std::make_shared<GrindingSynthSpec>(read_grinding_synth(section, r));
}

int GrindingKind::write_synth(const KindSpec& section, SynthContext& ctx) const {
  return write_grinding_tests(dynamic_cast<const GrindingSynthSpec&>(section), ctx);
}

}  // namespace chatterlab::app
