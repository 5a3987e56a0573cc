#include "app/kinds/cut/cut_estimation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <map>

#include "analysis/common/cutting_coefficients.h"
#include "analysis/common/modal_parameters.h"
#include "analysis/dynamics/simulated_bifurcation.h"
#include "analysis/estimate/cut_input.h"
#include "analysis/estimate/operating_point.h"
#include "analysis/milling/simulation.h"
#include "app/core/format.h"
#include "app/core/parallel.h"
#include "app/kinds/cut/cut_step.h"

namespace chatterlab::app {
namespace {

estimate::CutSetup setup_of(const TestSpec& t, const ToolSpec& tool) {
  estimate::CutSetup s;
  s.teeth = tool.teeth;
  s.radius_m = tool.radius_m;
  s.spindle_rpm = t.kind_spec<CutSpec>().spindle_rpm;
  s.feed_per_tooth_m = t.kind_spec<CutSpec>().feed_per_tooth_m;
  s.radial_immersion_m = t.kind_spec<CutSpec>().radial_immersion_m;
  s.operation = t.kind_spec<CutSpec>().operation == "down-milling"
                    ? milling::Operation::kDownMilling
                    : milling::Operation::kUpMilling;
  return s;
}

sync::CutSchedule schedule_of(const TestSpec& t) {
  return {t.kind_spec<CutSpec>().cut_window_s.first, t.kind_spec<CutSpec>().cut_window_s.second,
          t.kind_spec<CutSpec>().axial_depth_m.first, t.kind_spec<CutSpec>().axial_depth_m.second};
}

std::string modal_text(const estimate::ModalParameters& m) {
  return "m " + fmt_sig(m.m_kg, 4) + " kg, c " + fmt_sig(m.c_kg_s, 4) + " kg/s, k " +
         fmt_sig(m.k_N_m, 4) + " N/m";
}

std::string coefficients_text(const std::vector<estimate::ToothCoefficients>& k) {
  std::string s;
  for (std::size_t p = 0; p < k.size(); ++p) {
    s += (p ? ", " : "") + std::string("Kt") + std::to_string(p + 1) + " " +
         fmt_sig(k[p].Kt_N_m2, 4) + ", Kr" + std::to_string(p + 1) + " " + fmt_sig(k[p].Kr_N_m2, 4);
  }
  return s + " N/m^2";
}

// The variant's observability rank at the operating sample (000 sec. 4.5, eq. 4.33).
void rank_variant(VariantOutcome& v, const estimate::OperatingSample& op,
                  const std::vector<estimate::ToothCoefficients>& k,
                  const estimate::ModalParameters& identified, double T) {
  try {
    const estimate::OperatingState s = estimate::operating_state(v.run, op, k, identified);
    v.observability = estimate::observability(v.run.id, s.state, s.input, s.held, T);
    v.observability_status.succeed();
  } catch (const std::exception& e) {
    v.observability_status.fail(e.what());
  }
}

void chip_excerpt(const estimate::MeasuredCut& cut, const estimate::CutSetup& s, double t0_s,
                  CutEstimation& out) {
  const estimate::CutChips chips(cut, s);
  const double rev_s = 60.0 / s.spindle_rpm;
  const Eigen::Index first = chips.first_step();
  const Eigen::Index count = std::min<Eigen::Index>(
      static_cast<Eigen::Index>(2 * rev_s / cut.time_step_s), chips.samples() - first);
  const Eigen::Index stride = std::max<Eigen::Index>(1, count / 4000);
  const Eigen::Index points = count / stride;
  out.chip_t_s.resize(points);
  out.chip_m.setZero(points, s.teeth);
  for (Eigen::Index j = 0; j < points; ++j) {
    const Eigen::Index i = first + j * stride;
    const estimate::StepChips c = chips.chips(i);
    const double b = cut.depth_m.size() == 1 ? cut.depth_m[0] : cut.depth_m[i];
    out.chip_t_s[j] = t0_s + static_cast<double>(i) * cut.time_step_s;
    for (int p = 0; p < s.teeth; ++p) {
      out.chip_m(j, p) = b > 0 ? c.tooth[static_cast<std::size_t>(p)].bw_m2 / b : 0.0;
    }
  }
}

// The ramped cut simulated with the identified values (000 table 5.1).
SimulatedBifurcation simulate_ramp(const TestSpec& t, const milling::SimulationOptions& base,
                                   milling::ChipModel model, double noise_m) {
  SimulatedBifurcation s;
  s.chip_model = model == milling::ChipModel::kNumerical ? "numerical" : "traditional";
  try {
    milling::SimulationOptions o = base;
    o.chip_model = model;
    o.depth = sync::ramp_depth_profile(schedule_of(t), t.kind_spec<CutSpec>().spindle_rpm);
    const milling::SimulationResult sim = milling::simulate(o);
    s.steps = sim.steps;
    s.runtime_s = sim.runtime_s;
    dynamics::BifurcationOptions bo;
    bo.measurement_noise_m = noise_m;
    const dynamics::SimulatedRunBifurcation b = dynamics::simulated_run_bifurcation(sim, bo);
    if (!b.result) {
      s.status.fail("the simulated run stopped after " + std::to_string(b.completed_revolutions) +
                    " revolutions: " + sim.summary.message);
      return s;
    }
    if (!b.result->summary.ok()) {
      s.status.fail(b.result->summary.message);
      return s;
    }
    s.depth_m = b.result->bifurcation_depth_m;
    s.verdict = b.result->verdict;
    s.status.succeed();
  } catch (const std::exception& e) {
    s.status.fail(e.what());
  }
  return s;
}

// Analysis errors about the test's own values, prefixed with its test.yaml.
[[noreturn]] void rethrow_labelled(const TestSpec& t, const InputError& e) {
  throw InputError(t.yaml_label + ": " + e.what());
}

}  // namespace

std::vector<std::pair<std::string, double>> keyed_values(
    const estimate::ModalParameters& modal,
    const std::vector<estimate::ToothCoefficients>& coefficients) {
  std::vector<std::pair<std::string, double>> out = {
      {"m_kg", modal.m_kg}, {"c_kg_s", modal.c_kg_s}, {"k_N_m", modal.k_N_m}};
  for (std::size_t p = 0; p < coefficients.size(); ++p) {
    out.emplace_back("Kt" + std::to_string(p + 1) + "_N_m2", coefficients[p].Kt_N_m2);
    out.emplace_back("Kr" + std::to_string(p + 1) + "_N_m2", coefficients[p].Kr_N_m2);
  }
  return out;
}

std::vector<std::pair<std::string, double>> scale_free_values(
    const estimate::ModalParameters& m,
    const std::vector<estimate::ToothCoefficients>& coefficients) {
  std::vector<std::pair<std::string, double>> v = {{"fn_hz", natural_frequency_hz(m)},
                                                   {"zeta", damping_ratio(m)}};
  for (std::size_t p = 0; p < coefficients.size(); ++p) {
    const std::string n = std::to_string(p + 1);
    v.emplace_back("Kt" + n + "_over_k_per_m", coefficients[p].Kt_N_m2 / m.k_N_m);
    v.emplace_back("Kr" + n + "_over_k_per_m", coefficients[p].Kr_N_m2 / m.k_N_m);
  }
  return v;
}

std::vector<std::pair<std::string, double>> scale_free_values(const CutEstimation& e) {
  return scale_free_values(e.modal, e.coefficients);
}

std::map<std::string, double> sequence_values(const CutEstimation& e) {
  std::map<std::string, double> v;
  for (const auto& [k, value] : keyed_values(e.modal, e.coefficients)) v[k] = value;
  for (const auto& [k, value] : scale_free_values(e)) v[k] = value;
  return v;
}

IdentifiedSet identified_set(const CutEstimation& e) {
  IdentifiedSet s;
  const bool joint = e.joint.summary.ok();
  s.method = joint ? "joint" : "sequence";
  s.modal = joint ? e.joint.modal() : e.modal;
  s.coefficients = joint ? e.joint.coefficients() : e.coefficients;
  std::map<std::string, const estimate::IntervalValue*> intervals;
  if (joint) {
    for (const auto& [key, iv] : keyed_intervals(e.joint)) intervals[key] = iv;
  }
  auto add = [&](const std::string& key, double v) {
    IdentifiedValue x{key, v};
    const auto it = intervals.find(key);
    if (it != intervals.end()) {
      x.lo = it->second->lo;
      x.hi = it->second->hi;
    }
    s.values.push_back(x);
  };
  for (const auto& [key, v] : keyed_values(s.modal, s.coefficients)) add(key, v);
  for (const auto& [key, v] : scale_free_values(s.modal, s.coefficients)) add(key, v);
  return s;
}

std::vector<std::pair<std::string, const estimate::IntervalValue*>> keyed_intervals(
    const estimate::JointIdentificationResult& j) {
  std::vector<std::pair<std::string, const estimate::IntervalValue*>> v = {
      {"offset_deg", &j.offset_deg}, {"m_kg", &j.m_kg}, {"c_kg_s", &j.c_kg_s}};
  for (std::size_t p = 0; p < j.Kt_N_m2.size(); ++p) {
    const std::string n = std::to_string(p + 1);
    v.emplace_back("Kt" + n + "_N_m2", &j.Kt_N_m2[p]);
    v.emplace_back("Kr" + n + "_N_m2", &j.Kr_N_m2[p]);
  }
  v.emplace_back("fn_hz", &j.fn_hz);
  v.emplace_back("zeta", &j.zeta);
  for (std::size_t p = 0; p < j.Kt_over_k_per_m.size(); ++p) {
    const std::string n = std::to_string(p + 1);
    v.emplace_back("Kt" + n + "_over_k_per_m", &j.Kt_over_k_per_m[p]);
    v.emplace_back("Kr" + n + "_over_k_per_m", &j.Kr_over_k_per_m[p]);
  }
  return v;
}

std::vector<FeedbackDifference> feedback_differences(const CutEstimation& e) {
  const estimate::EkfResult* measured = nullptr;
  const estimate::EkfResult* feedback = nullptr;
  for (const auto& v : e.variants) {
    if (!v.run.summary.ok()) continue;
    if (v.run.id == estimate::EstimatorId::kCoeffXyPerTooth) measured = &v.run;
    if (v.run.id == estimate::EstimatorId::kCoeffXyFeedback) feedback = &v.run;
  }
  std::vector<FeedbackDifference> out;
  if (!measured || !feedback) return out;
  for (const auto& m : measured->estimates) {
    const double f = feedback->value(m.key);
    out.push_back({m.key, m.value, f, 100.0 * (f / m.value - 1.0)});
  }
  return out;
}

milling::SimulationOptions cut_model(const TestSpec& t, const ToolSpec& tool,
                                     const milling::AxisModal& x, const milling::AxisModal& y,
                                     const std::vector<milling::CuttingCoefficients>& k) {
  milling::SimulationOptions o;
  o.teeth = tool.teeth;
  o.radius_m = tool.radius_m;
  o.modal_x = x;
  o.modal_y = y;
  o.coefficients = k;
  o.operation = t.kind_spec<CutSpec>().operation == "down-milling"
                    ? milling::Operation::kDownMilling
                    : milling::Operation::kUpMilling;
  o.spindle_rpm = t.kind_spec<CutSpec>().spindle_rpm;
  o.feed_per_tooth_m = t.kind_spec<CutSpec>().feed_per_tooth_m;
  o.radial_immersion_m = t.kind_spec<CutSpec>().radial_immersion_m;
  return o;
}

CutEstimation run_cut_estimation(const TestSpec& t, const CutStepInputs& in,
                                 const sync::TachAngle& tach, const sync::TipDeflection& tip,
                                 const sync::RevolutionMean& measured_mean,
                                 const sync::OffsetAngleResult& initial_offset,
                                 const dynamics::BifurcationResult* measured_bifurcation,
                                 double detector_noise_m, const EstimationOptions& o, int jobs) {
  using estimate::EstimatorId;
  const auto t0 = std::chrono::steady_clock::now();
  CutEstimation out;
  try {
    if (!initial_offset.summary.ok() || !in.hammer_x || !in.coefficients || !in.tool) {
      out.summary.fail(
          "the identification sequence (000 sec. 5.1) starts from the offset angle found with the "
          "hammer-test and dynamometer values, which is not available: " +
          initial_offset.summary.message);
      return out;
    }
    const ToolSpec& tool = *in.tool;
    const estimate::CutSetup setup = setup_of(t, tool);
    const estimate::ModalParameters hammer{in.hammer_x->m_kg, in.hammer_x->c_kg_s,
                                           in.hammer_x->k_N_m};
    // 000 sec. 5.1 models the force by the dynamometer's Kt, Kr without its edge terms.
    const estimate::ToothCoefficients dyno = without_edge_terms(*in.coefficients);
    const std::vector<estimate::ToothCoefficients> dyno_teeth(static_cast<std::size_t>(tool.teeth),
                                                              dyno);

    const sync::CutSchedule schedule = schedule_of(t);
    estimate::MeasuredCut base;
    try {
      out.window = estimate::choose_estimation_window(
          schedule, t.kind_spec<CutSpec>().spindle_rpm, tool.teeth,
          t.kind_spec<CutSpec>().estimation_window_s, measured_bifurcation, o);
      base = estimate::window_samples(tip.x_m, tip.y_m, sync::theta1_rad(tach, 0.0),
                                      t.sample_rate_hz, schedule, out.window);
    } catch (const InputError& e) {
      rethrow_labelled(t, e);
    }
    base = estimate::resample_cut(base, o.resample_step_s);
    std::vector<std::string> warnings = out.window.warnings;
    out.resampled_samples = base.x_m.size();
    const double t_first = std::ceil(out.window.start_s * t.sample_rate_hz) / t.sample_rate_hz;

    // Identification passes (000 sec. 5.1; docs/identification.md).
    estimate::IdentificationInputs ident;
    ident.setup = setup;
    ident.cut_model = cut_model(t, tool, {}, {}, {});
    ident.initial_offset_deg = initial_offset.search.offset_angle_deg;
    ident.offset_depth_m = initial_offset.depth_m;
    ident.hammer = hammer;
    ident.dynamometer = dyno;
    estimate::IdentificationResult ir = estimate::identify_cut(base, measured_mean, ident, o);
    out.passes = std::move(ir.passes);
    out.converged = ir.converged;
    out.offset = std::move(ir.offset);
    if (!ir.summary.ok()) {
      out.summary.fail(ir.summary.message);
      return out;
    }
    out.modal = ir.modal;
    out.coefficients = ir.coefficients;
    warnings.insert(warnings.end(), ir.summary.warnings.begin(), ir.summary.warnings.end());
    out.summary.succeed();
    out.summary.warnings = warnings;

    // The joint estimate from the sequence's values, over the same measured revolution.
    try {
      out.joint =
          estimate::identify_joint(measured_mean, ident.cut_model, ident.offset_depth_m,
                                   out.offset.search.offset_angle_deg, out.modal, out.coefficients);
    } catch (const std::exception& e) {
      // The joint estimate stands beside the sequence: its failure never fails the sequence.
      out.joint.summary.fail(e.what());
    }

    // Every variant on the final offset, the identified values known (steps 3 above).
    const estimate::MeasuredCut cut =
        estimate::with_offset_angle(base, out.offset.search.offset_angle_deg);
    constexpr auto ids = estimate::all_estimators();  // the estimator table's order
    const estimate::OperatingSample op =
        estimate::largest_force_sample(cut, setup, out.coefficients);
    out.variants.resize(ids.size());
    parallel_for(ids.size(), jobs, [&](std::size_t i) {
      VariantOutcome& v = out.variants[i];
      const EstimatorId id = ids[i];
      // 000 sec. 6.2's repeatability study is of its EKFs; the unscented twins and the feedback
      // filter are not repeated (docs/estimators.md: it would triple the estimation's time).
      const bool repeat = o.repeat.runs > 0 &&
                          estimate::estimator_info(id).filter == estimate::FilterKind::kExtended;
      try {
        if (estimate::is_modal(id)) {
          estimate::ModalParameters start = hammer;
          const EstimatorId structure = estimate::structure_of(id);
          if (structure == EstimatorId::kModalXyMk) start.c_kg_s = out.modal.c_kg_s;
          if (structure == EstimatorId::kModalXyMc) start.k_N_m = out.modal.k_N_m;
          v.known = "coefficients identified (" + coefficients_text(out.coefficients) + ")";
          v.start = "hammer test (" + modal_text(start) + ")";
          v.run = estimate::ekf_modal(id, cut, setup, {out.coefficients, start}, o.modal);
          if (v.run.summary.ok() && repeat) {
            estimate::ModalParameters ref = out.modal;
            v.repeat =
                estimate::repeat_modal(id, cut, setup, {out.coefficients, ref}, o.modal, o.repeat);
          }
        } else {
          const bool shared = estimate::structure_of(id) == EstimatorId::kCoeffXy;
          const std::vector<estimate::ToothCoefficients> start =
              shared ? std::vector<estimate::ToothCoefficients>{dyno} : dyno_teeth;
          v.known = "modal identified (" + modal_text(out.modal) + ")";
          v.start =
              "dynamometer (" + coefficients_text({dyno}) + (shared ? "" : " every tooth") + ")";
          v.run = estimate::ekf_coeff(id, cut, setup, {out.modal, start}, o.coeff);
          if (v.run.summary.ok() && repeat) {
            // Reference: the identified per-tooth values; the one-pair filter has none, so its
            // own final estimate.
            const std::vector<estimate::ToothCoefficients> ref =
                shared ? std::vector<estimate::ToothCoefficients>{{v.run.value("Kt_N_m2"),
                                                                   v.run.value("Kr_N_m2")}}
                       : out.coefficients;
            v.repeat = estimate::repeat_coeff(id, cut, setup, {out.modal, ref}, o.coeff, o.repeat);
          }
        }
        if (v.run.summary.ok()) {
          rank_variant(v, op, out.coefficients, out.modal, cut.time_step_s);
        }
      } catch (const std::exception& e) {
        v.run.summary.fail(e.what());
        v.run.id = id;
        v.run.estimator = estimate::estimator_name(id);
      }
    });
    chip_excerpt(cut, setup, t_first, out);

    // Ramped cuts: the cut simulated with the identified values (000 table 5.1).
    if (t.kind_spec<CutSpec>().axial_depth_m.first != t.kind_spec<CutSpec>().axial_depth_m.second) {
      const milling::AxisModal axis = out.modal;
      const milling::SimulationOptions model = cut_model(t, tool, axis, axis, out.coefficients);
      out.simulated.resize(2);
      const milling::ChipModel models[] = {milling::ChipModel::kTraditional,
                                           milling::ChipModel::kNumerical};
      parallel_for(2, jobs, [&](std::size_t i) {
        out.simulated[i] = simulate_ramp(t, model, models[i], detector_noise_m);
      });
    }
  } catch (const std::exception& e) {
    out.summary.fail(e.what());
  }
  out.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace chatterlab::app
