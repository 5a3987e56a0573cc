// `chatterlab synth --out` follows the output-folder rules of report and simulate
// (docs/cli.md#the-output-folder): a re-run into a campaign it wrote leaves none of the earlier
// run's files behind, a non-empty folder that is not chatterlab's is refused untouched, and a
// spec that cannot be read changes nothing. `report` refuses --out set to the campaign itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "app/cli/exit_codes.h"
#include "app/cli/output_folder.h"
#include "tests/app/cli/run_binary.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::file_text;
using chatterlab::testing::quoted;
using chatterlab::testing::TempDir;

std::string tap_spec(bool with_y) {
  std::string s =
      "format: chatterlab-synth/1\n"
      "name: synth-out\n"
      "tap:\n"
      "  sample_rate_hz: 5120\n"
      "  hits: 1\n"
      "  hit_spacing_s: 0.3\n"
      "  axes:\n"
      "    x: {modes: [{m_kg: 0.03211, c_kg_s: 13.39, k_N_m: 1.023e6}]}\n";
  if (with_y) s += "    y: {modes: [{m_kg: 0.03211, c_kg_s: 13.39, k_N_m: 1.023e6}]}\n";
  return s;
}

TEST(SynthOut, ReRunLeavesNoStaleFileAndAForeignFolderIsRefused) {
  TempDir d;
  d.write("ab.yaml", tap_spec(true));
  d.write("a.yaml", tap_spec(false));
  const auto run = [&](const std::string& args) {
    return chatterlab::testing::run_chatterlab(args, d.path());
  };
  const fs::path c = d.path() / "c";

  const auto first = run("synth " + quoted(d.path() / "ab.yaml") + " --out " + quoted(c));
  ASSERT_EQ(first.status, kExitOk) << first.err;
  EXPECT_TRUE(fs::exists(c / "tap/y/hits.csv"));
  EXPECT_TRUE(fs::exists(c / "tap/y/test.yaml"));
  const std::string manifest = file_text(c / kManifestName);
  EXPECT_NE(manifest.find("\ntap/y/hits.csv\n"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("\ncampaign.yaml\n"), std::string::npos) << manifest;
  d.write("c/notes.txt", "the user's\n");

  // A spec that cannot be read: exit 1, the earlier campaign as it was.
  d.write("bad.yaml", "format: chatterlab-synth/1\n");
  const auto before_bad = files_below(c);
  const auto bad = run("synth " + quoted(d.path() / "bad.yaml") + " --out " + quoted(c));
  EXPECT_EQ(bad.status, kExitInputError);
  EXPECT_NE(bad.err.find("bad.yaml: key 'name' is missing"), std::string::npos) << bad.err;
  EXPECT_EQ(files_below(c), before_bad);

  // Only test A now: B's folder and files are gone, the user's file stays, and the folder holds
  // what a fresh run writes.
  const auto second = run("synth " + quoted(d.path() / "a.yaml") + " --out " + quoted(c));
  ASSERT_EQ(second.status, kExitOk) << second.err;
  EXPECT_FALSE(fs::exists(c / "tap/y"));
  EXPECT_TRUE(fs::exists(c / "tap/x/hits.csv"));
  EXPECT_EQ(file_text(c / "notes.txt"), "the user's\n");
  EXPECT_EQ(file_text(c / "truth.yaml").find("tap/y"), std::string::npos);
  const auto fresh =
      run("synth " + quoted(d.path() / "a.yaml") + " --out " + quoted(d.path() / "f"));
  ASSERT_EQ(fresh.status, kExitOk) << fresh.err;
  auto rerun_files = files_below(c);
  rerun_files.erase(std::remove(rerun_files.begin(), rerun_files.end(), "notes.txt"),
                    rerun_files.end());
  EXPECT_EQ(rerun_files, files_below(d.path() / "f"));
  EXPECT_EQ(file_text(c / "tap/x/hits.csv"), file_text(d.path() / "f/tap/x/hits.csv"));

  // A folder that is not chatterlab's: refused, nothing touched.
  d.write("thesis/chapter1.tex", "keep me\n");
  const auto foreign =
      run("synth " + quoted(d.path() / "a.yaml") + " --out " + quoted(d.path() / "thesis"));
  EXPECT_EQ(foreign.status, kExitInputError);
  EXPECT_NE(foreign.err.find("the folder is not empty and is not a chatterlab output folder"),
            std::string::npos)
      << foreign.err;
  EXPECT_EQ(files_below(d.path() / "thesis"), std::vector<std::string>{"chapter1.tex"});

  // report into the campaign it reads would clear the campaign: refused.
  const auto into = run("report " + quoted(c) + " --out " + quoted(c) + " --no-pdf --quiet");
  EXPECT_EQ(into.status, kExitInputError);
  EXPECT_NE(into.err.find("is the campaign folder or holds it"), std::string::npos) << into.err;
  EXPECT_TRUE(fs::exists(c / "tap/x/hits.csv"));
}

}  // namespace
}  // namespace chatterlab::app
