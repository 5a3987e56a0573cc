// The per-test cache (tests/support/result_cache.h) on the forcerec and sysid kinds: a small
// synthetic campaign of dyno-frf tests (one of them a drifted first pass, so that the force
// record also reconstructs with an other model), a force-record cut, an frf test (synth section
// `era`), a sweep-frf test and a spindle-current cut, reported once computing every test and
// once restoring them all; the two reports are the same.
#include <gtest/gtest.h>

#include "app/synth/synth.h"
#include "tests/support/result_cache.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

const char* kSpec =
    "format: chatterlab-synth/1\n"
    "name: result-cache-forcerec-sysid\n"
    "seed: 7\n"
    "tool: {teeth: 2, radius_mm: 6.35, helix_deg: 30}\n"
    "forcerec:\n"
    "  axes: [x]\n"
    "  hits: 3\n"
    "  cuts:\n"
    "    duration_s: 1.2\n"
    "    air_s: 0.4\n"
    "    drift: {fn_scale: 0.97}\n"
    "    list:\n"
    "      - {name: resonant, spindle_rpm: 15345, operation: down-milling, axial_depth_mm: 0.5,\n"
    "         radial_immersion_mm: 6.35, feed_per_tooth_mm: 0.0326}\n"
    "spindle:\n"
    "  cuts: {rpm: [5000], feed_per_tooth_mm: 0.1}\n"
    "era:\n"
    "  systems:\n"
    "    - {name: sys, order: 8, snr_db: 30}\n";

TEST(ResultCacheForcerecSysid, RestoredTestsGiveTheSameReport) {
  chatterlab::testing::TempDir dir;
  const auto campaign = dir.path() / "campaign";
  synthesize_campaign(dir.write("spec.yaml", kSpec), campaign);
  chatterlab::testing::expect_restored_report_equal(
      campaign, dir.path(),
      {"forcerec/hammer/x", "forcerec/hammer-before/x", "forcerec/cuts/resonant", "era/sys",
       "spindle/sweep", "spindle/cut-n05000"});
}

}  // namespace
}  // namespace chatterlab::app
