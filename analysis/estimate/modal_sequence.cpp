#include "analysis/estimate/modal_sequence.h"

#include <string>

namespace chatterlab {
namespace estimate {

ModalSequenceResult modal_mk_then_mc(const MeasuredCut& cut, const CutSetup& setup,
                                     const ModalEkfInputs& inputs, const ModalEkfOptions& options,
                                     const ModalSequenceOptions& sequence) {
  if (sequence.passes < 1) {
    throw InputError("sequence.passes = " + std::to_string(sequence.passes) + ": must be >= 1");
  }
  ModalSequenceResult res;
  double held_c = inputs.start.c_kg_s;
  for (int pass = 0; pass < sequence.passes; ++pass) {
    ModalEkfInputs mk = inputs;
    mk.start.c_kg_s = held_c;
    res.runs.push_back(ekf_modal_xy_mk(cut, setup, mk, options));
    const EkfResult& a = res.runs.back();
    if (!a.summary.ok()) {
      res.summary.fail("pass " + std::to_string(pass + 1) +
                       ", ekf-modal-xy-mk: " + a.summary.message);
      return res;
    }
    res.identified.m_kg = a.value("m_kg");
    res.identified.k_N_m = a.value("k_N_m");

    ModalEkfInputs mc = inputs;
    mc.start.k_N_m = res.identified.k_N_m;
    res.runs.push_back(ekf_modal_xy_mc(cut, setup, mc, options));
    const EkfResult& b = res.runs.back();
    if (!b.summary.ok()) {
      res.summary.fail("pass " + std::to_string(pass + 1) +
                       ", ekf-modal-xy-mc: " + b.summary.message);
      return res;
    }
    held_c = b.value("c_kg_s");
    res.identified.c_kg_s = held_c;
  }
  res.summary.succeed();
  return res;
}

}  // namespace estimate
}  // namespace chatterlab
