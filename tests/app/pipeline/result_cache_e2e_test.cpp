// The per-test cache seen from a report (app/pipeline/pipeline.h ResultCache): a campaign
// reported once keeps the results of its cacheable tests; reported again with them, those tests
// are restored, not computed, and the report is the same (tests/support/result_cache.h).
#include <gtest/gtest.h>

#include "render/temp_dir.h"
#include "tests/app/nightly/nightly_archive.h"
#include "tests/support/result_cache.h"

namespace chatterlab::app {
namespace {

TEST(ResultCache, RestoredTestsGiveTheSameReport) {
  render::TempDir dir("result-cache");
  chatterlab::testing::write_nightly_archive(dir.path() / "archive", dir.path());
  chatterlab::testing::expect_restored_report_equal(
      dir.path() / "archive" / "a", dir.path(),
      {"tap/x", "tap/y", "dyno/f050", "dyno/f100", "dyno/f150", "group:dyno-slot", "cuts/constant",
       "group:lobes"});
}

}  // namespace
}  // namespace chatterlab::app
