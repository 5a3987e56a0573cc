// Kind `sifs-static` and the group `sifs-static` (format section 6, 003 sec. 3.2): see
// sifs_kinds.h and docs/sifs.md.
#include <Eigen/QR>
#include <cmath>
#include <map>
#include <optional>

#include "app/core/archive_analysis.h"
#include "app/core/format.h"
#include "app/kinds/sifs/sifs_common.h"
#include "app/kinds/sifs/sifs_kinds.h"
#include "app/pipeline/cached_result.h"
#include "app/report/figure_jobs.h"
#include "app/report/results_json.h"
#include "app/report/truth.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

json matrix_json(const Eigen::Matrix3d& m) {
  json rows = json::array();
  for (int i = 0; i < 3; ++i) rows.push_back({m(i, 0), m(i, 1), m(i, 2)});
  return rows;
}

const char* const kPairNames[3] = {"s_x", "s_y", "s_z"};

}  // namespace

std::vector<std::string> SifsStaticKind::keys() const {
  return {"axis", "loads", "tool_length_mm"};
}

std::shared_ptr<const KindSpec> SifsStaticKind::parse(const YAML::Node& root, YamlReader& r) const {
  auto s = std::make_shared<SifsStaticSpec>();
  s->axis = read_sifs_axis(root, r, true);
  s->tool_length_mm = read_tool_length(root, r);
  const YAML::Node loads = root["loads"];
  if (!loads) {
    r.error("loads", "is required: a list of [start_s, end_s, load_N]");
    return s;
  }
  if (!loads.IsSequence() || loads.size() < 3) {
    r.error("loads",
            "must be a list of at least three [start_s, end_s, load_N] windows (unloaded, "
            "loaded, unloaded)");
    return s;
  }
  for (std::size_t i = 0; i < loads.size(); ++i) {
    const std::string key = "loads[" + std::to_string(i) + "]";
    const YAML::Node w = loads[i];
    sifs::LoadWindow lw;
    try {
      if (!w.IsSequence() || w.size() != 3) throw YAML::Exception(YAML::Mark::null_mark(), "");
      lw.start_s = w[0].as<double>();
      lw.end_s = w[1].as<double>();
      lw.load_n = w[2].as<double>();
    } catch (const YAML::Exception&) {
      r.error(key, "must be [start_s, end_s, load_N], three numbers");
      continue;
    }
    if (!(lw.start_s >= 0 && lw.end_s > lw.start_s) || !std::isfinite(lw.load_n)) {
      r.error(key, "must have 0 <= start_s < end_s and a finite load");
      continue;
    }
    s->loads.push_back(lw);
  }
  return s;
}

std::vector<std::string> SifsStaticKind::required_channels(const TestSpec&) const {
  return kWasherChannels;
}

std::vector<std::string> SifsStaticKind::check_record(const TestSpec& t, double duration_s) const {
  const auto& s = t.kind_spec<SifsStaticSpec>();
  for (std::size_t i = 0; i < s.loads.size(); ++i) {
    if (auto e =
            window_outside(t, "loads[" + std::to_string(i) + "]", s.loads[i].end_s, duration_s)) {
      return {*e};
    }
  }
  return {};
}

std::vector<std::string> SifsStaticKind::provides(const TestSpec&) const {
  return {value::kSifsStaticRecord};
}

std::string SifsStaticKind::describe_value(const std::string& name) const {
  return name == value::kSifsStaticRecord ? "a static calibration record" : "";
}

void SifsStaticKind::run(const TestSpec& t, const CampaignValues&, const RunContext&,
                         TestOutcome& out) const {
  const auto& s = t.kind_spec<SifsStaticSpec>();
  const SignalTable table = SignalTable::open(t.data, t.data_label());
  const sifs::Washers w = read_washers(table, t);
  auto res = std::make_unique<SifsStaticResult>();
  try {
    res->reduction = sifs::reduce_static_test(w, t.sample_rate_hz, s.axis, s.loads);
  } catch (const InputError& e) {
    throw InputError(t.yaml_label + ": " + e.what());
  }
  out.warnings.insert(out.warnings.end(), res->reduction.summary.warnings.begin(),
                      res->reduction.summary.warnings.end());
  if (!res->reduction.summary.ok()) {
    out.status.fail(t.data_label() + ": " + res->reduction.summary.message);
    return;
  }
  out.result = std::move(res);
  out.status.succeed();
}

void SifsStaticKind::publish(const TestOutcome& out, CampaignValues& values) const {
  values.put(value::kSifsStaticRecord, out.spec->id, out.result_of<SifsStaticResult>().reduction);
}

json SifsStaticKind::results(const TestOutcome& out) const {
  const auto& red = out.result_of<SifsStaticResult>().reduction;
  json drift = json::array();
  for (int i = 0; i < 6; ++i) drift.push_back(red.drift_per_s(i) * 60.0);
  json windows = json::array();
  for (std::size_t i = 0; i < red.windows.size(); ++i) {
    windows.push_back({{"start_s", red.windows[i].start_s},
                       {"end_s", red.windows[i].end_s},
                       {"load_N", red.windows[i].load_n},
                       {"s_N", {red.s[i](0), red.s[i](1), red.s[i](2)}}});
  }
  return {{"axis", sifs::to_string(red.axis)},
          {"drift_per_min", drift},
          {"drift_channels", kWasherChannels},
          {"windows", windows}};
}

std::string SifsStaticKind::note(const TestOutcome& out) const {
  const auto& red = out.result_of<SifsStaticResult>().reduction;
  return std::to_string(red.windows.size()) + " windows along " + sifs::to_string(red.axis);
}

// ---- group ---------------------------------------------------------------------------------

bool SifsStaticGroup::applies(const CampaignSpec& c) const {
  for (const auto& t : c.tests) {
    if (t.kind == "sifs-static") return true;
  }
  return false;
}

std::vector<Need> SifsStaticGroup::needs(const CampaignSpec&) const {
  return {{value::kSifsStaticRecord, false}};
}

std::vector<std::string> SifsStaticGroup::provides(const CampaignSpec&) const {
  return {value::kSifsCalibration};
}

std::string SifsStaticGroup::describe_value(const std::string& name) const {
  return name == value::kSifsCalibration ? "the sensor's calibration matrix" : "";
}

void SifsStaticGroup::run(const CampaignValues& in, const RunContext& ctx,
                          GroupOutcome& out) const {
  auto g = std::make_unique<SifsStaticGroupResult>();
  int members = 0;
  std::map<std::string, std::optional<double>> length_of;
  for (const auto& t : ctx.campaign->tests) {
    if (t.kind != "sifs-static") continue;
    ++members;
    if (const auto* s = dynamic_cast<const SifsStaticSpec*>(t.params.get())) {
      length_of[t.id] = s->tool_length_mm;
    }
  }
  std::map<double, std::vector<sifs::StaticReduction>> by_length;
  bool some_without = false;
  for (const auto& [id, red] : in.all<sifs::StaticReduction>(value::kSifsStaticRecord)) {
    out.members.push_back(id);
    g->ids.push_back(id);
    g->tests.push_back(*red);
    const auto L = length_of[id];
    if (L) {
      by_length[*L].push_back(*red);
    } else {
      some_without = true;
    }
  }
  const int analysed = static_cast<int>(g->tests.size());
  const auto finish = [&](const StepSummary& status) {
    out.status = status;
    if (!out.status.ok() && analysed < members) {
      out.status.fail(std::to_string(analysed) + " of " + std::to_string(members) +
                      " sifs-static tests analysed: " + status.message);
    }
    out.result = std::move(g);
  };
  if (by_length.size() <= 1) {
    // One tool (or none named): one calibration over every window.
    g->fit = sifs::fit_calibration(g->tests);
    g->calibration.C = g->fit.C;
    if (by_length.size() == 1 && !some_without) {
      g->calibration.single_length_mm = by_length.begin()->first;
    }
    finish(g->fit.summary);
    return;
  }
  if (some_without) {
    StepSummary s;
    s.fail(
        "the static tests name several tool lengths, but not all of them: set "
        "tool_length_mm in every sifs-static test");
    finish(s);
    return;
  }
  // Several tools: one calibration per length (each needs its three axes), then the straight
  // line of every entry against the length (003 eq. 3-4 generalised).
  for (const auto& [L, tests] : by_length) {
    sifs::CalibrationFit f = sifs::fit_calibration(tests);
    if (!f.summary.ok()) {
      StepSummary s;
      s.fail("tool_length_mm " + fmt_sig(L, 6) + ": " + f.summary.message);
      finish(s);
      return;
    }
    g->by_length.emplace_back(L, f);
    g->calibration.by_length.emplace_back(L, f.C);
  }
  g->fit = g->by_length.front().second;
  g->calibration.C = g->fit.C;
  const auto n = static_cast<Eigen::Index>(g->by_length.size());
  Eigen::MatrixX2d A(n, 2);
  for (Eigen::Index k = 0; k < n; ++k) {
    A.row(k) << g->by_length[static_cast<std::size_t>(k)].first, 1.0;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixX2d> qr(A);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      Eigen::VectorXd y(n);
      for (Eigen::Index k = 0; k < n; ++k) {
        y(k) = g->by_length[static_cast<std::size_t>(k)].second.C(i, j);
      }
      const Eigen::Vector2d p = qr.solve(y);
      g->calibration.slope_per_mm(i, j) = p(0);
      g->calibration.intercept(i, j) = p(1);
    }
  }
  StepSummary ok;
  ok.succeed();
  finish(ok);
}

void SifsStaticGroup::publish(const GroupOutcome& out, CampaignValues& values) const {
  values.put(value::kSifsCalibration, "group:" + name(),
             out.result_of<SifsStaticGroupResult>().calibration);
}

json SifsStaticGroup::results(const GroupOutcome& out) const {
  json d;
  d["tests"] = out.members;
  const auto* g = out.result_as<SifsStaticGroupResult>();
  if (!out.status.ok() || !g) {
    d["status"] = out.failure == Failure::kInternal ? "error" : "skipped";
    d["skip_reason"] = out.status.message;
    return d;
  }
  const auto& f = g->fit;
  d["calibration_matrix"] = matrix_json(f.C);
  d["sensitivity_matrix"] = matrix_json(f.S);
  d["residual_rms_N"] = f.residual_rms_n;
  d["residual_max_pct"] = f.residual_max_pct;
  d["windows"] = f.windows;
  d["cond_S"] = f.cond_S;
  json lin = json::object();
  for (int a = 0; a < 3; ++a) lin[kPairNames[a]] = number_or_null(f.linearity_pct(a));
  d["linearity_pct"] = lin;
  if (!g->by_length.empty()) {
    json lengths = json::array();
    for (const auto& [L, fit] : g->by_length) {
      lengths.push_back({{"tool_length_mm", L},
                         {"calibration_matrix", matrix_json(fit.C)},
                         {"residual_rms_N", fit.residual_rms_n},
                         {"residual_max_pct", fit.residual_max_pct}});
    }
    d["by_tool_length"] = lengths;
    d["tool_length_law"] = {{"slope_per_mm", matrix_json(g->calibration.slope_per_mm)},
                            {"intercept", matrix_json(g->calibration.intercept)}};
  }
  if (!out.status.warnings.empty()) d["warnings"] = out.status.warnings;
  return d;
}

namespace {

render::Figure sifs_static_figure(const SifsStaticGroupResult& g) {
  // Calibrated force C s_w against the applied load, per loaded axis, with the identity line.
  render::Figure fig;
  fig.height_in = 3.2;
  render::Axes& a = fig.panels.emplace_back();
  a.x_label = "applied load [N]";
  a.y_label = "calibrated force along the load [N]";
  a.legend = render::LegendPosition::kTopLeft;
  const char* colors[3] = {"#0072B2", "#D55E00", "#009E73"};
  double lo = 0, hi = 0;
  std::array<render::Series, 3> pts;
  for (int k = 0; k < 3; ++k) {
    pts[static_cast<std::size_t>(k)].label =
        std::string("load along ") + sifs::to_string(static_cast<sifs::Axis>(k));
    pts[static_cast<std::size_t>(k)].style = render::SeriesStyle::kPoints;
    pts[static_cast<std::size_t>(k)].color = colors[k];
  }
  for (const auto& t : g.tests) {
    const int k = static_cast<int>(t.axis);
    for (std::size_t i = 0; i < t.s.size(); ++i) {
      const Eigen::Vector3d f = g.fit.C * t.s[i];
      const double load = t.f[i](k);
      pts[static_cast<std::size_t>(k)].x.push_back(load);
      pts[static_cast<std::size_t>(k)].y.push_back(f(k));
      lo = std::min(lo, load);
      hi = std::max(hi, load);
    }
  }
  render::Series line;
  line.label = "identity";
  line.style = render::SeriesStyle::kDashedLine;
  line.color = "#555555";
  line.x = {lo, hi};
  line.y = {lo, hi};
  for (auto& p : pts) {
    if (!p.x.empty()) a.series.push_back(p);
  }
  a.series.push_back(line);
  return fig;
}

}  // namespace

void SifsStaticGroup::figures(const CampaignResults&, const GroupOutcome& out,
                              FigureJobs& jobs) const {
  if (!out.status.ok()) return;
  jobs.add("group:" + name(), "calibration", "figures/sifs-static-calibration",
           sifs_static_figure(out.result_of<SifsStaticGroupResult>()));
}

json SifsStaticGroup::report_section(const CampaignResults&, const GroupOutcome& out,
                                     const FigureSet& figures) const {
  json d;
  d["ok"] = out.status.ok();
  d["message"] = out.status.message;
  d["tests"] = out.members;
  const auto* g = out.result_as<SifsStaticGroupResult>();
  if (out.status.ok() && g) {
    const auto& f = g->fit;
    json rows = json::array();
    const char* names[3] = {"f<sub>x</sub>", "f<sub>y</sub>", "f<sub>z</sub>"};
    for (int i = 0; i < 3; ++i) {
      rows.push_back(
          {{"name", names[i]},
           {"c0", fmt_sig(f.C(i, 0), 4)},
           {"c1", fmt_sig(f.C(i, 1), 4)},
           {"c2", fmt_sig(f.C(i, 2), 4)},
           {"linearity", std::isfinite(f.linearity_pct(i)) ? fmt_sig(f.linearity_pct(i), 3)
                                                           : std::string("n/a")}});
    }
    d["rows"] = rows;
    d["residual_rms_N"] = fmt_sig(f.residual_rms_n, 3);
    d["residual_max_pct"] = fmt_sig(f.residual_max_pct, 3);
    d["windows"] = f.windows;
    d["cond_S"] = fmt_sig(f.cond_S, 3);
    d["figure"] = figures.of("group:" + name(), "calibration");
  }
  return {
      {"toc",
       json::array({{{"anchor", "sifs-static"}, {"title", "Spindle sensor: static calibration"}}})},
      {"sifs_static", d}};
}

// truth.yaml `calibration_matrix` (top level, not a `tests:` entry) against the fit: compared
// once, at the first entry the group is shown.
void SifsStaticGroup::compare_truth(const TruthInput& in, const std::string&,
                                    const GroupOutcome& out, TruthComparison& c) const {
  const auto* g = out.result_as<SifsStaticGroupResult>();
  if (!out.status.ok() || !g) return;
  for (const auto& row : c.rows) {
    if (row.source == "group:sifs-static") return;
  }
  const YAML::Node cm = (*in.root)["calibration_matrix"];
  if (!cm || !cm.IsSequence() || cm.size() != 3) return;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double v = std::nan("");
      try {
        v = cm[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)].as<double>();
      } catch (const YAML::Exception&) {
      }
      add_truth_row(c, "calibration_matrix[" + std::to_string(i) + "][" + std::to_string(j) + "]",
                    "group:sifs-static", v, g->fit.C(i, j));
    }
  }
}

// ---- the per-test cache (app/core/archive.h) -------------------------------------------------

template <class Ar>
void fields(Ar& ar, SifsCalibration& c) {
  LAYOUT_GUARD(SifsCalibration, 256);
  ar(c.C, c.by_length, c.slope_per_mm, c.intercept, c.single_length_mm);
}

template <class Ar>
void fields(Ar& ar, SifsStaticResult& r) {
  LAYOUT_GUARD(SifsStaticResult, 304);
  ar(r.reduction);
}

template <class Ar>
void fields(Ar& ar, SifsStaticGroupResult& g) {
  LAYOUT_GUARD(SifsStaticGroupResult, 656);
  ar(g.ids, g.tests, g.fit, g.by_length, g.calibration);
}

std::string SifsStaticKind::save(const TestOutcome& out) const {
  return save_result<SifsStaticResult>(out);
}

void SifsStaticKind::restore(const TestSpec&, const std::string& bytes, TestOutcome& out) const {
  restore_result<SifsStaticResult>(bytes, out);
}

std::string SifsStaticGroup::save(const GroupOutcome& out) const {
  return save_result<SifsStaticGroupResult>(out);
}

void SifsStaticGroup::restore(const std::string& bytes, GroupOutcome& out) const {
  restore_result<SifsStaticGroupResult>(bytes, out);
}

}  // namespace chatterlab::app
