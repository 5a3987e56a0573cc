// fields() of the ERA model structs (app/core/archive.h) that the frf and sweep-frf kinds'
// results both hold.
#pragma once

#include "app/core/archive_analysis.h"
#include "app/kinds/sysid/sysid_kinds.h"

namespace chatterlab::app {

template <class Ar>
void fields(Ar& ar, DriveModel& m) {
  LAYOUT_GUARD(DriveModel, 168);
  ar(m.id, m.model, m.input_unit, m.output_unit);
}

template <class Ar>
void fields(Ar& ar, EraModelResult& m) {
  LAYOUT_GUARD(EraModelResult, 592);
  ar(m.era, m.input_unit, m.output_unit, m.drive);
}

}  // namespace chatterlab::app
