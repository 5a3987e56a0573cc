// read_inspections on a grinding test's inspections table (format section 7: header
// cycle[,available_cycle],ds_mm,Ra_um,roundness_um; its own CSV reader, not SignalTable's).
// InputError is expected.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "app/kinds/grinding/grinding_kind.h"
#include "fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = chatterlab::fuzz::write_input("inspections.csv", data, size);
  std::vector<std::string> warnings;
  try {
    (void)chatterlab::app::read_inspections(file, "inspections.csv", warnings);
  } catch (const chatterlab::InputError&) {
  }
  return 0;
}
