// load_campaign on a campaign folder whose campaign.yaml is the input (one fixed tap test
// below it). load_campaign collects problems rather than throwing; InputError is still
// accepted as an outcome, anything else surfaces.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "analysis/common/summary.h"
#include "app/core/campaign.h"
#include "fuzz/fuzz_common.h"

namespace {
const char kTest[] =
    "kind: tap\naxis: x\nsample_rate_hz: 51200\ndata: {file: hits.csv}\n"
    "response: acceleration\nhits: auto\n";
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool once = [] {
    chatterlab::fuzz::write_input("c/tap/x/test.yaml", reinterpret_cast<const std::uint8_t*>(kTest),
                                  std::strlen(kTest));
    return true;
  }();
  (void)once;
  chatterlab::fuzz::write_input("c/campaign.yaml", data, size);
  try {
    const auto c = chatterlab::app::load_campaign(chatterlab::fuzz::temp_dir() / "c");
    (void)c;
  } catch (const chatterlab::InputError&) {
  }
  return 0;
}
