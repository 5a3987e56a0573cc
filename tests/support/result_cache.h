// A campaign reported twice through the per-test cache (app/pipeline/pipeline.h ResultCache):
// once computing every test and keeping the cacheable ones, once restoring them. The two
// reports must be the same: results.json equal in every number (rel 0) but timings, every other
// file but the pages that show timings byte for byte.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli/output_folder.h"
#include "app/nightly/compare.h"
#include "app/report/report.h"
#include "tests/app/cli/run_binary.h"

namespace chatterlab::testing {

class MemoryCache : public app::ResultCache {
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

inline int report_with_cache(const std::filesystem::path& campaign,
                             const std::filesystem::path& out, MemoryCache& cache) {
  app::ReportOptions o;
  o.pdf = false;
  o.jobs = 2;
  o.cache = &cache;
  std::ostringstream log;
  o.errors = &log;
  std::filesystem::create_directories(out);
  return app::run_report(campaign, out, o, log);
}

// Reports `campaign` into scratch/computed and scratch/restored; `expected_cached` are the
// nodes (test ids, "group:<name>") that must be kept by the first and restored by the second.
inline void expect_restored_report_equal(const std::filesystem::path& campaign,
                                         const std::filesystem::path& scratch,
                                         std::vector<std::string> expected_cached) {
  namespace fs = std::filesystem;
  MemoryCache first;
  const int rc = report_with_cache(campaign, scratch / "computed", first);
  std::vector<std::string> kept;
  for (const auto& [name, bytes] : first.kept) kept.push_back(name);
  std::sort(expected_cached.begin(), expected_cached.end());
  EXPECT_EQ(kept, expected_cached);
  EXPECT_TRUE(first.found.empty());

  MemoryCache second;
  second.given = first.kept;
  EXPECT_EQ(report_with_cache(campaign, scratch / "restored", second), rc);
  std::vector<std::string> found = second.found;
  std::sort(found.begin(), found.end());
  EXPECT_EQ(found, expected_cached);
  // Restored nodes are not kept again.
  for (const auto& name : expected_cached) EXPECT_EQ(second.kept.count(name), 0u) << name;

  app::CompareOptions exact;
  exact.fallback.rel = 0;
  exact.fallback.abs = 0;
  const app::Comparison c =
      app::compare_results(app::read_json_file(scratch / "computed" / "results.json"),
                           app::read_json_file(scratch / "restored" / "results.json"), exact);
  EXPECT_EQ(c.flags(), 0) << app::comparison_text(c);
  EXPECT_EQ(c.numbers_equal, c.numbers_compared);
  int files = 0;
  for (const auto& f : app::files_below(scratch / "computed")) {
    // results.json and results.csv hold the tests' runtimes, index.html shows them.
    if (f == "results.json" || f == "results.csv" || f == "index.html" || f.rfind(".", 0) == 0) {
      continue;
    }
    ++files;
    EXPECT_TRUE(file_text(scratch / "computed" / f) == file_text(scratch / "restored" / f))
        << f << " differs";
  }
  EXPECT_GT(files, 0);
}

}  // namespace chatterlab::testing
