#include "app/kinds/dyno_slot/dyno_slot_kind.h"

#include <cmath>

#include "analysis/common/constants.h"
#include "app/core/archive_analysis.h"
#include "app/core/format.h"
#include "app/core/signals.h"
#include "app/core/yaml_reader.h"
#include "app/kinds/common/conditions.h"
#include "app/kinds/dyno_slot/dyno_slot_synth.h"
#include "app/pipeline/cached_result.h"
#include "app/pipeline/pipeline.h"
#include "app/report/figure_jobs.h"
#include "app/report/results_json.h"
#include "app/report/truth.h"
#include "app/synth/synth.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

const char* mean_force_model_name(cutting::SlotMeanForceModel m) {
  return m == cutting::SlotMeanForceModel::kSingleToothChip ? "single-tooth-chip"
                                                            : "dissertation-eq-3.5";
}

json options_json(const cutting::DynoOptions& o) {
  return {{"mean_force_model", mean_force_model_name(o.mean_force_model)},
          {"zero_threshold_V", o.zero_threshold_V},
          {"zero_hysteresis_V", o.zero_hysteresis_V},
          {"rpm_tolerance", o.rpm_tolerance},
          {"min_revolutions", o.min_revolutions},
          {"min_samples_per_revolution", o.min_samples_per_revolution}};
}

json dyno_json(const DynoRecordOutcome& d) {
  const auto& r = d.result;
  return {{"feed_per_tooth_m", d.feed_per_tooth_m},
          {"axial_depth_m", d.axial_depth_m},
          {"spindle_rpm", d.spindle_rpm},
          {"measured_rpm", number_or_null(r.measured_rpm)},
          {"revolutions", r.revolutions},
          {"theta_dyn_deg", number_or_null(r.theta_dyn_rad * kRadToDeg)},
          {"mean_Ft_N", number_or_null(r.mean_Ft_N)},
          {"mean_Fr_N", number_or_null(r.mean_Fr_N)},
          {"spread_Ft_N", number_or_null(r.spread_Ft_N)},
          {"spread_Fr_N", number_or_null(r.spread_Fr_N)},
          {"offset_x_N", number_or_null(r.offset_x_N)},
          {"offset_y_N", number_or_null(r.offset_y_N)},
          {"switching_contrast", number_or_null(r.switching_contrast)}};
}

json line_json(const cutting::FittedLine& l) {
  return {{"slope_N_m2", number_or_null(l.slope_N_per_m2)},
          {"intercept_N_m", number_or_null(l.intercept_N_per_m)},
          {"rms_residual_N", number_or_null(l.rms_residual_N)},
          {"r_squared", number_or_null(l.r_squared)}};
}

json dyno_context(const CampaignResults& r, const GroupOutcome& out, const std::string& figure) {
  const DynoGroupResult* gr = out.result_as<DynoGroupResult>();
  json d;
  json records = json::array();
  for (const auto& t : r.tests) {
    const auto* rec = t.status.ok() ? t.result_as<DynoRecordOutcome>() : nullptr;
    if (!rec) continue;
    const auto& res = rec->result;
    records.push_back({{"id", t.spec->id},
                       {"feed_mm", fmt_sig(rec->feed_per_tooth_m * 1e3, 3)},
                       {"depth_mm", fmt_sig(rec->axial_depth_m * 1e3, 3)},
                       {"rpm", fmt_sig(rec->spindle_rpm, 5)},
                       {"revolutions", res.revolutions},
                       {"theta_dyn_deg", fmt_fixed(res.theta_dyn_rad * kRadToDeg, 2)},
                       {"mean_Ft_N", fmt_sig(res.mean_Ft_N, 4)},
                       {"mean_Fr_N", fmt_sig(res.mean_Fr_N, 4)}});
  }
  d["has_records"] = !records.empty();
  d["records"] = records;
  static const DynoGroupResult kNone;
  const DynoGroupResult& g = gr ? *gr : kNone;
  d["fit_ok"] = out.status.ok();
  d["fit_message"] = out.status.message;
  d["figure"] = figure;
  d["toc"] = json::array({{{"anchor", "dyno"}, {"title", "Dynamometer slot cuts"}}});
  const auto& k = g.fit.coefficients;
  d["Ktc_e8"] = fmt_fixed(k.Kt_N_m2 / 1e8, 2);
  d["Kte_e3"] = fmt_sig(k.Kte_N_m / 1e3, 3);
  d["Krc_e8"] = fmt_fixed(k.Kr_N_m2 / 1e8, 2);
  d["Kre_e3"] = fmt_sig(k.Kre_N_m / 1e3, 3);
  d["rms_t_N"] = fmt_sig(g.fit.tangential.rms_residual_N, 3);
  d["rms_r_N"] = fmt_sig(g.fit.radial.rms_residual_N, 3);
  d["r2_t"] = fmt_fixed(g.fit.tangential.r_squared, 4);
  d["r2_r"] = fmt_fixed(g.fit.radial.r_squared, 4);
  std::string tool =
      r.campaign.workpiece.empty() ? std::string("workpiece not given") : r.campaign.workpiece;
  if (r.campaign.tool) {
    tool += " / " + std::to_string(r.campaign.tool->teeth) +
            "-tooth, r = " + fmt_sig(r.campaign.tool->radius_m * 1e3, 3) + " mm";
    if (r.campaign.tool->helix_deg)
      tool += ", " + fmt_sig(*r.campaign.tool->helix_deg, 3) + "-deg helix";
  }
  d["tool_label"] = tool;
  d["convention_note"] =
      g.fit.mean_force_model == cutting::SlotMeanForceModel::kSingleToothChip
          ? "Coefficients use mean |F| = (2/\u03c0) b K<sub>c</sub> h + b K<sub>e</sub>, which "
            "agrees "
            "with the force model of eqs 3.3\u20133.4 (one tooth cutting a chip h sin \u03b8 at a "
            "time); 000 eq. 3.5 as printed gives half these K<sub>tc</sub>, K<sub>rc</sub> "
            "(docs/dyno-coefficients.md)."
          : "Coefficients use 000 eqs 3.5 and 3.9\u20133.12 as printed (mean |F| = (4/\u03c0) b "
            "K<sub>c</sub> h + b K<sub>e</sub>); the force model of eqs 3.3\u20133.4 implies twice "
            "these K<sub>tc</sub>, K<sub>rc</sub> (docs/dyno-coefficients.md).";
  return d;
}

}  // namespace

std::vector<std::string> DynoSlotKind::keys() const {
  return {"spindle_rpm", "feed_per_tooth_mm", "axial_depth_mm"};
}

std::shared_ptr<const KindSpec> DynoSlotKind::parse(const YAML::Node& root, YamlReader& r) const {
  auto s = std::make_shared<DynoSlotSpec>();
  read_speed_and_feed(root, r, &s->spindle_rpm, &s->feed_per_tooth_m);
  s->axial_depth_m = r.required_double(root, "axial_depth_mm") * kMm;
  if (s->axial_depth_m <= 0) r.error("axial_depth_mm", "must be > 0");
  return s;
}

std::vector<std::string> DynoSlotKind::check_campaign(const CampaignSpec& c,
                                                      const TestSpec& t) const {
  if (auto e = needs_tool(c, t)) return {*e};
  return {};
}

std::vector<std::string> DynoSlotKind::provides(const TestSpec&) const {
  return {value::kDynoSlotRecord};
}

void DynoSlotKind::run(const TestSpec& t, const CampaignValues&, const RunContext&,
                       TestOutcome& out) const {
  const DynoSlotSpec& spec = t.kind_spec<DynoSlotSpec>();
  const SignalTable table = SignalTable::open(t.data, t.data_label());
  const Eigen::VectorXd fx = table.channel("Fx", t.channel("Fx"));
  const Eigen::VectorXd fy = table.channel("Fy", t.channel("Fy"));
  const ChannelSpec zero_cal = t.channel("zero");
  const Eigen::VectorXd zero = table.channel("zero", zero_cal);
  cutting::DynoOptions opt = options_;
  if (zero_cal.threshold) opt.zero_threshold_V = *zero_cal.threshold;
  auto d = std::make_unique<DynoRecordOutcome>();
  d->id = t.id;
  d->feed_per_tooth_m = spec.feed_per_tooth_m;
  d->axial_depth_m = spec.axial_depth_m;
  d->spindle_rpm = spec.spindle_rpm;
  d->result = cutting::analyse_slot_record(fx, fy, zero, t.sample_rate_hz, spec.spindle_rpm, opt);
  out.warnings.insert(out.warnings.end(), d->result.summary.warnings.begin(),
                      d->result.summary.warnings.end());
  if (!d->result.summary.ok()) {
    out.status.fail(t.data_label() + ": " + d->result.summary.message);
    return;
  }
  out.result = std::move(d);
  out.status.succeed();
}

template <class Ar>
void fields(Ar& ar, DynoRecordOutcome& d) {
  LAYOUT_GUARD(DynoRecordOutcome, 288);
  ar(d.id, d.feed_per_tooth_m, d.axial_depth_m, d.spindle_rpm, d.result);
}

template <class Ar>
void fields(Ar& ar, DynoGroupResult& g) {
  LAYOUT_GUARD(DynoGroupResult, 240);
  ar(g.records, g.fit);
}

std::string DynoSlotKind::save(const TestOutcome& out) const {
  return save_result<DynoRecordOutcome>(out);
}

void DynoSlotKind::restore(const TestSpec&, const std::string& bytes, TestOutcome& out) const {
  restore_result<DynoRecordOutcome>(bytes, out);
}

void DynoSlotKind::publish(const TestOutcome& out, CampaignValues& values) const {
  values.put(value::kDynoSlotRecord, out.spec->id, out.result_of<DynoRecordOutcome>());
}

json DynoSlotKind::results(const TestOutcome& out) const {
  return dyno_json(out.result_of<DynoRecordOutcome>());
}

json DynoSlotKind::settings(const CampaignSpec&) const { return options_json(options_); }

std::string DynoSlotKind::note(const TestOutcome& out) const {
  return "theta_dyn " +
         fmt_fixed(out.result_of<DynoRecordOutcome>().result.theta_dyn_rad * kRadToDeg, 2) + " deg";
}

bool DynoSlotGroup::applies(const CampaignSpec& c) const {
  for (const auto& t : c.tests) {
    if (t.kind == "dyno-slot") return true;
  }
  return false;
}

// Optional: with fewer than two records the fit itself says how many were analysed.
std::vector<Need> DynoSlotGroup::needs(const CampaignSpec&) const {
  return {{value::kDynoSlotRecord, false}};
}

std::vector<std::string> DynoSlotGroup::provides(const CampaignSpec&) const {
  return {value::kCuttingCoefficients};
}

void DynoSlotGroup::run(const CampaignValues& in, const RunContext& ctx, GroupOutcome& out) const {
  const CampaignSpec& c = *ctx.campaign;
  auto g = std::make_unique<DynoGroupResult>();
  int members = 0;
  for (const auto& t : c.tests) members += t.kind == "dyno-slot";
  std::vector<double> feeds, ft, fr, depth;
  for (const auto& [id, rec] : in.all<DynoRecordOutcome>(value::kDynoSlotRecord)) {
    out.members.push_back(id);
    g->records.push_back(*rec);
    feeds.push_back(rec->feed_per_tooth_m);
    ft.push_back(rec->result.mean_Ft_N);
    fr.push_back(rec->result.mean_Fr_N);
    depth.push_back(rec->axial_depth_m);
  }
  out.result = std::move(g);
  if (c.tool && c.tool->teeth != 2) {
    out.status.fail(
        "the slot method of 000 sec. 3.2 assumes a two-tooth tool (one tooth cutting "
        "at a time); campaign.yaml tool.teeth = " +
        std::to_string(c.tool->teeth));
    return;
  }
  if (feeds.size() < 2) {
    out.status.fail(std::to_string(feeds.size()) + " of " + std::to_string(members) +
                    " dyno-slot records analysed: a line fit needs at least two feeds");
    return;
  }
  const auto map = [](const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  };
  auto* result = static_cast<DynoGroupResult*>(out.result.get());
  result->fit = cutting::fit_slot_coefficients(map(feeds), map(ft), map(fr), map(depth), options_);
  out.status = result->fit.summary;
}

void DynoSlotGroup::publish(const GroupOutcome& out, CampaignValues& values) const {
  values.put(value::kCuttingCoefficients, "group:" + name(),
             out.result_of<DynoGroupResult>().fit.coefficients);
}

std::string DynoSlotGroup::save(const GroupOutcome& out) const {
  return save_result<DynoGroupResult>(out);
}

void DynoSlotGroup::restore(const std::string& bytes, GroupOutcome& out) const {
  restore_result<DynoGroupResult>(bytes, out);
}

json DynoSlotGroup::results(const GroupOutcome& out) const {
  json d;
  d["tests"] = out.members;
  const DynoGroupResult* g = out.result_as<DynoGroupResult>();
  if (out.status.ok() && g) {
    const auto& k = g->fit.coefficients;
    d["Ktc_N_m2"] = k.Kt_N_m2;
    d["Kte_N_m"] = k.Kte_N_m;
    d["Krc_N_m2"] = k.Kr_N_m2;
    d["Kre_N_m"] = k.Kre_N_m;
    d["mean_force_model"] = mean_force_model_name(g->fit.mean_force_model);
    d["tangential_fit"] = line_json(g->fit.tangential);
    d["radial_fit"] = line_json(g->fit.radial);
    if (!out.status.warnings.empty()) d["warnings"] = out.status.warnings;
  } else {
    d["status"] = out.failure == Failure::kInternal ? "error" : "skipped";
    d["skip_reason"] = out.status.message;
  }
  return d;
}

json DynoSlotGroup::settings(const CampaignSpec&) const { return options_json(options_); }

void DynoSlotGroup::figures(const CampaignResults&, const GroupOutcome& out,
                            FigureJobs& jobs) const {
  if (!out.status.ok()) return;
  jobs.add("group:" + name(), "force", "figures/dyno-force-vs-feed",
           dyno_force_figure(out.result_of<DynoGroupResult>()));
}

json DynoSlotGroup::report_section(const CampaignResults& r, const GroupOutcome& out,
                                   const FigureSet& figures) const {
  json d = dyno_context(r, out, figures.of("group:" + name(), "force"));
  json section = {{"toc", d["toc"]}, {"dyno", d}};
  return section;
}

// The group is matched by its members' common prefix ("dyno/").
void DynoSlotGroup::compare_truth(const TruthInput& in, const std::string& key,
                                  const GroupOutcome& out, TruthComparison& c) const {
  const DynoGroupResult* g = out.result_as<DynoGroupResult>();
  if (!out.status.ok() || !g || out.members.empty() || out.members.front().rfind(key, 0) != 0) {
    return;
  }
  const YAML::Node& v = *in.entry;
  const auto& k = g->fit.coefficients;
  add_truth_row(c, "Ktc_N_m2", key, truth_number(v, "Ktc_N_m2"), k.Kt_N_m2);
  add_truth_row(c, "Kte_N_m", key, truth_number(v, "Kte_N_m"), k.Kte_N_m);
  add_truth_row(c, "Krc_N_m2", key, truth_number(v, "Krc_N_m2"), k.Kr_N_m2);
  add_truth_row(c, "Kre_N_m", key, truth_number(v, "Kre_N_m"), k.Kre_N_m);
  const double th = truth_number(v, "theta_dyn_deg");
  if (!std::isfinite(th)) return;
  for (const auto& rec : g->records) {
    if (rec.id.rfind(key, 0) != 0) continue;
    // theta_dyn is defined modulo pi: compare on the representative nearest the truth.
    const double est = rec.result.theta_dyn_rad * kRadToDeg;
    add_truth_row(c, "theta_dyn_deg", rec.id, th, est + 180.0 * std::round((th - est) / 180.0));
  }
}

render::Figure dyno_force_figure(const DynoGroupResult& g) {
  // Per unit depth when the records' depths differ, else in newtons at the common depth.
  double depth = -1;
  bool same_depth = true;
  for (const auto& rec : g.records) {
    if (depth < 0) depth = rec.axial_depth_m;
    same_depth = same_depth && std::abs(rec.axial_depth_m - depth) < 1e-12;
  }
  const double scale_depth = same_depth ? depth : 1e-3;  // N, or N per mm of depth
  render::Series ft, fr, lt, lr;
  ft.label = "tangential, measured";
  fr.label = "radial, measured";
  ft.style = fr.style = render::SeriesStyle::kPoints;
  lt.label = "tangential, fit";
  lr.label = "radial, fit";
  ft.color = lt.color = "#0072B2";
  fr.color = lr.color = "#D55E00";
  lt.style = lr.style = render::SeriesStyle::kDashedLine;
  double hmax = 0;
  for (const auto& rec : g.records) {
    const double h_mm = rec.feed_per_tooth_m * 1e3;
    const double s = scale_depth / rec.axial_depth_m;
    ft.x.push_back(h_mm);
    ft.y.push_back(rec.result.mean_Ft_N * s);
    fr.x.push_back(h_mm);
    fr.y.push_back(rec.result.mean_Fr_N * s);
    hmax = std::max(hmax, h_mm);
  }
  for (int i = 0; i <= 20; ++i) {
    const double h_mm = hmax * 1.1 * i / 20.0;
    lt.x.push_back(h_mm);
    lt.y.push_back(g.fit.tangential.force_N(h_mm * 1e-3, scale_depth));
    lr.x.push_back(h_mm);
    lr.y.push_back(g.fit.radial.force_N(h_mm * 1e-3, scale_depth));
  }
  render::Figure fig;
  fig.height_in = 3.4;
  render::Axes& a = fig.panels.emplace_back();
  a.x_label = "feed per tooth [mm]";
  a.y_label = same_depth ? "average force magnitude [N]" : "average force per depth [N/mm]";
  a.x_range = render::Range{0, hmax * 1.1};
  a.legend = render::LegendPosition::kTopLeft;
  a.series = {ft, fr, lt, lr};
  return fig;
}

std::shared_ptr<const KindSpec> DynoSlotKind::parse_synth(const YAML::Node& section,
                                                          const SynthContext& ctx,
                                                          YamlReader& r) const {
  if (!ctx.tool_given) r.error("tool", "is required by the spec's `dyno` section");
  return std::make_shared<DynoSynthSpec>(read_dyno_synth(section, r));
}

int DynoSlotKind::write_synth(const KindSpec& section, SynthContext& ctx) const {
  return write_dyno_tests(dynamic_cast<const DynoSynthSpec&>(section), ctx);
}

}  // namespace chatterlab::app
