// SignalTable::open on text (CSV dialects, detected or stated), raw .f32/.f64 and the channel
// reads after it. The first byte picks the file's extension and the dialect data: states; the
// rest is the file. InputError is the expected outcome of bad input.
#include <cstddef>
#include <cstdint>
#include <string>

#include "analysis/common/summary.h"
#include "app/core/signals.h"
#include "fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::uint8_t sel = data[0];
  static const char* const kExt[] = {".csv", ".txt", ".f32", ".f64"};
  static const char kDelim[] = {0, ',', ';', '\t'};
  chatterlab::app::DataSpec spec;
  spec.relative_file = std::string("signals") + kExt[sel & 3];
  spec.file = chatterlab::fuzz::write_input(spec.relative_file, data + 1, size - 1);
  spec.delimiter = kDelim[(sel >> 2) & 3];
  spec.decimal = (sel & 0x10) != 0 ? ',' : '.';
  spec.skip_lines = (sel >> 5) & 1;
  spec.channels = (sel & 0x40) != 0 ? std::vector<std::string>{"force", "response"}
                                    : std::vector<std::string>{"x"};
  if ((sel & 0x80) != 0) spec.sample_rate_hz = 1000.0;
  try {
    const auto table = chatterlab::app::SignalTable::open(spec, spec.relative_file);
    for (const auto& name : table.names()) {
      const auto c = table.channel(name);
      if (c.size() != static_cast<Eigen::Index>(table.samples())) __builtin_trap();
    }
    chatterlab::app::ChannelSpec by_index;
    by_index.column = chatterlab::app::ColumnRef{"", 0};
    (void)table.channel("force", by_index);
  } catch (const chatterlab::InputError&) {
  }
  return 0;
}
