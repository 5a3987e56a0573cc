// uff::read_uff58 on ASCII dataset 58 and binary 58b files; then SignalTable::open on the same
// bytes as a .uff signal file (channels from time records). InputError is expected.
#include <cstddef>
#include <cstdint>

#include "analysis/common/summary.h"
#include "app/core/signals.h"
#include "app/formats/uff58.h"
#include "fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = chatterlab::fuzz::write_input("record.uff", data, size);
  try {
    const auto functions = chatterlab::app::uff::read_uff58(file);
    for (const auto& f : functions) {
      if (f.complex_ordinate ? f.real.size() != 0 : f.values.size() != 0) __builtin_trap();
    }
  } catch (const chatterlab::InputError&) {
  }
  try {
    chatterlab::app::DataSpec spec;
    spec.file = file;
    spec.relative_file = "record.uff";
    const auto table = chatterlab::app::SignalTable::open(spec, spec.relative_file);
    for (const auto& name : table.names()) (void)table.channel(name);
  } catch (const chatterlab::InputError&) {
  }
  return 0;
}
