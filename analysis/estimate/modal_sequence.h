// Modal parameters two at a time (000 sec. 5.1, with the filters of sec. 6.1): ekf-modal-xy-mk
// with the damping held at the hammer test's value, then ekf-modal-xy-mc with the stiffness held
// at the mk estimate. 000 reports m and k from the mk run and c from the mc run.
//
// One pass is 000's procedure. With the hammer damping far off (000: 13.39 against 22.21 kg/s)
// the mk run absorbs the damping error into m and k (+1.4 % in
// tests/analysis/estimate/estimate_modal_test.cpp, up to +2.2 % over noise seeds); a second pass
// runs mk again with the mc damping, which removes it (to 0.03 %). Every run starts from the same
// initial m, k (and c).
#pragma once

#include <vector>

#include "analysis/common/summary.h"
#include "analysis/estimate/ekf_variants.h"

namespace chatterlab {
namespace estimate {

struct ModalSequenceOptions {
  // mk-then-mc passes, >= 1. 1: 000 sec. 5.1. Default 2 (see above).
  int passes = 2;
};

struct ModalSequenceResult {
  StepSummary summary;          // failed if a run failed (names it)
  std::vector<EkfResult> runs;  // mk, mc, mk, mc, ... in order
  ModalParameters identified;   // m_kg, k_N_m of the last mk run, c_kg_s of the last mc run
};

// inputs.start: initial m, c, k; its c_kg_s is the damping the first mk run holds (the hammer
// test's). Throws InputError as ekf_modal does, or "sequence.passes = 0: must be >= 1".
ModalSequenceResult modal_mk_then_mc(const MeasuredCut& cut, const CutSetup& setup,
                                     const ModalEkfInputs& inputs,
                                     const ModalEkfOptions& options = {},
                                     const ModalSequenceOptions& sequence = {});

}  // namespace estimate
}  // namespace chatterlab
