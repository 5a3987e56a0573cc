// chatterlab nightly --slurm (app/nightly/slurm.h) against a real Slurm: a one-node cluster on
// loopback (munged, slurmctld and slurmd of Debian's slurm-wlm and munge, started by
// tests/support/slurm_cluster.sh into the test's own folder). The archive of
// nightly_e2e_test runs once in process and once through a job array and its reduce job; the
// two sites must hold the same results (every number but timings), the same statuses and the
// same lists of recomputed tests. A second --slurm run with nothing changed submits no task.
//
// Where the cluster cannot be started (Slurm not installed, no munge), the tests are skipped
// with the reason; with CHATTERLAB_REQUIRE_SLURM=1 (set by .ci/run) they fail instead.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "app/nightly/compare.h"
#include "app/nightly/nightly.h"
#include "render/subprocess.h"
#include "render/temp_dir.h"
#include "tests/app/cli/run_binary.h"
#include "tests/app/nightly/nightly_archive.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

class NightlySlurm : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new render::TempDir("nightly-slurm");
    const fs::path script =
        fs::path(CHATTERLAB_SOURCE_DIR) / "tests" / "support" / "slurm_cluster.sh";
    cluster_ = dir_->path() / "cluster";
    const render::ProcessResult r =
        render::run_process({"bash", script.string(), "start", cluster_.string()});
    if (r.exit_code == 0) {
      ::setenv("SLURM_CONF", (cluster_ / "slurm.conf").c_str(), 1);
      up_ = true;
    } else {
      reason_ = r.err + r.out;
    }
    chatterlab::testing::write_nightly_archive(dir_->path() / "archive", dir_->path());
  }
  static void TearDownTestSuite() {
    if (up_) {
      const fs::path script =
          fs::path(CHATTERLAB_SOURCE_DIR) / "tests" / "support" / "slurm_cluster.sh";
      render::run_process({"bash", script.string(), "stop", cluster_.string()});
    }
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    if (up_) return;
    const char* require = std::getenv("CHATTERLAB_REQUIRE_SLURM");
    if (require != nullptr && std::string(require) == "1") {
      FAIL() << "CHATTERLAB_REQUIRE_SLURM=1 and Slurm could not be started: " << reason_;
    }
    GTEST_SKIP() << "Slurm could not be started on loopback: " << reason_;
  }
  static render::TempDir* dir_;
  static fs::path cluster_;
  static bool up_;
  static std::string reason_;
};
render::TempDir* NightlySlurm::dir_ = nullptr;
fs::path NightlySlurm::cluster_;
bool NightlySlurm::up_ = false;
std::string NightlySlurm::reason_;

TEST_F(NightlySlurm, AJobArrayGivesTheSiteTheLocalRunGives) {
  const fs::path root = dir_->path() / "archive";
  const fs::path local = dir_->path() / "site-local";
  const fs::path slurm = dir_->path() / "site-slurm";
  NightlyOptions o;
  o.pdf = false;
  o.jobs = 1;
  std::ostringstream log;
  o.errors = &log;
  // broken/ cannot be read: exit 1 in both.
  ASSERT_EQ(run_nightly(root, local, o, log), 1) << log.str();
  const auto r = chatterlab::testing::run_chatterlab(
      "nightly " + chatterlab::testing::quoted(root) + " --out " +
          chatterlab::testing::quoted(slurm) + " --no-pdf --jobs 1 --slurm --slurm-wait",
      dir_->path());
  ASSERT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("submitted"), std::string::npos) << r.out;

  // The job scripts are in the site: three tasks (a, b and broken) and the reduce job.
  const std::string array = chatterlab::testing::file_text(slurm / "slurm" / "run-1" / "array.sh");
  EXPECT_NE(array.find("#SBATCH --array=0-2\n"), std::string::npos) << array;
  EXPECT_NE(array.find("#SBATCH --cpus-per-task=1\n"), std::string::npos) << array;
  EXPECT_TRUE(fs::is_regular_file(slurm / "slurm" / "run-1" / "reduce.sh"));

  const json a = read_json(local / "nightly.json");
  const json b = read_json(slurm / "nightly.json");
  ASSERT_EQ(a["campaigns"].size(), 3u);
  ASSERT_EQ(b["campaigns"].size(), a["campaigns"].size());
  for (const auto& [name, c] : a["campaigns"].items()) {
    ASSERT_TRUE(b["campaigns"].contains(name)) << name;
    const json& s = b["campaigns"][name];
    EXPECT_EQ(s["status"], c["status"]) << name;
    EXPECT_EQ(s["recomputed"], c["recomputed"]) << name;
    EXPECT_EQ(s["cached"], c["cached"]) << name;
    EXPECT_EQ(s.contains("results"), c.contains("results")) << name;
    if (!c.contains("results")) continue;
    // Every number equal to rounding (tolerance rel 1e-9, timings ignored: compare's default).
    const Comparison cmp = compare_results(read_json(local / c["results"].get<std::string>()),
                                           read_json(slurm / s["results"].get<std::string>()));
    EXPECT_EQ(cmp.flags(), 0) << name << "\n" << comparison_text(cmp);
    EXPECT_GT(cmp.numbers_compared, 50) << name;
  }
  EXPECT_EQ(b["campaigns"]["nightly-a"]["recomputed"].size(), 6u);
  // The staged report folders went into the site: nothing is left of them.
  EXPECT_FALSE(fs::exists(slurm / "slurm" / "run-1" / "out" / "nightly-a"));

  // Nothing changed: no task is submitted, the reduce job alone records the run.
  const auto again = chatterlab::testing::run_chatterlab(
      "nightly " + chatterlab::testing::quoted(root) + " --out " +
          chatterlab::testing::quoted(slurm) + " --no-pdf --jobs 1 --slurm --slurm-wait",
      dir_->path());
  ASSERT_EQ(again.status, 1) << again.out << again.err;
  EXPECT_FALSE(fs::exists(slurm / "slurm" / "run-2" / "array.sh"));
  EXPECT_TRUE(fs::is_regular_file(slurm / "slurm" / "run-2" / "reduce.sh"));
  const json c = read_json(slurm / "nightly.json");
  EXPECT_TRUE(c["campaigns"]["nightly-a"]["recomputed"].empty());
  EXPECT_EQ(c["campaigns"]["nightly-a"]["cached"].size(), 6u);

  // The program run locally shares the site's cache: after them it recomputes nothing (the
  // binary: the cache keys hold the program's own SHA-256).
  const auto local_after = chatterlab::testing::run_chatterlab(
      "nightly " + chatterlab::testing::quoted(root) + " --out " +
          chatterlab::testing::quoted(slurm) + " --no-pdf --jobs 1",
      dir_->path());
  ASSERT_EQ(local_after.status, 1) << local_after.out << local_after.err;
  const json d = read_json(slurm / "nightly.json");
  EXPECT_TRUE(d["campaigns"]["nightly-a"]["recomputed"].empty());
  EXPECT_EQ(d["campaigns"]["nightly-b"]["cached"].size(), 5u);
}

}  // namespace
}  // namespace chatterlab::app
