#include "app/kinds/cut/cut_estimation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>

#include "analysis/estimate/cut_input.h"
#include "analysis/milling/simulation.h"
#include "app/core/format.h"
#include "app/core/parallel.h"
#include "app/kinds/cut/cut_step.h"

namespace chatterlab::app {
namespace {

constexpr double kDegToRad = 0.017453292519943295;

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

// Window rule (docs/identification.md): test.yaml estimation_window_s when given; otherwise
// window_s plus one chip delay, at constant depth ending one revolution before the cut ends (the
// most settled cutting), on a ramp centred where the depth is 3/4 of the measured bifurcation
// depth (chatter-free cutting, as deep as it stays chatter-free) or 3/4 of the deepest depth
// when the run never chatters. Never earlier than settle_revolutions after the cut starts.
EstimationWindow choose_window(const TestSpec& t, int teeth, const dynamics::BifurcationResult* bif,
                               const EstimationOptions& o, std::vector<std::string>& warnings) {
  const sync::CutSchedule s = schedule_of(t);
  const double rev_s = 60.0 / t.kind_spec<CutSpec>().spindle_rpm;
  const double tau_s = rev_s / teeth;  // the chip delay: the filters start this much later
  const double first = s.cut_start_s + o.settle_revolutions * rev_s;
  const double last = s.cut_end_s - rev_s;
  EstimationWindow w;
  if (t.kind_spec<CutSpec>().estimation_window_s) {
    w.start_s = t.kind_spec<CutSpec>().estimation_window_s->first;
    w.end_s = t.kind_spec<CutSpec>().estimation_window_s->second;
    w.rule = "test.yaml estimation_window_s";
  } else {
    const double length = o.window_s + tau_s;
    if (s.depth_start_m == s.depth_end_m) {
      w.end_s = last;
      w.rule = "the last " + fmt_sig(o.window_s, 4) + " s of the constant-depth cut";
    } else {
      const double lo = std::min(s.depth_start_m, s.depth_end_m);
      const double hi = std::max(s.depth_start_m, s.depth_end_m);
      double target = 0.75 * hi;
      if (bif && bif->summary.ok && bif->bifurcation_depth_m) {
        target = 0.75 * *bif->bifurcation_depth_m;
        w.rule = "centred at 3/4 of the measured bifurcation depth";
      } else if (bif && bif->summary.ok && bif->verdict == dynamics::RunVerdict::kAllChatter) {
        target = lo + 0.25 * (hi - lo);
        w.rule = "centred near the shallow end (the run chatters throughout)";
        warnings.push_back(
            "estimation: the bifurcation detector finds chatter over the whole run; the filters' "
            "model assumes chatter-free cutting");
      } else {
        w.rule = "centred at 3/4 of the deepest depth (no bifurcation measured)";
      }
      target = std::clamp(target, lo, hi);
      const double frac = (target - s.depth_start_m) / (s.depth_end_m - s.depth_start_m);
      const double centre = s.cut_start_s + frac * (s.cut_end_s - s.cut_start_s);
      w.end_s = centre + 0.5 * length;
    }
    w.end_s = std::min(w.end_s, last);
    w.start_s = std::max(first, w.end_s - length);
    w.end_s = std::min(last, w.start_s + length);
    if (w.end_s - w.start_s < 0.999 * length) {
      warnings.push_back(
          "estimation: the cut holds " + fmt_sig(std::max(0.0, w.end_s - w.start_s - tau_s), 3) +
          " s of settled cutting, less than estimation.window_s = " + fmt_sig(o.window_s, 4) +
          " s");
    }
  }
  if (!(w.end_s - w.start_s > 4 * rev_s)) {
    throw InputError(t.yaml_label + ": estimation window " + fmt_sig(w.start_s, 6) + " to " +
                     fmt_sig(w.end_s, 6) +
                     " s: the filters need at least four revolutions of settled cutting (after " +
                     fmt_sig(o.settle_revolutions, 4) + " settling revolutions)");
  }
  w.depth_start_m = s.depth_at_m(w.start_s);
  w.depth_end_m = s.depth_at_m(w.end_s);
  return w;
}

// The window's tip deflections and tachometer phase (theta_1 with offset 0), resampled once;
// each offset adds to theta_1 (theta_1 = phase + offset).
estimate::MeasuredCut measured_window(const TestSpec& t, const sync::TachAngle& tach,
                                      const sync::TipDeflection& tip, const EstimationWindow& w,
                                      double step_s) {
  const double fs = t.sample_rate_hz;
  const auto i0 = static_cast<Eigen::Index>(std::ceil(w.start_s * fs));
  const auto i1 = std::min<Eigen::Index>(static_cast<Eigen::Index>(std::floor(w.end_s * fs)),
                                         tip.x_m.size() - 1);
  if (i1 - i0 < 8) {
    throw InputError(t.yaml_label + ": estimation window " + fmt_sig(w.start_s, 6) + " to " +
                     fmt_sig(w.end_s, 6) + " s lies outside the record");
  }
  const Eigen::Index n = i1 - i0 + 1;
  estimate::MeasuredCut raw;
  raw.time_step_s = 1.0 / fs;
  raw.x_m = tip.x_m.segment(i0, n);
  raw.y_m = tip.y_m.segment(i0, n);
  raw.theta1_rad = sync::theta1_rad(tach, 0.0).segment(i0, n);
  const sync::CutSchedule s = schedule_of(t);
  if (s.depth_start_m == s.depth_end_m) {
    raw.depth_m = Eigen::VectorXd::Constant(1, s.depth_start_m);
  } else {
    raw.depth_m.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      raw.depth_m[i] = s.depth_at_m(static_cast<double>(i0 + i) / fs);
    }
  }
  return estimate::resample_cut(raw, step_s);
}

estimate::MeasuredCut with_offset(const estimate::MeasuredCut& base, double offset_deg) {
  estimate::MeasuredCut c = base;
  c.theta1_rad.array() += offset_deg * kDegToRad;
  return c;
}

std::vector<milling::CuttingCoefficients> simulator_coefficients(
    const std::vector<estimate::ToothCoefficients>& k) {
  std::vector<milling::CuttingCoefficients> out;
  for (const auto& c : k) out.push_back(milling::cutting_coefficients(c.Kt_N_m2, c.Kr_N_m2));
  return out;
}

double relative_change(double a, double b) {
  return std::abs(a - b) / std::max(std::abs(b), 1e-300);
}

bool settled(const IdentificationPass& now, const IdentificationPass& before,
             const EstimationOptions& o) {
  double worst = std::max({relative_change(now.modal.m_kg, before.modal.m_kg),
                           relative_change(now.modal.c_kg_s, before.modal.c_kg_s),
                           relative_change(now.modal.k_N_m, before.modal.k_N_m)});
  for (std::size_t p = 0; p < now.coefficients.size(); ++p) {
    worst = std::max(
        {worst, relative_change(now.coefficients[p].Kt_N_m2, before.coefficients[p].Kt_N_m2),
         relative_change(now.coefficients[p].Kr_N_m2, before.coefficients[p].Kr_N_m2)});
  }
  double moved = std::abs(now.offset_after_deg - before.offset_after_deg);
  moved = std::min(moved, 360.0 - moved);
  return moved < o.offset_tolerance_deg && worst < o.parameter_tolerance;
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

// The operating point of 000 sec. 4.5 for the observability rank: the sample of the window with
// the largest cutting force (a tooth cuts), deflections measured there, velocities by central
// difference, parameters at the run's final estimates.
struct OperatingSample {
  Eigen::Index k = 0;
  estimate::StepChips chips;
  Eigen::Vector4d deflection = Eigen::Vector4d::Zero();
};

OperatingSample operating_sample(const estimate::MeasuredCut& cut, const estimate::CutSetup& s,
                                 const std::vector<estimate::ToothCoefficients>& k) {
  const estimate::CutChips chips(cut, s);
  OperatingSample best;
  double largest = -1.0;
  for (Eigen::Index i = std::max<Eigen::Index>(chips.first_step(), 1); i + 1 < chips.samples();
       ++i) {
    const estimate::StepChips c = chips.chips(i);
    const double f = estimate::cutting_force_N(c, k).norm();
    if (f > largest) {
      largest = f;
      best.k = i;
      best.chips = c;
    }
  }
  const Eigen::Index i = best.k;
  const double T = cut.time_step_s;
  best.deflection << cut.x_m[i], (cut.x_m[i + 1] - cut.x_m[i - 1]) / (2 * T), cut.y_m[i],
      (cut.y_m[i + 1] - cut.y_m[i - 1]) / (2 * T);
  return best;
}

void rank_variant(VariantOutcome& v, const OperatingSample& op,
                  const std::vector<estimate::ToothCoefficients>& k,
                  const estimate::ModalParameters& identified, double T) {
  using estimate::EstimatorId;
  const estimate::EkfResult& r = v.run;
  try {
    estimate::ForceInput u;
    estimate::ModalParameters held = identified;
    Eigen::VectorXd state;
    const auto value = [&r](const char* key) { return r.value(key); };
    switch (r.id) {
      case EstimatorId::kModalX:
        u.known_N = estimate::cutting_force_N(op.chips, k);
        state.resize(5);
        state << op.deflection[0], op.deflection[1], value("m_kg"), value("c_kg_s"), value("k_N_m");
        break;
      case EstimatorId::kModalXy:
        u.known_N = estimate::cutting_force_N(op.chips, k);
        state.resize(7);
        state << op.deflection, value("m_kg"), value("c_kg_s"), value("k_N_m");
        break;
      case EstimatorId::kModalXyMk:
        u.known_N = estimate::cutting_force_N(op.chips, k);
        state.resize(6);
        state << op.deflection, value("m_kg"), value("k_N_m");
        break;
      case EstimatorId::kModalXyMc:
        u.known_N = estimate::cutting_force_N(op.chips, k);
        state.resize(6);
        state << op.deflection, value("m_kg"), value("c_kg_s");
        break;
      case EstimatorId::kCoeffXy:
        for (int p = 0; p < op.chips.teeth; ++p) {
          u.regressor_m2 +=
              estimate::tooth_regressor_m2(op.chips.tooth[static_cast<std::size_t>(p)]);
        }
        state.resize(6);
        state << op.deflection, value("Kt_N_m2"), value("Kr_N_m2");
        break;
      case EstimatorId::kCoeffXyPerTooth: {
        // The filter of the tooth that cuts at the operating point (each filter has the same
        // structure; its tooth's columns are the ones that can be zero).
        int p = 0;
        double bw = -1.0;
        for (int q = 0; q < op.chips.teeth; ++q) {
          if (op.chips.tooth[static_cast<std::size_t>(q)].bw_m2 > bw) {
            bw = op.chips.tooth[static_cast<std::size_t>(q)].bw_m2;
            p = q;
          }
        }
        u.regressor_m2 = estimate::tooth_regressor_m2(op.chips.tooth[static_cast<std::size_t>(p)]);
        std::vector<estimate::ToothCoefficients> others = k;
        others[static_cast<std::size_t>(p)] = {0.0, 0.0};
        u.known_N = estimate::cutting_force_N(op.chips, others);
        state.resize(6);
        const std::string n = std::to_string(p + 1);
        state << op.deflection, r.value("Kt" + n + "_N_m2"), r.value("Kr" + n + "_N_m2");
        break;
      }
    }
    if (r.id == EstimatorId::kModalXyMk) held.c_kg_s = identified.c_kg_s;
    if (r.id == EstimatorId::kModalXyMc) held.k_N_m = identified.k_N_m;
    v.observability = estimate::observability(r.id, state, u, held, T);
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

SimulatedBifurcation simulate_ramp(const TestSpec& t, const milling::SimulationOptions& base,
                                   milling::ChipModel model, double noise_m) {
  SimulatedBifurcation s;
  s.chip_model = model == milling::ChipModel::kNumerical ? "numerical" : "traditional";
  try {
    const sync::CutSchedule c = schedule_of(t);
    milling::SimulationOptions o = base;
    o.chip_model = model;
    const double revolutions =
        (c.cut_end_s - c.cut_start_s) * t.kind_spec<CutSpec>().spindle_rpm / 60.0;
    o.depth = milling::DepthProfile::ramp(
        c.depth_start_m, c.depth_end_m,
        revolutions / (std::abs(c.depth_end_m - c.depth_start_m) * 1e3));
    const milling::SimulationResult sim = milling::simulate(o);
    s.steps = sim.steps;
    s.runtime_s = sim.runtime_s;
    Eigen::Index done = 0;
    while (done < sim.samples.x_m.size() && std::isfinite(sim.samples.x_m[done])) ++done;
    dynamics::BifurcationOptions bo;
    bo.measurement_noise_m = noise_m;
    bo.ends_unbounded = !sim.summary.ok;
    if (done <= bo.window_revolutions) {
      s.status.fail("the simulated run stopped after " + std::to_string(done) +
                    " revolutions: " + sim.summary.message);
      return s;
    }
    const dynamics::BifurcationResult b = dynamics::detect_bifurcation(
        sim.samples.depth_m.head(done), sim.samples.x_m.head(done), bo);
    if (!b.summary.ok) {
      s.status.fail(b.summary.message);
      return s;
    }
    s.depth_m = b.bifurcation_depth_m;
    s.verdict = b.verdict;
    s.status.succeed();
  } catch (const std::exception& e) {
    s.status.fail(e.what());
  }
  return s;
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

std::vector<std::pair<std::string, double>> scale_free_values(const CutEstimation& e) {
  const estimate::ModalParameters& m = e.modal;
  std::vector<std::pair<std::string, double>> v = {
      {"fn_hz", std::sqrt(m.k_N_m / m.m_kg) / (2 * M_PI)},
      {"zeta", m.c_kg_s / (2 * std::sqrt(m.k_N_m * m.m_kg))}};
  for (std::size_t p = 0; p < e.coefficients.size(); ++p) {
    const std::string n = std::to_string(p + 1);
    v.emplace_back("Kt" + n + "_over_k_per_m", e.coefficients[p].Kt_N_m2 / m.k_N_m);
    v.emplace_back("Kr" + n + "_over_k_per_m", e.coefficients[p].Kr_N_m2 / m.k_N_m);
  }
  return v;
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
    if (!initial_offset.summary.ok || !in.hammer_x || !in.coefficients || !in.tool) {
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
    const estimate::ToothCoefficients dyno{in.coefficients->Ktc_N_per_m2,
                                           in.coefficients->Krc_N_per_m2};
    const std::vector<estimate::ToothCoefficients> dyno_teeth(static_cast<std::size_t>(tool.teeth),
                                                              dyno);

    std::vector<std::string> warnings;
    out.window = choose_window(t, tool.teeth, measured_bifurcation, o, warnings);
    const estimate::MeasuredCut base = measured_window(t, tach, tip, out.window, o.resample_step_s);
    out.resampled_samples = base.x_m.size();
    const double t_first = std::ceil(out.window.start_s * t.sample_rate_hz) / t.sample_rate_hz;

    // Identification passes (000 sec. 5.1; docs/identification.md).
    double offset_deg = initial_offset.search.offset_angle_deg;
    estimate::ModalParameters known = hammer;
    double held_c = hammer.c_kg_s;
    estimate::ModalSequenceOptions one_pass;
    one_pass.passes = 1;
    for (int pass = 0; pass < o.max_passes; ++pass) {
      const estimate::MeasuredCut cut = with_offset(base, offset_deg);
      IdentificationPass p;
      p.offset_deg = offset_deg;
      const estimate::EkfResult coeff =
          estimate::ekf_coeff_xy_per_tooth(cut, setup, {known, dyno_teeth}, o.coeff);
      if (!coeff.summary.ok) {
        out.summary.fail("identification pass " + std::to_string(pass + 1) +
                         ": ekf-coeff-xy-per-tooth: " + coeff.summary.message);
        return out;
      }
      for (int q = 1; q <= tool.teeth; ++q) {
        const std::string n = std::to_string(q);
        p.coefficients.push_back(
            {coeff.value("Kt" + n + "_N_m2"), coeff.value("Kr" + n + "_N_m2")});
      }
      const estimate::ModalSequenceResult seq = estimate::modal_mk_then_mc(
          cut, setup, {p.coefficients, {hammer.m_kg, held_c, hammer.k_N_m}}, o.modal, one_pass);
      if (!seq.summary.ok) {
        out.summary.fail("identification pass " + std::to_string(pass + 1) + ": " +
                         seq.summary.message);
        return out;
      }
      p.modal = seq.identified;
      const milling::AxisModal axis{p.modal.m_kg, p.modal.c_kg_s, p.modal.k_N_m};
      sync::OffsetAngleResult again = sync::find_offset_angle(
          measured_mean, cut_model(t, tool, axis, axis, simulator_coefficients(p.coefficients)),
          initial_offset.depth_m);
      if (!again.summary.ok) {
        out.summary.fail("identification pass " + std::to_string(pass + 1) +
                         ": offset angle with the identified values: " + again.summary.message);
        return out;
      }
      p.offset_after_deg = again.search.offset_angle_deg;
      p.offset_relative_error = again.relative_error;
      out.offset = std::move(again);
      out.converged = !out.passes.empty() && settled(p, out.passes.back(), o);
      out.passes.push_back(p);
      known = p.modal;
      held_c = p.modal.c_kg_s;
      offset_deg = p.offset_after_deg;
      if (out.converged) break;
    }
    const IdentificationPass& last = out.passes.back();
    out.modal = last.modal;
    out.coefficients = last.coefficients;
    if (!out.converged && o.max_passes > 1) {
      warnings.push_back("identification: not settled after " + std::to_string(o.max_passes) +
                         " passes (offset and parameters still move by more than the tolerances)");
    }
    out.summary.succeed();
    out.summary.warnings = warnings;

    // Every variant on the final offset, the identified values known (steps 3 above).
    const estimate::MeasuredCut cut = with_offset(base, out.offset.search.offset_angle_deg);
    const std::vector<EstimatorId> ids = {EstimatorId::kModalX,    EstimatorId::kModalXy,
                                          EstimatorId::kModalXyMk, EstimatorId::kModalXyMc,
                                          EstimatorId::kCoeffXy,   EstimatorId::kCoeffXyPerTooth};
    const OperatingSample op = operating_sample(cut, setup, out.coefficients);
    out.variants.resize(ids.size());
    parallel_for(ids.size(), jobs, [&](std::size_t i) {
      VariantOutcome& v = out.variants[i];
      const EstimatorId id = ids[i];
      try {
        if (estimate::is_modal(id)) {
          estimate::ModalParameters start = hammer;
          if (id == EstimatorId::kModalXyMk) start.c_kg_s = out.modal.c_kg_s;
          if (id == EstimatorId::kModalXyMc) start.k_N_m = out.modal.k_N_m;
          v.known = "coefficients identified (" + coefficients_text(out.coefficients) + ")";
          v.start = "hammer test (" + modal_text(start) + ")";
          v.run = estimate::ekf_modal(id, cut, setup, {out.coefficients, start}, o.modal);
          if (v.run.summary.ok && o.repeat.runs > 0) {
            estimate::ModalParameters ref = out.modal;
            v.repeat =
                estimate::repeat_modal(id, cut, setup, {out.coefficients, ref}, o.modal, o.repeat);
          }
        } else {
          const bool shared = id == EstimatorId::kCoeffXy;
          const std::vector<estimate::ToothCoefficients> start =
              shared ? std::vector<estimate::ToothCoefficients>{dyno} : dyno_teeth;
          v.known = "modal identified (" + modal_text(out.modal) + ")";
          v.start =
              "dynamometer (" + coefficients_text({dyno}) + (shared ? "" : " every tooth") + ")";
          v.run = estimate::ekf_coeff(id, cut, setup, {out.modal, start}, o.coeff);
          if (v.run.summary.ok && o.repeat.runs > 0) {
            // Reference: the identified per-tooth values; the one-pair filter has none, so its
            // own final estimate.
            const std::vector<estimate::ToothCoefficients> ref =
                shared ? std::vector<estimate::ToothCoefficients>{{v.run.value("Kt_N_m2"),
                                                                   v.run.value("Kr_N_m2")}}
                       : out.coefficients;
            v.repeat = estimate::repeat_coeff(id, cut, setup, {out.modal, ref}, o.coeff, o.repeat);
          }
        }
        if (v.run.summary.ok) {
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
      const milling::AxisModal axis{out.modal.m_kg, out.modal.c_kg_s, out.modal.k_N_m};
      const milling::SimulationOptions model =
          cut_model(t, tool, axis, axis, simulator_coefficients(out.coefficients));
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
