// fields() of the forcerec kinds' structs (app/core/archive.h) that both kinds hold: a
// dyno-frf result's model is also the model a force record reconstructs with.
#pragma once

#include "app/core/archive_analysis.h"
#include "app/kinds/forcerec/forcerec_kinds.h"

namespace chatterlab::app {

template <class Ar>
void fields(Ar& ar, DynoModel& m) {
  LAYOUT_GUARD(DynoModel, 208);
  ar(m.id, m.axis, m.model, m.realization, m.fit_pct);
}

}  // namespace chatterlab::app
