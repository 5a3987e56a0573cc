// mat::numeric_variables and read_vector (libmatio underneath) on .mat files, then
// SignalTable::open on the same bytes as a .mat signal file. InputError is expected. libmatio
// runs in a reader process (app/formats/matfile.cpp); its death is an InputError here.
#include <hdf5.h>

#include <chrono>
#include <cstddef>
#include <cstdint>

#include "analysis/common/summary.h"
#include "app/core/signals.h"
#include "app/formats/matfile.h"
#include "fuzz/fuzz_common.h"

// An input makes up to four reads (two here, two in SignalTable::open): each one caught in a
// loop is killed after 2 s, so that all four stay inside libFuzzer's -timeout=10. A reply is
// cut at 256 MiB, well inside -rss_limit_mb=2048 (the reply string grows by doubling, and ASan
// keeps freed memory in quarantine). The reads go to one reader process kept for 1,000 reads
// rather than a process forked per read: a fork of this ASan process cost 3 ms a read, the
// target ran 76 inputs a second, and 10 million would have taken 36 hours (docs/fuzzing.md,
// "Speed").
extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  chatterlab::app::mat::set_reader_time_limit(std::chrono::seconds(2));
  chatterlab::app::mat::set_reader_reply_limit(std::size_t{256} << 20);
  chatterlab::app::mat::set_reader_process_reuse(1000);
  // libhdf5 keeps the blocks it frees on free lists of its own, by default at most 64 KB a
  // regular list and 1 MB over all of them (H5FL.c). The metadata cache of each H5Fopen (about
  // 0.5 MB) passes the per-list limit: it went back to malloc at each close, and ASan maps a
  // block that large anew each time, so every v7.3 read cleared fresh pages (20 % of the
  // samples). The regular lists may now keep 4 MB each, 16 MB in all, so the next open reuses
  // the block; the array and block lists keep their defaults (one block list per chunk size,
  // which a kept reader process fed 1,000 fuzzed files would pile up). The reader processes,
  // forked from this one, inherit the setting. What it can hide is a heap error inside libhdf5
  // on a recycled block, which the reader process contains either way; the program keeps
  // libhdf5's defaults (a reader process there reads one file). docs/fuzzing.md, "Speed".
  H5set_free_list_limits(16 << 20, 4 << 20, 4 << 20, 256 << 10, 16 << 20, 1 << 20);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = chatterlab::fuzz::write_input("signals.mat", data, size);
  bool listed = false;
  try {
    // One read_vector: the first vector whole, or the first matrix's last column. Each call is
    // a read in the reader process (matfile.cpp), so not one per variable.
    const auto variables = chatterlab::app::mat::numeric_variables(file);
    listed = true;
    for (const auto& v : variables) {
      if (v.vector()) {
        (void)chatterlab::app::mat::read_vector(file, v.name);
        break;
      }
      if (v.cols > 1) {
        (void)chatterlab::app::mat::read_vector(file, v.name, v.cols - 1);
        break;
      }
    }
  } catch (const chatterlab::InputError&) {
  }
  // SignalTable::read_mat lists the variables first, with the same call: a file the listing
  // refused is not read again.
  if (!listed) return 0;
  try {
    chatterlab::app::DataSpec spec;
    spec.file = file;
    spec.relative_file = "signals.mat";
    const auto table = chatterlab::app::SignalTable::open(spec, spec.relative_file);
    for (const auto& name : table.names()) (void)table.channel(name);
  } catch (const chatterlab::InputError&) {
  }
  return 0;
}
