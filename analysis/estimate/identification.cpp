#include "analysis/estimate/identification.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <string>
#include <utility>

#include "analysis/common/modal_parameters.h"
#include "analysis/common/require.h"
#include "analysis/estimate/ekf_variants.h"
#include "analysis/estimate/modal_sequence.h"

namespace chatterlab {
namespace estimate {
namespace {

double relative_change(double a, double b) {
  return std::abs(a - b) / std::max(std::abs(b), 1e-300);
}

void validate(const IdentificationOptions& o) {
  require_rule(o.max_passes >= 1, "identification.max_passes", o.max_passes, "must be >= 1");
  require_rule(o.offset_tolerance_deg >= 0, "identification.offset_tolerance_deg",
               o.offset_tolerance_deg, "must be >= 0");
  require_rule(o.parameter_tolerance >= 0, "identification.parameter_tolerance",
               o.parameter_tolerance, "must be >= 0");
}

}  // namespace

bool passes_settled(const IdentificationPass& now, const IdentificationPass& before,
                    const IdentificationOptions& o) {
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

IdentificationResult identify_cut(const MeasuredCut& window,
                                  const sync::RevolutionMean& measured_mean,
                                  const IdentificationInputs& in, const IdentificationOptions& o) {
  validate(o);
  IdentificationResult out;
  const std::vector<ToothCoefficients> dyno_teeth(static_cast<std::size_t>(in.setup.teeth),
                                                  in.dynamometer);
  double offset_deg = in.initial_offset_deg;
  ModalParameters known = in.hammer;
  double held_c = in.hammer.c_kg_s;
  ModalSequenceOptions one_pass;
  one_pass.passes = 1;
  try {
    for (int pass = 0; pass < o.max_passes; ++pass) {
      const std::string label = "identification pass " + std::to_string(pass + 1) + ": ";
      const MeasuredCut cut = with_offset_angle(window, offset_deg);
      IdentificationPass p;
      p.offset_deg = offset_deg;
      const EkfResult coeff = ekf_coeff_xy_per_tooth(cut, in.setup, {known, dyno_teeth}, o.coeff);
      if (!coeff.summary.ok()) {
        out.summary.fail(label + "ekf-coeff-xy-per-tooth: " + coeff.summary.message);
        return out;
      }
      for (int q = 1; q <= in.setup.teeth; ++q) {
        const std::string n = std::to_string(q);
        p.coefficients.push_back(
            {coeff.value("Kt" + n + "_N_m2"), coeff.value("Kr" + n + "_N_m2")});
      }
      const ModalSequenceResult seq = modal_mk_then_mc(
          cut, in.setup, {p.coefficients, {in.hammer.m_kg, held_c, in.hammer.k_N_m}}, o.modal,
          one_pass);
      if (!seq.summary.ok()) {
        out.summary.fail(label + seq.summary.message);
        return out;
      }
      p.modal = seq.identified;
      milling::SimulationOptions model = in.cut_model;
      model.modal_x = p.modal;
      model.modal_y = model.modal_x;
      model.coefficients = p.coefficients;
      sync::OffsetAngleResult again =
          sync::find_offset_angle(measured_mean, model, in.offset_depth_m);
      if (!again.summary.ok()) {
        out.summary.fail(label +
                         "offset angle with the identified values: " + again.summary.message);
        return out;
      }
      p.offset_after_deg = again.search.offset_angle_deg;
      p.offset_relative_error = again.relative_error;
      out.offset = std::move(again);
      out.converged = !out.passes.empty() && passes_settled(p, out.passes.back(), o);
      out.passes.push_back(p);
      known = p.modal;
      held_c = p.modal.c_kg_s;
      offset_deg = p.offset_after_deg;
      if (out.converged) break;
    }
  } catch (const std::exception& e) {
    out.summary.fail(e.what());
    return out;
  }
  const IdentificationPass& last = out.passes.back();
  out.modal = last.modal;
  out.coefficients = last.coefficients;
  out.summary.succeed();
  if (!out.converged && o.max_passes > 1) {
    out.summary.warnings.push_back(
        "identification: not settled after " + std::to_string(o.max_passes) +
        " passes (offset and parameters still move by more than the tolerances)");
  }
  return out;
}

}  // namespace estimate
}  // namespace chatterlab
