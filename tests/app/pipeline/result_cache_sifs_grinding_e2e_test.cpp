// The per-test cache for kinds sifs-static, sifs-tap, sifs-cut (and their groups sifs-static,
// sifs-cut) and grinding: a small synthetic campaign reported once keeps every one of their
// results; reported again with them, each is restored and the report is the same
// (tests/support/result_cache.h).
#include <gtest/gtest.h>

#include "app/synth/synth.h"
#include "tests/support/result_cache.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::TempDir;

TEST(ResultCacheSifs, RestoredSifsTestsAndGroupsGiveTheSameReport) {
  TempDir dir;
  const char* spec =
      "format: chatterlab-synth/1\n"
      "name: cache-sifs\n"
      "seed: 9\n"
      "tool: {teeth: 4, radius_mm: 9.525}\n"
      "sifs:\n"
      "  cuts: {rpm: [9000], duration_s: 2.6}\n";
  synthesize_campaign(dir.write("spec.yaml", spec), dir.path() / "campaign");
  chatterlab::testing::expect_restored_report_equal(
      dir.path() / "campaign", dir.path(),
      {"sifs/static-x", "sifs/static-y", "sifs/static-z", "group:sifs-static", "sifs/tap-x",
       "sifs/tap-y", "sifs/cut-n09000", "group:sifs-cut"});
}

TEST(ResultCacheGrinding, RestoredGrindingTestGivesTheSameReport) {
  TempDir dir;
  const char* spec =
      "format: chatterlab-synth/1\n"
      "name: cache-grinding\n"
      "seed: 11\n"
      "grinding:\n"
      "  schedule: [{u_mm_s: 0.0254, rows: 30}, {u_mm_s: 0.002, rows: 10}, {u_mm_s: 0, rows: 10}]\n"
      "  tests:\n"
      "    - name: series-a\n"
      "      cycles: 8\n"
      "      late: [[3, 5]]\n"
      "      dressings: [{before_cycle: 6, depth_mm: 0.040, true_depth_mm: 0.0412}]\n";
  synthesize_campaign(dir.write("spec.yaml", spec), dir.path() / "campaign");
  chatterlab::testing::expect_restored_report_equal(dir.path() / "campaign", dir.path(),
                                                    {"grinding/series-a"});
}

}  // namespace
}  // namespace chatterlab::app
