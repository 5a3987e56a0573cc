// fields() of the analysis structs that kinds' results hold (app/core/archive.h), each in its
// struct's namespace. A kind's own structs list theirs beside the kind.
#pragma once

#include "analysis/common/modal_parameters.h"
#include "analysis/frf/modal_fit.h"
#include "analysis/frf/mode.h"
#include "app/core/archive.h"

namespace chatterlab {

template <class Ar>
void fields(Ar& ar, ModalParameters& p) {
  LAYOUT_GUARD(ModalParameters, 24);
  ar(p.m_kg, p.c_kg_s, p.k_N_m);
}

namespace frf {

template <class Ar>
void fields(Ar& ar, Mode& m) {
  LAYOUT_GUARD(Mode, 40);
  fields(ar, static_cast<ModalParameters&>(m));
  ar(m.fn_hz, m.zeta);
}

template <class Ar>
void fields(Ar& ar, ModeQuality& q) {
  LAYOUT_GUARD(ModeQuality, 24);
  ar(q.resolution_limited, q.half_power_bins, q.negative_constant, q.at_bound, q.from_residual);
}

}  // namespace frf
}  // namespace chatterlab
