#include "app/kinds/lobes/lobes_group.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/frf/mode.h"
#include "app/core/archive_analysis.h"
#include "app/core/format.h"
#include "app/kinds/cut/cut_summary.h"
#include "app/kinds/dyno_slot/dyno_slot_kind.h"
#include "app/kinds/tap/tap_kind.h"
#include "app/lobes/lobes_run.h"
#include "app/pipeline/cached_result.h"
#include "app/report/figure_jobs.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

const char* operation_name(milling::Operation op) {
  return op == milling::Operation::kDownMilling ? "down-milling" : "up-milling";
}

// Two immersions are one condition within 0.1 um.
bool same_condition(const CutSummary& c, milling::Operation op, double immersion_m) {
  return c.operation == op && std::abs(c.radial_immersion_m - immersion_m) <= 1e-7;
}

std::vector<ModalParameters> as_modal(const std::vector<frf::Mode>& modes) {
  return std::vector<ModalParameters>(modes.begin(), modes.end());
}

std::string modes_note(const std::vector<frf::Mode>& modes) {
  std::string s;
  for (const auto& m : modes) s += (s.empty() ? "" : ", ") + fmt_sig(m.fn_hz, 4) + " Hz";
  return s;
}

}  // namespace

void add_measured_points(const std::vector<const CutSummary*>& cuts, LobeDiagram& d) {
  for (const CutSummary* c : cuts) {
    MeasuredPoint p;
    p.test = c->id;
    p.spindle_rpm = c->spindle_rpm;
    p.ramp = c->ramped;
    p.depth_low_m = std::min(c->depth_start_m, c->depth_end_m);
    p.depth_high_m = std::max(c->depth_start_m, c->depth_end_m);
    if (!c->ramped) {
      p.chatter = c->chatter;
    } else if (c->bifurcation_ok) {
      if (c->bifurcation_depth_m) {
        const double b = std::clamp(*c->bifurcation_depth_m, p.depth_low_m, p.depth_high_m);
        p.bifurcation_depth_m = b;
        p.stable_m.push_back({p.depth_low_m, b});
        p.chatter_m.push_back({b, p.depth_high_m});
      } else if (c->verdict == dynamics::RunVerdict::kAllStable) {
        p.stable_m.push_back({p.depth_low_m, p.depth_high_m});
      } else if (c->verdict == dynamics::RunVerdict::kAllChatter) {
        p.chatter_m.push_back({p.depth_low_m, p.depth_high_m});
      }
    }
    d.measured.push_back(p);
  }
  for (const CutSummary* up : cuts) {
    if (!up->bifurcation_ok || up->profile != dynamics::DepthProfile::kIncline ||
        !up->bifurcation_depth_m) {
      continue;
    }
    for (const CutSummary* down : cuts) {
      if (!down->bifurcation_ok || down->profile != dynamics::DepthProfile::kDecline ||
          !down->bifurcation_depth_m ||
          std::abs(down->spindle_rpm - up->spindle_rpm) > 1e-3 * up->spindle_rpm) {
        continue;
      }
      d.hysteresis.push_back({up->spindle_rpm, up->id, down->id, *up->bifurcation_depth_m,
                              *down->bifurcation_depth_m});
    }
  }
  for (const auto& p : d.measured) d.measured_rpm.push_back(p.spindle_rpm);
  std::sort(d.measured_rpm.begin(), d.measured_rpm.end());
  d.measured_rpm.erase(std::unique(d.measured_rpm.begin(), d.measured_rpm.end()),
                       d.measured_rpm.end());
}

namespace {

// Speeds of a diagram: half the slowest to 1.5 times the fastest measured cut; without cuts,
// 0.2 to 1.5 times the speed whose tooth-passing frequency is the dominant mode's.
std::vector<double> speed_grid(const LobeDiagram& d, const lobes::LobesInput& in) {
  double lo = 0, hi = 0;
  if (!d.measured_rpm.empty()) {
    lo = 0.5 * d.measured_rpm.front();
    hi = 1.5 * d.measured_rpm.back();
  } else {
    double fn = 0.0, peak = -1.0;
    for (const auto* modes : {&in.x_modes, &in.y_modes}) {
      for (const auto& m : *modes) {
        const double r = 1.0 / std::max(m.c_kg_s * std::sqrt(m.k_N_m / m.m_kg), 1e-300);
        if (r > peak) {
          peak = r;
          fn = natural_frequency_hz(m);
        }
      }
    }
    const double rpm0 = 60.0 * fn / in.teeth;
    lo = 0.2 * rpm0;
    hi = 1.5 * rpm0;
  }
  std::vector<double> v(kCampaignLobeSpeeds);
  for (int i = 0; i < kCampaignLobeSpeeds; ++i) {
    v[static_cast<std::size_t>(i)] = lo + (hi - lo) * i / (kCampaignLobeSpeeds - 1);
  }
  return v;
}

void compute(LobeSource& s, const LobeDiagram& d, int jobs, bool zoa) {
  s.input.max_depth_m = d.max_depth_m;
  s.input.spindle_rpm = speed_grid(d, s.input);
  const lobes::SemiDiscretizationOptions o = semi_discretization_options(s.input, 0, jobs);
  s.steps_per_tooth = o.steps_per_tooth;
  s.sd = lobes::semi_discretization(s.input, o);
  if (zoa) s.zoa = lobes::zero_order(s.input);
  if (!d.measured_rpm.empty()) {
    lobes::LobesInput at = s.input;
    at.spindle_rpm = d.measured_rpm;
    s.at_measured = lobes::semi_discretization(at, o);
  }
}

// Computes a source and adds it to the diagram; values the lobes cannot take (an identified
// damping below zero, a mode with a NaN) leave a note naming the source instead, and the other
// sources are drawn.
void add_source(LobeSource s, LobeDiagram& d, int jobs, bool zoa) {
  try {
    compute(s, d, jobs, zoa);
  } catch (const InputError& e) {
    d.notes.push_back(s.label + ": lobes not drawn: " + e.what());
    return;
  }
  d.sources.push_back(std::move(s));
}

std::optional<double> limit_at(const LobeSource& s, double rpm) {
  for (const auto& r : s.at_measured.speeds) {
    if (r.spindle_rpm == rpm) return r.limit_depth_m;
  }
  return std::nullopt;
}

std::string figure_key(const LobeDiagram& d) { return "lobes:" + d.slug; }

}  // namespace

bool LobesGroup::applies(const CampaignSpec& c) const {
  if (!c.tool) return false;
  bool tap = false, coefficients = false;
  for (const auto& t : c.tests) {
    tap = tap || t.kind == "tap";
    coefficients = coefficients || t.kind == "dyno-slot" || t.kind == "cut";
  }
  return tap && coefficients;
}

std::vector<Need> LobesGroup::needs(const CampaignSpec&) const {
  return {{value::kHammerModesX, false},
          {value::kHammerModesY, false},
          {value::kCuttingCoefficients, false},
          {value::kCutSummary, false}};
}

void LobesGroup::run(const CampaignValues& in, const RunContext& ctx, GroupOutcome& out) const {
  const CampaignSpec& c = *ctx.campaign;
  auto result = std::make_unique<LobesGroupResult>();
  std::vector<const CutSummary*> cuts;
  for (const auto& [id, s] : in.all<CutSummary>(value::kCutSummary)) {
    cuts.push_back(s);
    out.members.push_back(id);
  }
  const ToolSpec& tool = *c.tool;
  if (tool.teeth < 1 || tool.teeth > milling::kMaxTeeth || !(tool.radius_m > 0)) {
    out.result = std::move(result);
    out.status.fail("campaign.yaml tool: teeth must be 1.." + std::to_string(milling::kMaxTeeth) +
                    " and radius_mm > 0 for stability lobes");
    return;
  }
  // The conditions: each (operation, immersion) of the cut tests; without cut tests, a slot.
  std::vector<std::pair<milling::Operation, double>> conditions;
  for (const CutSummary* s : cuts) {
    bool seen = false;
    for (const auto& [op, ri] : conditions) seen = seen || same_condition(*s, op, ri);
    if (!seen) conditions.emplace_back(s->operation, s->radial_immersion_m);
  }
  if (conditions.empty()) {
    conditions.emplace_back(milling::Operation::kUpMilling, 2.0 * tool.radius_m);
  }

  std::string hx_src, hy_src;
  const auto* modes_x = in.first<std::vector<frf::Mode>>(value::kHammerModesX, &hx_src);
  const auto* modes_y = in.first<std::vector<frf::Mode>>(value::kHammerModesY, &hy_src);
  const auto* dyno = in.first<milling::CuttingCoefficients>(value::kCuttingCoefficients);

  for (const auto& [op, immersion] : conditions) {
    LobeDiagram d;
    d.operation = op;
    d.radial_immersion_m = immersion;
    // Figure names: unique per diagram even for immersions that print alike.
    d.slug = std::string(op == milling::Operation::kDownMilling ? "down" : "up") + "-" +
             fmt_sig(immersion * kMToMm, 4) + "mm";
    for (const auto& other : result->diagrams) {
      if (other.slug == d.slug) {
        d.slug += "-" + std::to_string(result->diagrams.size() + 1);
        break;
      }
    }
    std::vector<const CutSummary*> here;
    for (const CutSummary* s : cuts) {
      if (same_condition(*s, op, immersion)) here.push_back(s);
    }
    add_measured_points(here, d);
    double deepest = 0.0;
    for (const auto& p : d.measured) deepest = std::max(deepest, p.depth_high_m);
    // Depths searched: twice the deepest measured cut, at least 10 mm (docs/lobes.md).
    d.max_depth_m = std::max(2.0 * deepest, 10e-3);

    lobes::LobesInput base;
    base.teeth = tool.teeth;
    base.radius_m = tool.radius_m;
    base.operation = op;
    base.radial_immersion_m = std::min(immersion, 2.0 * tool.radius_m);
    if (immersion > 2.0 * tool.radius_m) {
      d.notes.push_back("radial immersion " + fmt_sig(immersion * kMToMm, 4) +
                        " mm is more than the tool diameter: drawn as a slot");
    }
    if (modes_x && dyno) {
      LobeSource s;
      s.key = "hammer-dyno";
      s.label = "hammer + dynamometer";
      s.input = base;
      s.input.x_modes = as_modal(*modes_x);
      s.input.y_modes = as_modal(modes_y ? *modes_y : *modes_x);
      s.input.Kt_N_m2.assign(static_cast<std::size_t>(tool.teeth), dyno->Kt_N_m2);
      s.input.Kr_N_m2.assign(static_cast<std::size_t>(tool.teeth), dyno->Kr_N_m2);
      s.note = "modes of " + hx_src + " (" + modes_note(*modes_x) + ") on x and " +
               (modes_y ? hy_src + " (" + modes_note(*modes_y) + ")"
                        : std::string("the same on y (no tap test of y)")) +
               "; Ktc, Krc of the dyno-slot group on every tooth (edge terms do not enter the "
               "linear model)";
      add_source(std::move(s), d, ctx.jobs, true);
    } else {
      d.notes.push_back(
          "hammer + dynamometer lobes not drawn: " +
          std::string(!modes_x ? in.why_missing(value::kHammerModesX, "the hammer-test modes of x")
                               : in.why_missing(value::kCuttingCoefficients,
                                                "the dynamometer cutting coefficients")));
    }
    for (const CutSummary* cs : cuts) {
      if (!same_condition(*cs, op, immersion)) continue;
      if (!cs->identified) continue;
      if (static_cast<int>(cs->Kt_N_m2.size()) != tool.teeth) {
        d.notes.push_back("identified, " + cs->id +
                          ": lobes not drawn: " + std::to_string(cs->Kt_N_m2.size()) +
                          " coefficient pairs for a " + std::to_string(tool.teeth) + "-tooth tool");
        continue;
      }
      LobeSource s;
      s.key = "identified:" + cs->id;
      s.label = "identified, " + cs->id;
      s.input = base;
      s.input.x_modes = {cs->modal};
      s.input.y_modes = {cs->modal};
      s.input.Kt_N_m2 = cs->Kt_N_m2;
      s.input.Kr_N_m2 = cs->Kr_N_m2;
      s.note =
          "m, c, k (x and y) and per-tooth Kt, Kr identified from " + cs->id + " (000 sec. 5.1)";
      add_source(std::move(s), d, ctx.jobs, false);
    }
    if (d.sources.empty() && d.notes.empty()) {
      d.notes.push_back("no identified set at this condition");
    }
    result->diagrams.push_back(std::move(d));
  }
  bool any = false;
  std::string why;
  for (const auto& d : result->diagrams) {
    any = any || !d.sources.empty();
    for (const auto& n : d.notes) why += (why.empty() ? "" : "; ") + n;
  }
  out.result = std::move(result);
  if (!any) {
    out.status.fail(
        "no lobes could be drawn: " +
        (why.empty() ? std::string("no modal parameters with cutting coefficients") : why));
    return;
  }
  out.status.succeed();
}

template <class Ar>
void fields(Ar& ar, MeasuredPoint& p) {
  LAYOUT_GUARD(MeasuredPoint, 136);
  ar(p.test, p.spindle_rpm, p.ramp, p.depth_low_m, p.depth_high_m, p.chatter, p.stable_m,
     p.chatter_m, p.bifurcation_depth_m);
}

template <class Ar>
void fields(Ar& ar, Hysteresis& h) {
  LAYOUT_GUARD(Hysteresis, 88);
  ar(h.spindle_rpm, h.incline, h.decline, h.onset_m, h.end_m);
}

template <class Ar>
void fields(Ar& ar, LobeSource& s) {
  LAYOUT_GUARD(LobeSource, 704);
  ar(s.key, s.label, s.note, s.input, s.steps_per_tooth, s.sd, s.zoa, s.at_measured);
}

template <class Ar>
void fields(Ar& ar, LobeDiagram& d) {
  LAYOUT_GUARD(LobeDiagram, 176);
  ar(d.slug, d.operation, d.radial_immersion_m, d.max_depth_m, d.measured_rpm, d.sources,
     d.measured, d.hysteresis, d.notes);
}

template <class Ar>
void fields(Ar& ar, LobesGroupResult& r) {
  LAYOUT_GUARD(LobesGroupResult, 32);
  ar(r.diagrams);
}

std::string LobesGroup::save(const GroupOutcome& out) const {
  return save_result<LobesGroupResult>(out);
}

void LobesGroup::restore(const std::string& bytes, GroupOutcome& out) const {
  restore_result<LobesGroupResult>(bytes, out);
}

json LobesGroup::results(const GroupOutcome& out) const {
  json g;
  g["tests"] = out.members;
  const LobesGroupResult* r = out.result_as<LobesGroupResult>();
  if (!out.status.ok() || r == nullptr) {
    g["status"] = out.failure == Failure::kInternal ? "error" : "skipped";
    g["skip_reason"] = out.status.message;
    return g;
  }
  json diagrams = json::array();
  for (const auto& d : r->diagrams) {
    json dj;
    dj["operation"] = operation_name(d.operation);
    dj["radial_immersion_mm"] = d.radial_immersion_m * kMToMm;
    dj["max_depth_mm"] = d.max_depth_m * kMToMm;
    dj["notes"] = d.notes;
    json sources = json::object();
    for (const auto& s : d.sources) {
      json sj;
      sj["note"] = s.note;
      json mx = json::array(), my = json::array();
      for (const auto* modes : {&s.input.x_modes, &s.input.y_modes}) {
        for (const auto& m : *modes) {
          (modes == &s.input.x_modes ? mx : my)
              .push_back({{"m_kg", m.m_kg},
                          {"c_kg_s", m.c_kg_s},
                          {"k_N_m", m.k_N_m},
                          {"fn_hz", natural_frequency_hz(m)}});
        }
      }
      sj["modes_x"] = mx;
      sj["modes_y"] = my;
      sj["Kt_N_m2"] = s.input.Kt_N_m2;
      sj["Kr_N_m2"] = s.input.Kr_N_m2;
      json methods;
      methods["semi-discretization"] = lobes_method_json(s.sd, true);
      methods["semi-discretization"]["steps_per_tooth"] = s.steps_per_tooth;
      if (s.zoa) methods["zoa"] = lobes_method_json(s.zoa->lobes, false);
      sj["methods"] = methods;
      sources[s.key] = sj;
    }
    dj["sources"] = sources;
    json measured = json::array();
    for (const auto& p : d.measured) {
      json mj;
      mj["test"] = p.test;
      mj["spindle_rpm"] = p.spindle_rpm;
      mj["ramp"] = p.ramp;
      mj["depth_mm"] = {p.depth_low_m * kMToMm, p.depth_high_m * kMToMm};
      if (!p.ramp) {
        mj["state"] = p.chatter ? json(*p.chatter ? "chatter" : "stable") : json(nullptr);
      } else {
        mj["bifurcation_depth_mm"] =
            p.bifurcation_depth_m ? json(*p.bifurcation_depth_m * kMToMm) : json(nullptr);
        mj["state"] = !p.stable_m.empty() && !p.chatter_m.empty() ? json("changes")
                      : !p.stable_m.empty()                       ? json("stable")
                      : !p.chatter_m.empty()                      ? json("chatter")
                                                                  : json(nullptr);
      }
      // What each source predicts at this speed: its limit, and for a constant-depth cut the
      // state it predicts (stable below the limit).
      json pred = json::object();
      for (const auto& s : d.sources) {
        const auto lim = limit_at(s, p.spindle_rpm);
        json pj;
        pj["limit_depth_mm"] = lim ? json(*lim * kMToMm) : json(nullptr);
        if (!p.ramp) {
          const bool chatter = lim && p.depth_low_m >= *lim;
          pj["state"] = chatter ? "chatter" : "stable";
          if (p.chatter) pj["agrees"] = chatter == *p.chatter;
        }
        pred[s.key] = pj;
      }
      mj["predicted"] = pred;
      measured.push_back(mj);
    }
    dj["measured"] = measured;
    json hyst = json::array();
    for (const auto& h : d.hysteresis) {
      hyst.push_back({{"spindle_rpm", h.spindle_rpm},
                      {"incline", h.incline},
                      {"decline", h.decline},
                      {"onset_depth_mm", h.onset_m * kMToMm},
                      {"end_depth_mm", h.end_m * kMToMm},
                      {"band_mm", std::abs(h.onset_m - h.end_m) * kMToMm}});
    }
    dj["hysteresis"] = hyst;
    diagrams.push_back(dj);
  }
  g["diagrams"] = diagrams;
  if (!out.status.warnings.empty()) g["warnings"] = out.status.warnings;
  return g;
}

void LobesGroup::figures(const CampaignResults&, const GroupOutcome& out, FigureJobs& jobs) const {
  if (!out.status.ok()) return;
  for (const auto& d : out.result_of<LobesGroupResult>().diagrams) {
    if (d.sources.empty()) continue;
    std::vector<LobeCurve> curves;
    for (const auto& s : d.sources) {
      curves.push_back({s.label, &s.sd, false, true, s.key == "hammer-dyno"});
      if (s.zoa) curves.push_back({s.label + " (ZOA)", &s.zoa->lobes, true, false, false});
    }
    jobs.add("group:" + name(), figure_key(d), "figures/lobes-" + d.slug,
             lobes_figure(curves, d.measured, d.hysteresis, d.max_depth_m));
  }
}

json LobesGroup::report_section(const CampaignResults&, const GroupOutcome& out,
                                const FigureSet& figures) const {
  json l;
  l["ok"] = out.status.ok();
  l["message"] = out.status.message;
  json diagrams = json::array();
  if (const LobesGroupResult* r = out.status.ok() ? out.result_as<LobesGroupResult>() : nullptr) {
    for (const auto& d : r->diagrams) {
      json dj;
      dj["condition"] = std::string(operation_name(d.operation)) + ", radial immersion " +
                        fmt_sig(d.radial_immersion_m * kMToMm, 4) + " mm";
      dj["figure"] = figures.of("group:" + name(), figure_key(d));
      dj["has_figure"] = !dj["figure"].get<std::string>().empty();
      dj["notes"] = d.notes;
      json sources = json::array();
      for (const auto& s : d.sources) {
        const auto min = lobe_minimum(s.sd);
        sources.push_back({{"label", s.label},
                           {"note", s.note},
                           {"minimum", min ? fmt_sig(min->depth_m * kMToMm, 3) + " mm at " +
                                                 fmt_sig(min->spindle_rpm, 5) + " rpm"
                                           : std::string("stable to ") +
                                                 fmt_sig(d.max_depth_m * kMToMm, 3) + " mm"},
                           {"runtime_s", fmt_sig(s.sd.runtime_s, 3)}});
      }
      dj["sources"] = sources;
      json rows = json::array();
      for (const auto& p : d.measured) {
        json row;
        row["test"] = p.test;
        row["rpm"] = fmt_sig(p.spindle_rpm, 5);
        row["depth"] = p.ramp ? fmt_sig(p.depth_low_m * kMToMm, 3) + "\u2013" +
                                    fmt_sig(p.depth_high_m * kMToMm, 3) + " mm"
                              : fmt_sig(p.depth_low_m * kMToMm, 3) + " mm";
        std::string measured = "not determined";
        if (!p.ramp && p.chatter) measured = *p.chatter ? "chatter" : "stable";
        if (p.ramp && p.bifurcation_depth_m) {
          measured = "bifurcation at " + fmt_sig(*p.bifurcation_depth_m * kMToMm, 3) + " mm";
        } else if (p.ramp && !p.stable_m.empty()) {
          measured = "stable throughout";
        } else if (p.ramp && !p.chatter_m.empty()) {
          measured = "chatter throughout";
        }
        row["measured"] = measured;
        std::string predicted;
        for (const auto& s : d.sources) {
          const auto lim = limit_at(s, p.spindle_rpm);
          predicted += (predicted.empty() ? "" : "; ") + s.label + ": " +
                       (lim ? fmt_sig(*lim * kMToMm, 3) + " mm" : std::string("none"));
        }
        row["predicted"] = predicted;
        rows.push_back(row);
      }
      dj["measured"] = rows;
      dj["has_measured"] = !rows.empty();
      json hyst = json::array();
      for (const auto& h : d.hysteresis) {
        hyst.push_back({{"rpm", fmt_sig(h.spindle_rpm, 5)},
                        {"incline", h.incline},
                        {"decline", h.decline},
                        {"onset", fmt_sig(h.onset_m * kMToMm, 3)},
                        {"end", fmt_sig(h.end_m * kMToMm, 3)},
                        {"band", fmt_sig(std::abs(h.onset_m - h.end_m) * kMToMm, 3)}});
      }
      dj["hysteresis"] = hyst;
      dj["has_hysteresis"] = !hyst.empty();
      diagrams.push_back(dj);
    }
  }
  l["diagrams"] = diagrams;
  return {{"toc", json::array({{{"anchor", "lobes"}, {"title", "Stability lobes"}}})},
          {"lobes", l}};
}

}  // namespace chatterlab::app
