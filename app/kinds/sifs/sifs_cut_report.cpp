// Figures and report sections of the sifs-cut kind, and the group `sifs-cut` (the tap-test
// RMSE(speed, q) map and the Q_opt table, 003 sec. 6.1 and tables 8-15).
#include <cmath>
#include <limits>

#include "analysis/common/constants.h"
#include "app/core/archive_analysis.h"
#include "app/core/format.h"
#include "app/kinds/sifs/sifs_common.h"
#include "app/kinds/sifs/sifs_kinds.h"
#include "app/pipeline/cached_result.h"
#include "app/report/figure_jobs.h"
#include "app/report/results_json.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

constexpr const char* kAxisNames[2] = {"x", "y"};

std::string pct_or_na(double v) { return std::isfinite(v) ? fmt_sig(v, 3) : std::string("n/a"); }

}  // namespace

render::Figure sifs_cut_spectrum_figure(const SifsCutResult& c, int axis) {
  const SifsAxisResult& ax = c.axes[static_cast<std::size_t>(axis)];
  std::vector<double> f, meas, comp, ref;
  for (std::size_t i = 0; i < ax.harmonics.size(); ++i) {
    const Eigen::Index k = static_cast<Eigen::Index>(i);
    f.push_back(ax.harmonics[i] * c.spindle_hz);
    meas.push_back(std::abs(ax.c_measured(k)));
    comp.push_back(std::abs(ax.c_compensated(k)));
    if (c.has_reference) ref.push_back(std::abs(ax.c_reference(k)));
  }
  render::Figure fig;
  fig.height_in = 3.2;
  render::Axes& a = fig.panels.emplace_back();
  a.x_label = "frequency [Hz]";
  a.y_label = std::string("|c_h|, f_") + kAxisNames[axis] + " [N]";
  a.log_y = true;
  a.legend = render::LegendPosition::kAuto;
  if (c.has_reference) {
    a.series.emplace_back(f, ref, "reference (dynamometer)", render::SeriesStyle::kLinePoints,
                          "#000000");
  }
  a.series.emplace_back(f, meas, "sensor, uncompensated", render::SeriesStyle::kLinePoints,
                        "#0072B2");
  a.series.emplace_back(f, comp, "sensor, Kalman compensated", render::SeriesStyle::kLinePoints,
                        "#D55E00");
  return fig;
}

render::Figure sifs_cut_rmse_figure(const SifsCutResult& c) {
  render::Figure fig;
  fig.height_in = 4.2;
  for (int a = 0; a < 2; ++a) {
    const SifsAxisResult& ax = c.axes[static_cast<std::size_t>(a)];
    render::Axes& p = fig.panels.emplace_back();
    p.x_label = "q exponent n (q = 2^n)";
    p.y_label = std::string("RMSE ") + kAxisNames[a] + " [N]";
    p.log_y = true;
    p.legend = render::LegendPosition::kAuto;
    std::vector<double> n, tap;
    for (std::size_t i = 0; i < ax.tap_curve.exponents.size(); ++i) {
      n.push_back(ax.tap_curve.exponents[i]);
      tap.push_back(ax.tap_curve.rmse_n(static_cast<Eigen::Index>(i)));
    }
    p.series.emplace_back(n, tap, "tap test (hammer reference)", render::SeriesStyle::kLine,
                          "#0072B2");
    p.series.emplace_back(
        std::vector<double>{static_cast<double>(ax.q_exponent)},
        std::vector<double>{ax.tap_curve.rmse_n(ax.q_exponent - ax.tap_curve.exponents.front())},
        "tap-test choice", render::SeriesStyle::kLinePoints, "#0072B2");
    if (ax.cut_curve.summary.ok()) {
      std::vector<double> cn, cut;
      for (std::size_t i = 0; i < ax.cut_curve.exponents.size(); ++i) {
        cn.push_back(ax.cut_curve.exponents[i]);
        cut.push_back(ax.cut_curve.rmse_n(static_cast<Eigen::Index>(i)));
      }
      p.series.emplace_back(cn, cut, "cut (dynamometer reference)", render::SeriesStyle::kLine,
                            "#D55E00");
      const int b = ax.cut_curve.best_exponent;
      p.series.emplace_back(
          std::vector<double>{static_cast<double>(b)},
          std::vector<double>{ax.cut_curve.rmse_n(b - ax.cut_curve.exponents.front())},
          "cutting optimum", render::SeriesStyle::kLinePoints, "#D55E00");
    }
  }
  return fig;
}

void SifsCutKind::figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const {
  const auto& r = out.result_of<SifsCutResult>();
  const std::string stem = figure_stem("sifs-cut", out.spec->id);
  jobs.add(out.spec->id, "spectrum-x", stem + "spectrum-x", sifs_cut_spectrum_figure(r, 0));
  jobs.add(out.spec->id, "spectrum-y", stem + "spectrum-y", sifs_cut_spectrum_figure(r, 1));
  jobs.add(out.spec->id, "rmse", stem + "rmse", sifs_cut_rmse_figure(r));
}

json SifsCutKind::report_section(const CampaignResults&, const std::vector<const TestOutcome*>& ok,
                                 const FigureSet& figures) const {
  if (ok.empty()) return nullptr;
  json tests = json::array();
  for (const TestOutcome* t : ok) {
    const auto& r = t->result_of<SifsCutResult>();
    const auto& s = t->spec->kind_spec<SifsCutSpec>();
    json j;
    j["id"] = t->spec->id;
    j["rpm"] = fmt_sig(r.spindle_rpm, 5);
    j["tpf_hz"] = fmt_sig(r.tooth_passing_hz, 5);
    j["filter_rate_hz"] = fmt_sig(r.filter_rate_hz, 5);
    j["gain"] = sifs::to_string(s.gain);
    j["has_reference"] = r.has_reference;
    json axes = json::array();
    for (int a = 0; a < 2; ++a) {
      const SifsAxisResult& ax = r.axes[static_cast<std::size_t>(a)];
      json e;
      e["axis"] = kAxisNames[a];
      e["q_exponent"] = ax.q_exponent;
      e["cut_exponent"] =
          ax.cut_curve.summary.ok() ? std::to_string(ax.cut_curve.best_exponent) : "n/a";
      e["r_N"] = fmt_sig(ax.r_cut_n, 3);
      e["r_tap_N"] = fmt_sig(ax.r_tap_n, 3);
      e["rmse_measured_N"] = pct_or_na(ax.rmse_measured_n);
      e["rmse_compensated_N"] = pct_or_na(ax.rmse_compensated_n);
      e["bw_before_hz"] = fmt_sig(ax.bandwidth_before_hz, 4);
      e["bw_after_hz"] = pct_or_na(ax.bandwidth_after_hz);
      std::string ub;
      for (std::size_t i = 0; i < ax.unbalance.harmonics.size(); ++i) {
        const auto c = ax.unbalance.c(static_cast<Eigen::Index>(i));
        ub += (ub.empty() ? "" : ", ") + std::to_string(ax.unbalance.harmonics[i]) +
              "x: " + fmt_sig(std::abs(c), 3) + " N at " + fmt_fixed(std::arg(c) * kRadToDeg, 1) +
              " deg";
      }
      e["unbalance"] = ub.empty() ? std::string("not fitted") : ub;
      json hs = json::array();
      for (std::size_t i = 0; i < ax.harmonics.size() && i < 12; ++i) {
        const Eigen::Index k = static_cast<Eigen::Index>(i);
        json h;
        h["h"] = ax.harmonics[i];
        h["f_hz"] = fmt_sig(ax.harmonics[i] * r.spindle_hz, 5);
        h["measured_N"] = fmt_sig(std::abs(ax.c_measured(k)), 3);
        h["compensated_N"] = fmt_sig(std::abs(ax.c_compensated(k)), 3);
        if (r.has_reference) {
          const auto cr = ax.c_reference(k);
          const double ra = std::abs(cr);
          h["reference_N"] = fmt_sig(ra, 3);
          h["err_before_pct"] =
              pct_or_na(ra > 0 ? 100 * (std::abs(ax.c_measured(k)) - ra) / ra : NAN);
          h["err_after_pct"] =
              pct_or_na(ra > 0 ? 100 * (std::abs(ax.c_compensated(k)) - ra) / ra : NAN);
          double d = std::arg(ax.c_compensated(k) / cr) * kRadToDeg;
          if (d <= -180) d += 360;
          h["phase_after_deg"] = ra > 0 ? fmt_fixed(d, 1) : std::string("n/a");
        }
        hs.push_back(h);
      }
      e["harmonics"] = hs;
      e["more_harmonics"] = ax.harmonics.size() > 12;
      e["spectrum_figure"] = figures.of(t->spec->id, std::string("spectrum-") + kAxisNames[a]);
      axes.push_back(e);
    }
    j["axes"] = axes;
    j["rmse_figure"] = figures.of(t->spec->id, "rmse");
    j["compensated_file"] = sifs_compensated_path(t->spec->id);
    j["has_warnings"] = !t->warnings.empty();
    j["warnings"] = t->warnings;
    tests.push_back(j);
  }
  return {{"toc",
           json::array({{{"anchor", "sifs-cut"}, {"title", "Spindle sensor: compensated cuts"}}})},
          {"sifs_cuts_intro", true},
          {"sifs_cuts", tests}};
}

// ---- group ---------------------------------------------------------------------------------

std::vector<double> sifs_map_grid(const std::vector<double>& cut_rpm) {
  std::vector<double> g;
  for (int r = 1000; r <= 24000; r += 500) g.push_back(r);
  g.insert(g.end(), cut_rpm.begin(), cut_rpm.end());
  std::sort(g.begin(), g.end());
  g.erase(
      std::unique(g.begin(), g.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }),
      g.end());
  return g;
}

bool SifsCutGroup::applies(const CampaignSpec& c) const {
  for (const auto& t : c.tests) {
    if (t.kind == "sifs-cut") return true;
  }
  return false;
}

std::vector<Need> SifsCutGroup::needs(const CampaignSpec& c) const {
  std::vector<Need> n{{value::kSifsCutSummary, false}};
  for (const auto& t : c.tests) {
    if (t.kind != "sifs-cut" || !t.usable()) continue;
    const auto& s = t.kind_spec<SifsCutSpec>();
    n.push_back({value::sifs_tap(s.tap_x), false});
    n.push_back({value::sifs_tap(s.tap_y), false});
    break;  // the map uses the first cut's taps
  }
  return n;
}

void SifsCutGroup::run(const CampaignValues& in, const RunContext& ctx, GroupOutcome& out) const {
  auto g = std::make_unique<SifsCutGroupResult>();
  const CampaignSpec& c = *ctx.campaign;
  const TestSpec* first = nullptr;
  for (const auto& t : c.tests) {
    if (t.kind == "sifs-cut" && t.usable()) {
      first = &t;
      break;
    }
  }
  std::vector<double> rpm;
  for (const auto& [id, sum] :
       in.all<std::shared_ptr<const SifsCutSummary>>(value::kSifsCutSummary)) {
    out.members.push_back(id);
    g->cuts.push_back(**sum);
    rpm.push_back((*sum)->spindle_rpm);
  }
  if (!first || !c.tool) {
    out.result = std::move(g);
    out.status.fail(first ? "campaign.yaml has no tool" : "no usable sifs-cut test");
    return;
  }
  const auto& s = first->kind_spec<SifsCutSpec>();
  g->filter_rate_hz = s.filter_rate_hz.value_or(first->sample_rate_hz);
  g->teeth = c.tool->teeth;
  const double band_lo = s.band_hz ? s.band_hz->first : 0.0;
  const double band_hi = s.band_hz ? s.band_hz->second : 0.4 * g->filter_rate_hz;
  const std::string ids[2] = {s.tap_x, s.tap_y};
  const std::vector<double> grid = sifs_map_grid(rpm);
  std::string missing;
  for (int a = 0; a < 2; ++a) {
    const auto* p = in.first<std::shared_ptr<const SifsTapData>>(value::sifs_tap(ids[a]));
    g->tap_ids[static_cast<std::size_t>(a)] = ids[a];
    if (!p) {
      missing = in.why_missing(value::sifs_tap(ids[a]), "the sensor model of " + ids[a]);
      continue;
    }
    try {
      const sifs::TapSweepInput tin =
          tap_sweep_input(**p, g->filter_rate_hz, band_lo, band_hi, s.gain);
      g->maps[static_cast<std::size_t>(a)] = sifs::tap_map(tin, grid, g->teeth, ctx.jobs);
    } catch (const InputError& e) {
      throw InputError("tap map of " + ids[a] + " at the filter rate of " + first->id + ": " +
                       e.what());
    }
  }
  out.result = std::move(g);
  if (!missing.empty()) {
    out.status.fail(missing);
    out.failure = Failure::kInput;
    return;
  }
  out.status.succeed();
}

json SifsCutGroup::results(const GroupOutcome& out) const {
  json d;
  d["tests"] = out.members;
  const auto* g = out.result_as<SifsCutGroupResult>();
  if (!out.status.ok() || !g) {
    d["status"] = out.failure == Failure::kInternal ? "error" : "skipped";
    d["skip_reason"] = out.status.message;
    return d;
  }
  json rpm = json::array(), qx = json::array(), qy = json::array(), cx = json::array(),
       cy = json::array();
  for (const auto& c : g->cuts) {
    rpm.push_back(c.spindle_rpm);
    qx.push_back(c.tap_exponent[0]);
    qy.push_back(c.tap_exponent[1]);
    cx.push_back(c.cut_exponent[0] ? json(c.cut_exponent[0]) : json(nullptr));
    cy.push_back(c.cut_exponent[1] ? json(c.cut_exponent[1]) : json(nullptr));
  }
  // How often the tap-test choice is within one step of n of the cutting optimum (the report's
  // sentence): axis-cuts with a cutting optimum, and those matched.
  int compared = 0, matched = 0;
  for (const auto& c : g->cuts) {
    for (std::size_t a = 0; a < 2; ++a) {
      if (!c.cut_exponent[a]) continue;
      ++compared;
      matched += std::abs(c.tap_exponent[a] - c.cut_exponent[a]) <= 1;
    }
  }
  d["compared_axis_cuts_count"] = compared;
  d["tap_within_one_step_count"] = matched;
  d["spindle_rpm"] = rpm;
  d["q_exponent_x"] = qx;
  d["q_exponent_y"] = qy;
  d["cut_optimum_q_exponent_x"] = cx;
  d["cut_optimum_q_exponent_y"] = cy;
  json map = json::object();
  map["filter_rate_hz"] = g->filter_rate_hz;
  for (int a = 0; a < 2; ++a) {
    const sifs::TapMap& m = g->maps[static_cast<std::size_t>(a)];
    if (m.rpm.empty()) continue;
    json rows = json::array(), best = json::array();
    for (int b : m.best_exponent) best.push_back(b > 0 ? json(b) : json(nullptr));
    for (Eigen::Index i = 0; i < m.rmse_n.rows(); ++i) {
      json row = json::array();
      for (Eigen::Index j = 0; j < m.rmse_n.cols(); ++j)
        row.push_back(number_or_null(m.rmse_n(i, j)));
      rows.push_back(row);
    }
    map[std::string("tap_") + kAxisNames[a]] = {{"test", g->tap_ids[static_cast<std::size_t>(a)]},
                                                {"spindle_rpm", m.rpm},
                                                {"q_exponents", m.exponents},
                                                {"rmse_N", rows},
                                                {"best_q_exponent", best}};
  }
  d["tap_map"] = map;
  return d;
}

json SifsCutGroup::settings(const CampaignSpec&) const {
  return {{"map_grid_rpm", "1000 to 24000 in 500 rpm steps, plus every cut's speed"}};
}

render::Figure sifs_map_figure(const SifsCutGroupResult& g) {
  render::Figure fig;
  fig.height_in = 4.2;
  for (int a = 0; a < 2; ++a) {
    const sifs::TapMap& m = g.maps[static_cast<std::size_t>(a)];
    render::Axes& p = fig.panels.emplace_back();
    p.x_label = "spindle speed [rpm]";
    p.y_label = std::string("q exponent, ") + kAxisNames[a];
    p.legend = render::LegendPosition::kAuto;
    std::vector<double> x, y;
    for (std::size_t i = 0; i < m.rpm.size(); ++i) {
      x.push_back(m.rpm[i]);
      // -1: no harmonic in the band at this speed (a gap in the line).
      y.push_back(m.best_exponent[i] > 0 ? m.best_exponent[i]
                                         : std::numeric_limits<double>::quiet_NaN());
    }
    p.series.emplace_back(x, y, "tap-test choice (0.5 % rule)", render::SeriesStyle::kLine,
                          "#0072B2");
    std::vector<double> cx, cy;
    for (const auto& c : g.cuts) {
      const int e = c.cut_exponent[static_cast<std::size_t>(a)];
      if (e == 0) continue;
      cx.push_back(c.spindle_rpm);
      cy.push_back(e);
    }
    if (!cx.empty()) {
      p.series.emplace_back(cx, cy, "cutting optimum (dynamometer)", render::SeriesStyle::kPoints,
                            "#D55E00");
    }
  }
  return fig;
}

void SifsCutGroup::figures(const CampaignResults&, const GroupOutcome& out,
                           FigureJobs& jobs) const {
  if (!out.status.ok()) return;
  jobs.add("group:" + name(), "map", "figures/sifs-cut-q-map",
           sifs_map_figure(out.result_of<SifsCutGroupResult>()));
}

json SifsCutGroup::report_section(const CampaignResults&, const GroupOutcome& out,
                                  const FigureSet& figures) const {
  json d;
  d["ok"] = out.status.ok();
  d["message"] = out.status.message;
  const auto* g = out.result_as<SifsCutGroupResult>();
  if (out.status.ok() && g) {
    json rows = json::array();
    int matched = 0, compared = 0;
    for (const auto& c : g->cuts) {
      json r;
      r["id"] = c.id;
      r["rpm"] = fmt_sig(c.spindle_rpm, 5);
      for (int a = 0; a < 2; ++a) {
        const std::string k = kAxisNames[a];
        const int tap = c.tap_exponent[static_cast<std::size_t>(a)];
        const int cut = c.cut_exponent[static_cast<std::size_t>(a)];
        r["tap_" + k] = tap;
        r["cut_" + k] = cut ? std::to_string(cut) : std::string("n/a");
        if (cut) {
          ++compared;
          matched += std::abs(tap - cut) <= 1;
        }
      }
      rows.push_back(r);
    }
    d["rows"] = rows;
    d["has_comparison"] = compared > 0;
    d["matched"] = matched;
    d["compared"] = compared;
    d["figure"] = figures.of("group:" + name(), "map");
    d["filter_rate_hz"] = fmt_sig(g->filter_rate_hz, 5);
  }
  return {{"toc", json::array({{{"anchor", "sifs-q"}, {"title", "Spindle sensor: Q tuning"}}})},
          {"sifs_q", d}};
}

// ---- the per-test cache (app/core/archive.h) -------------------------------------------------

template <class Ar>
void fields(Ar& ar, SifsCutSummary& s) {
  LAYOUT_GUARD(SifsCutSummary, 56);
  ar(s.id, s.spindle_rpm, s.tap_exponent, s.cut_exponent);
}

template <class Ar>
void fields(Ar& ar, SifsCutGroupResult& g) {
  LAYOUT_GUARD(SifsCutGroupResult, 304);
  ar(g.cuts, g.tap_ids, g.maps, g.filter_rate_hz, g.teeth);
}

std::string SifsCutGroup::save(const GroupOutcome& out) const {
  return save_result<SifsCutGroupResult>(out);
}

void SifsCutGroup::restore(const std::string& bytes, GroupOutcome& out) const {
  restore_result<SifsCutGroupResult>(bytes, out);
}

}  // namespace chatterlab::app
