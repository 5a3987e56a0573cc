// The built-in kinds: adding a kind adds one line here (docs/adding-a-kind.md).
#include "app/kinds/cut/cut_kind.h"
#include "app/kinds/dyno_slot/dyno_slot_kind.h"
#include "app/kinds/forcerec/forcerec_kinds.h"
#include "app/kinds/grinding/grinding_kind.h"
#include "app/kinds/lobes/lobes_group.h"
#include "app/kinds/sifs/sifs_kinds.h"
#include "app/kinds/sysid/sysid_kinds.h"
#include "app/kinds/tap/tap_kind.h"
#include "app/pipeline/registry.h"

namespace chatterlab::app {

void register_builtin_kinds(KindRegistry& r) {
  r.add(std::make_unique<TapKind>());
  r.add(std::make_unique<DynoSlotKind>());
  r.add(std::make_unique<DynoSlotGroup>());
  r.add(std::make_unique<CutKind>());
  r.add(std::make_unique<LobesGroup>());
  r.add(std::make_unique<GrindingKind>());
  r.add(std::make_unique<SifsStaticKind>());
  r.add(std::make_unique<SifsStaticGroup>());
  r.add(std::make_unique<SifsTapKind>());
  r.add(std::make_unique<SifsCutKind>());
  r.add(std::make_unique<SifsCutGroup>());
  r.add(std::make_unique<FrfKind>());
  r.add(std::make_unique<SweepFrfKind>());
  r.add(std::make_unique<SpindleCurrentKind>());
  r.add(std::make_unique<DynoFrfKind>());
  r.add(std::make_unique<ForceRecordKind>());
}

}  // namespace chatterlab::app
