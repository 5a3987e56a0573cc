// The per-test cache seen from a report (app/pipeline/pipeline.h ResultCache): a campaign
// reported once keeps the results of its cacheable tests; reported again with them, those tests
// are restored, not computed, and the report is the same: results.json equal in every number
// but timings, every figure and data file byte for byte.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "app/cli/output_folder.h"
#include "app/nightly/compare.h"
#include "app/report/report.h"
#include "render/temp_dir.h"
#include "tests/app/cli/run_binary.h"
#include "tests/app/nightly/nightly_archive.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;

class MemoryCache : public ResultCache {
 public:
  std::optional<std::string> find(const std::string& name) const override {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = given.find(name);
    if (it == given.end()) return std::nullopt;
    found.push_back(name);
    return it->second;
  }
  void keep(const std::string& name, std::string bytes) override {
    std::lock_guard<std::mutex> lock(mutex_);
    kept[name] = std::move(bytes);
  }
  std::map<std::string, std::string> given, kept;
  mutable std::vector<std::string> found;

 private:
  mutable std::mutex mutex_;
};

int report(const fs::path& campaign, const fs::path& out, MemoryCache& cache) {
  ReportOptions o;
  o.pdf = false;
  o.jobs = 2;
  o.cache = &cache;
  std::ostringstream log;
  o.errors = &log;
  fs::create_directories(out);
  return run_report(campaign, out, o, log);
}

TEST(ResultCache, RestoredTestsGiveTheSameReport) {
  render::TempDir dir("result-cache");
  chatterlab::testing::write_nightly_archive(dir.path() / "archive", dir.path());
  const fs::path campaign = dir.path() / "archive" / "a";
  MemoryCache first;
  ASSERT_EQ(report(campaign, dir.path() / "one", first), 0);
  // The cacheable kinds' tests that succeeded are kept.
  EXPECT_EQ(first.kept.count("tap/x"), 1u);
  EXPECT_EQ(first.kept.count("tap/y"), 1u);
  EXPECT_TRUE(first.found.empty());

  MemoryCache second;
  second.given = first.kept;
  ASSERT_EQ(report(campaign, dir.path() / "two", second), 0);
  std::vector<std::string> found = second.found;
  std::sort(found.begin(), found.end());
  std::vector<std::string> expected;
  for (const auto& [name, bytes] : first.kept) expected.push_back(name);
  EXPECT_EQ(found, expected);
  // Restored tests are not kept again (nothing new was computed for them).
  for (const auto& name : expected) EXPECT_EQ(second.kept.count(name), 0u) << name;

  // results.json: every number equal (rel 0), timings aside.
  CompareOptions exact;
  exact.fallback.rel = 0;
  exact.fallback.abs = 0;
  const Comparison c = compare_results(read_json_file(dir.path() / "one" / "results.json"),
                                       read_json_file(dir.path() / "two" / "results.json"), exact);
  EXPECT_EQ(c.flags(), 0) << comparison_text(c);
  EXPECT_EQ(c.numbers_equal, c.numbers_compared);
  EXPECT_GT(c.numbers_compared, 1000);
  // Every file but the pages that show timings, byte for byte.
  int files = 0;
  for (const auto& f : files_below(dir.path() / "one")) {
    // results.json and results.csv hold the tests' runtimes, index.html shows them.
    if (f == "results.json" || f == "results.csv" || f == "index.html" || f.rfind(".", 0) == 0) {
      continue;
    }
    ++files;
    EXPECT_TRUE(chatterlab::testing::file_text(dir.path() / "one" / f) ==
                chatterlab::testing::file_text(dir.path() / "two" / f))
        << f << " differs";
  }
  EXPECT_GT(files, 10);
}

}  // namespace
}  // namespace chatterlab::app
