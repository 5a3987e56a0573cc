// frf_text::read_frf_text on FRF tables. The first byte picks the stated delimiter and decimal
// mark (or detection); the rest is the file. InputError is expected.
#include <cstddef>
#include <cstdint>

#include "analysis/common/summary.h"
#include "app/formats/frf_text.h"
#include "fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char kDelim[] = {0, ',', ';', '\t', ' '};
  static const char kDecimal[] = {0, '.', ','};
  chatterlab::app::frf_text::ReadOptions options;
  options.delimiter = kDelim[(data[0] & 0x0f) % 5];
  options.decimal = kDecimal[(data[0] >> 4) % 3];
  const auto file = chatterlab::fuzz::write_input("frf.csv", data + 1, size - 1);
  try {
    const auto t = chatterlab::app::frf_text::read_frf_text(file, "frf.csv", options);
    if (t.f_hz.size() != t.h.size()) __builtin_trap();
  } catch (const chatterlab::InputError&) {
  }
  return 0;
}
