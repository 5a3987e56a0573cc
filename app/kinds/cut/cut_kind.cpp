#include "app/kinds/cut/cut_kind.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "app/core/archive_analysis.h"
#include "app/core/yaml_reader.h"
#include "app/kinds/common/conditions.h"
#include "app/kinds/cut/cut_synth.h"
#include "app/pipeline/cached_result.h"
#include "app/synth/synth.h"

namespace chatterlab::app {
namespace {

// campaign.yaml estimation: bounds stated in docs/format/campaign.md ("What the reader refuses").
constexpr long kMaxPasses = 100;      // identification passes (the default settles in a few)
constexpr long kMaxRepeatRuns = 100;  // repeatability runs, each a whole estimation (default 10)

}  // namespace

using nlohmann::json;

std::vector<std::string> CutKind::keys() const {
  return {"operation",           "spindle_rpm",    "feed_per_tooth_mm",
          "radial_immersion_mm", "axial_depth_mm", "cut_window_s",
          "air_window_s",        "sensor_to_tip",  "estimation_window_s"};
}

std::shared_ptr<const KindSpec> CutKind::parse(const YAML::Node& root, YamlReader& r) const {
  auto spec = std::make_shared<CutSpec>();
  CutSpec& s = *spec;
  s.operation = r.required_string(root, "operation");
  if (!s.operation.empty() && s.operation != "up-milling" && s.operation != "down-milling") {
    r.error("operation", "must be up-milling or down-milling, got '" + s.operation + "'");
  }
  read_speed_and_feed(root, r, &s.spindle_rpm, &s.feed_per_tooth_m);
  s.radial_immersion_m = r.required_double(root, "radial_immersion_mm") * kMm;
  if (s.radial_immersion_m <= 0) r.error("radial_immersion_mm", "must be > 0");
  if (auto d = r.optional_number_or_pair(root, "axial_depth_mm")) {
    s.axial_depth_m = {d->first * kMm, d->second * kMm};
    if (d->first < 0 || d->second < 0) r.error("axial_depth_mm", "must be >= 0");
  } else if (!root["axial_depth_mm"]) {
    r.error("axial_depth_mm", "is missing");
  }
  // The windows: finite, end > start here; inside the record in check_record, which `validate`
  // and `report` both run (pipeline check_signals).
  const auto window = [&](const char* key) -> std::optional<std::pair<double, double>> {
    const auto w = r.optional_pair(root, key);
    if (!w) return std::nullopt;
    if (!std::isfinite(w->first) || !std::isfinite(w->second)) {
      r.error(key, "must be two finite numbers [start, end], got [" + window_text(w->first) + ", " +
                       window_text(w->second) + "]");
    } else if (!(w->second > w->first)) {
      r.error(key, "must be [start, end] with end > start, got [" + window_text(w->first) + ", " +
                       window_text(w->second) + "]");
    }
    return w;
  };
  if (auto w = window("cut_window_s")) {
    s.cut_window_s = *w;
  } else if (!root["cut_window_s"]) {
    r.error("cut_window_s", "is missing");
  }
  s.air_window_s = window("air_window_s");
  s.sensor_to_tip = r.optional_double(root, "sensor_to_tip").value_or(1.0);
  if (!(s.sensor_to_tip > 0)) r.error("sensor_to_tip", "must be > 0");
  s.estimation_window_s = window("estimation_window_s");
  if (s.estimation_window_s) {
    const auto& [a, b] = *s.estimation_window_s;
    if (!(b > a) || a < s.cut_window_s.first || b > s.cut_window_s.second) {
      r.error("estimation_window_s", "must be [start, end] with end > start inside cut_window_s");
    }
  }
  return spec;
}

// campaign.yaml `estimation:` (docs/formats.md): every key optional.
std::shared_ptr<const KindSpec> CutKind::parse_campaign_block(const std::string&,
                                                              const YAML::Node& e,
                                                              YamlReader& r) const {
  auto block = std::make_shared<EstimationBlock>();
  EstimationOptions& o = block->options;
  if (!e) return block;
  if (!e.IsMap()) {
    r.error("estimation", "must be a mapping (docs/formats.md)");
    return block;
  }
  r.check_keys(e,
               {"window_s", "resample_step_s", "settle_revolutions", "max_passes", "repeat_runs",
                "repeat_spread", "seed"},
               "estimation");
  const auto positive = [&](const char* key, double& into) {
    if (const auto v = r.optional_double(e, key, "estimation")) {
      if (*v > 0 && std::isfinite(*v)) {
        into = *v;
      } else {
        r.error(std::string("estimation.") + key, "must be > 0");
      }
    }
  };
  const auto whole = [&](const char* key, double lowest) -> std::optional<double> {
    const auto v = r.optional_double(e, key, "estimation");
    if (v && !(*v >= lowest && *v == std::floor(*v) && *v < 1e9)) {
      r.error(std::string("estimation.") + key,
              "must be a whole number >= " + std::to_string(static_cast<int>(lowest)));
      return std::nullopt;
    }
    return v;
  };
  positive("window_s", o.window_s);
  positive("resample_step_s", o.resample_step_s);
  if (const auto v = r.optional_double(e, "settle_revolutions", "estimation")) {
    if (*v >= 0 && std::isfinite(*v)) {
      o.settle_revolutions = *v;
    } else {
      r.error("estimation.settle_revolutions", "must be >= 0");
    }
  }
  if (const auto v = r.optional_int(e, "max_passes", "estimation", 1, kMaxPasses)) {
    o.max_passes = static_cast<int>(*v);
  }
  if (const auto v = r.optional_double(e, "repeat_runs", "estimation")) {
    // Each run repeats the whole estimation: bounded so that a typo cannot hang the report.
    if (*v == 0 || (*v >= 2 && *v == std::floor(*v) && *v <= kMaxRepeatRuns)) {
      o.repeat.runs = static_cast<int>(*v);
    } else {
      r.error("estimation.repeat_runs",
              "must be 0 (no repeatability runs) or a whole number >= 2 (at most " +
                  std::to_string(kMaxRepeatRuns) + "), got '" + e["repeat_runs"].Scalar() + "'");
    }
  }
  if (const auto v = r.optional_double(e, "repeat_spread", "estimation")) {
    if (*v > 0 && *v < 1) {
      o.repeat.spread = *v;
    } else {
      r.error("estimation.repeat_spread", "must be in (0, 1)");
    }
  }
  if (const auto v = whole("seed", 0)) o.repeat.seed = static_cast<std::uint64_t>(*v);
  return block;
}

std::vector<std::string> CutKind::check_campaign(const CampaignSpec& c, const TestSpec& t) const {
  if (auto e = needs_tool(c, t)) return {*e};
  return {};
}

std::vector<std::string> CutKind::check_record(const TestSpec& t, double duration_s) const {
  return cut_window_errors(t, duration_s);
}

// Optional needs: without them the tachometer, runout and deflection steps still run and the
// offset and identification steps say what is missing.
std::vector<Need> CutKind::needs(const TestSpec&) const {
  return {{value::kHammerModeX, false},
          {value::kHammerModeY, false},
          {value::kCuttingCoefficients, false}};
}

std::string CutKind::describe_value(const std::string& name) const {
  return name == value::kCutSummary ? "the cut tests' conditions and identified values" : "";
}

template <class Ar>
void fields(Ar& ar, VariantOutcome& v) {
  LAYOUT_GUARD(VariantOutcome, 848);
  ar(v.run, v.observability_status, v.observability, v.repeat, v.known, v.start);
}

template <class Ar>
void fields(Ar& ar, SimulatedBifurcation& b) {
  LAYOUT_GUARD(SimulatedBifurcation, 168);
  ar(b.chip_model, b.status, b.depth_m, b.verdict, b.steps, b.runtime_s);
}

template <class Ar>
void fields(Ar& ar, CutEstimation& e) {
  LAYOUT_GUARD(CutEstimation, 1240);
  ar(e.summary, e.window, e.resampled_samples, e.passes, e.converged, e.modal, e.coefficients,
     e.offset, e.joint, e.variants, e.chip_t_s, e.chip_m, e.simulated, e.runtime_s);
}

template <class Ar>
void fields(Ar& ar, CutOutcome& c) {
  LAYOUT_GUARD(CutOutcome, 2808);
  ar(c.summary, c.warnings, c.tach, c.contour, c.air_revolutions, c.excerpt_t_s, c.excerpt_raw_x_m,
     c.excerpt_x_m, c.offset_status, c.offset, c.offset_measured, c.bifurcation_status, c.ramped,
     c.orbit_status, c.orbit, c.orbit_noise_floor_m, c.depth_n_m, c.x_n_m, c.bifurcation,
     c.poincare, c.detector_noise_m, c.estimation);
}

std::string CutKind::save(const TestOutcome& out) const { return save_result<CutOutcome>(out); }

void CutKind::restore(const TestSpec&, const std::string& bytes, TestOutcome& out) const {
  restore_result<CutOutcome>(bytes, out);
}

void CutKind::publish(const TestOutcome& t, CampaignValues& values) const {
  const CutOutcome& c = t.result_of<CutOutcome>();
  const CutSpec& spec = t.spec->kind_spec<CutSpec>();
  CutSummary s;
  s.id = t.spec->id;
  s.operation = spec.operation == "down-milling" ? milling::Operation::kDownMilling
                                                 : milling::Operation::kUpMilling;
  s.spindle_rpm = spec.spindle_rpm;
  s.radial_immersion_m = spec.radial_immersion_m;
  s.depth_start_m = spec.axial_depth_m.first;
  s.depth_end_m = spec.axial_depth_m.second;
  s.ramped = c.ramped;
  if (!c.ramped && c.orbit_status.ok()) {
    s.chatter = c.orbit.shape != dynamics::OrbitShape::kFixedPoint;
  }
  if (c.ramped && c.bifurcation_status.ok()) {
    s.bifurcation_ok = true;
    s.profile = c.bifurcation.profile;
    s.verdict = c.bifurcation.verdict;
    s.bifurcation_depth_m = c.bifurcation.bifurcation_depth_m;
  }
  if (c.estimation.summary.ok()) {
    // The identified set: the joint estimate when it succeeded (identified_set).
    const IdentifiedSet set = identified_set(c.estimation);
    s.identified = true;
    s.modal = set.modal;
    for (const auto& k : set.coefficients) {
      s.Kt_N_m2.push_back(k.Kt_N_m2);
      s.Kr_N_m2.push_back(k.Kr_N_m2);
    }
  }
  const std::string id = s.id;  // not s.id: s is moved into the call
  values.put(value::kCutSummary, id, std::move(s));
}

const EstimationOptions& estimation_options(const CampaignSpec& c) {
  static const EstimationOptions kDefaults;
  const auto* b = c.block<EstimationBlock>("estimation");
  return b ? b->options : kDefaults;
}

CutStepInputs cut_inputs(const CampaignSpec& c, const CampaignValues& values) {
  CutStepInputs in;
  in.tool = c.tool;
  std::vector<std::string> sources;
  std::string src;
  if (const auto* m = values.first<frf::Mode>(value::kHammerModeX, &src)) {
    in.hammer_x = *m;
    sources.push_back(src);
  }
  if (const auto* m = values.first<frf::Mode>(value::kHammerModeY, &src)) {
    in.hammer_y = *m;
    sources.push_back(src);
  }
  std::sort(sources.begin(), sources.end());
  for (const auto& s : sources) in.hammer_source += (in.hammer_source.empty() ? "" : ", ") + s;
  if (const auto* k = values.first<milling::CuttingCoefficients>(value::kCuttingCoefficients)) {
    in.coefficients = *k;
  }
  return in;
}

void CutKind::run(const TestSpec& t, const CampaignValues& values, const RunContext& ctx,
                  TestOutcome& out) const {
  CutStepOptions options;
  options.estimation = estimation_options(*ctx.campaign);
  options.estimation_errors = ctx.campaign->errors_of_block("estimation");
  options.jobs = ctx.jobs;
  out.adopt(
      std::make_unique<CutOutcome>(run_cut_test(t, cut_inputs(*ctx.campaign, values), options)));
}

// Every estimation setting in force (campaign.yaml `estimation:` or the defaults), with the
// filters' Q, R and P0 diagonals (000 eqs 6.1-6.7).
json CutKind::settings(const CampaignSpec& c) const {
  const EstimationOptions& o = estimation_options(c);
  const auto discretization = [](estimate::Discretization d) {
    return d == estimate::Discretization::kSymplecticEuler ? "symplectic-euler" : "forward-euler";
  };
  const auto& m = o.modal;
  const auto& k = o.coeff;
  return {{"window_s", o.window_s},
          {"resample_step_s", o.resample_step_s},
          {"settle_revolutions", o.settle_revolutions},
          {"max_passes", o.max_passes},
          {"offset_tolerance_deg", o.offset_tolerance_deg},
          {"parameter_tolerance", o.parameter_tolerance},
          {"repeat_runs", o.repeat.runs},
          {"repeat_spread", o.repeat.spread},
          {"seed", o.repeat.seed},
          {"modal_ekf",
           {{"discretization", discretization(m.discretization)},
            {"q_force_N2", m.q_force_N2},
            {"q_mass", m.q_mass},
            {"q_damping", m.q_damping},
            {"q_stiffness", m.q_stiffness},
            {"r_m2", m.r_m2},
            {"p0_deflection_m2", m.p0_deflection_m2},
            {"p0_velocity_m2_s2", m.p0_velocity_m2_s2},
            {"p0_mass_kg2", m.p0_mass_kg2},
            {"p0_damping_kg2_s2", m.p0_damping_kg2_s2},
            {"p0_stiffness_N2_m2", m.p0_stiffness_N2_m2},
            {"history_points", m.history_points}}},
          {"ukf",
           {{"alpha", m.ukf.alpha},
            {"beta", m.ukf.beta},
            {"kappa", m.ukf.kappa},
            {"modal_p0_relative_sd", m.ukf_p0_relative_sd},
            {"repeated", false}}},
          {"coeff_ekf",
           {{"discretization", discretization(k.discretization)},
            {"q_force_N2", k.q_force_N2},
            {"q_Kt", k.q_Kt},
            {"q_Kr", k.q_Kr},
            {"r_m2", k.r_m2},
            {"p0_deflection_m2", k.p0_deflection_m2},
            {"p0_velocity_m2_s2", k.p0_velocity_m2_s2},
            {"p0_Kt", k.p0_Kt},
            {"p0_Kr", k.p0_Kr},
            {"tooth_gate", k.gate == estimate::ToothGate::kNone ? "none" : "engaged"},
            {"history_points", k.history_points}}}};
}

const TestOutcome* identification_source(const CampaignResults& r) {
  const TestOutcome* ramped = nullptr;
  for (const auto& t : r.tests) {
    const CutOutcome* c = t.status.ok() ? t.result_as<CutOutcome>() : nullptr;
    if (!c || !c->estimation.summary.ok()) continue;
    if (!c->ramped) return &t;
    if (!ramped) ramped = &t;
  }
  return ramped;
}

std::shared_ptr<const KindSpec> CutKind::parse_synth(const YAML::Node& section,
                                                     const SynthContext& ctx, YamlReader& r) const {
  if (!ctx.tool_given) r.error("tool", "is required by the spec's `cut` section");
  return std::make_shared<CutSynthSpec>(read_cut_synth(section, ctx, r));
}

int CutKind::write_synth(const KindSpec& section, SynthContext& ctx) const {
  return write_cut_tests(dynamic_cast<const CutSynthSpec&>(section), ctx);
}

}  // namespace chatterlab::app
