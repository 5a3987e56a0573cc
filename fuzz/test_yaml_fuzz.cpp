// load_test on a test.yaml given as input, in a campaign folder with a fixed campaign.yaml and
// a small hits.csv beside the test. InputError is an accepted outcome; anything else surfaces.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "analysis/common/summary.h"
#include "app/core/campaign.h"
#include "fuzz/fuzz_common.h"

namespace {
const char kCampaign[] = "name: fuzz\nmachine: m\ntool: {teeth: 2, radius_mm: 6}\n";
const char kHits[] = "force,response\n0,0\n1,0.5\n0,0.25\n";

void put(const char* name, const char* text) {
  chatterlab::fuzz::write_input(name, reinterpret_cast<const std::uint8_t*>(text),
                                std::strlen(text));
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool once = [] {
    put("c/campaign.yaml", kCampaign);
    put("c/t/hits.csv", kHits);
    return true;
  }();
  (void)once;
  const auto file = chatterlab::fuzz::write_input("c/t/test.yaml", data, size);
  try {
    const auto t = chatterlab::app::load_test(chatterlab::fuzz::temp_dir() / "c", file);
    (void)t;
  } catch (const chatterlab::InputError&) {
  }
  return 0;
}
