// The --out folder: a non-empty folder that is not chatterlab's is refused untouched; the
// previous run's files (the manifest's, or for an older folder the known names and what its
// results.json names) are removed, nothing else: not the user's files, nothing outside the
// folder, not through a symbolic link.
#include "app/cli/output_folder.h"

#include <gtest/gtest.h>

#include <fstream>

#include "analysis/common/summary.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::TempDir;
using Files = std::vector<std::string>;

TEST(OutputFolder, AbsentOrEmptyFoldersAreFine) {
  TempDir d;
  OutputFolder absent = OutputFolder::open(d.path() / "new");
  EXPECT_EQ(absent.clear_previous(), 0);
  fs::create_directories(d.path() / "empty");
  OutputFolder empty = OutputFolder::open(d.path() / "empty/");
  EXPECT_EQ(empty.clear_previous(), 0);
  d.write("empty/index.html", "new");
  empty.write_manifest();
  EXPECT_EQ(files_below(d.path() / "empty"), (Files{".chatterlab-files", "index.html"}));
}

TEST(OutputFolder, RefusesAForeignFolderAndTouchesNothing) {
  TempDir d;
  d.write("mine/results.json", "{\"format\": \"someone-else/1\"}\n");
  d.write("mine/figures/plot.svg", "<svg/>");
  try {
    OutputFolder::open(d.path() / "mine");
    FAIL() << "not refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is not a chatterlab output folder"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(files_below(d.path() / "mine"), (Files{"figures/plot.svg", "results.json"}));
}

TEST(OutputFolder, RemovesTheManifestsFilesAndTheFoldersItEmpties) {
  TempDir d;
  d.write("out/.chatterlab-files",
          "# header\nindex.html\nfigures/tap-x.svg\nsifs/cut/compensated.csv\nreport.pdf\n"
          "gone-already.txt\n");
  d.write("out/index.html", "old");
  d.write("out/figures/tap-x.svg", "old");
  d.write("out/figures/mine.svg", "the user's");
  d.write("out/sifs/cut/compensated.csv", "old");
  d.write("out/report.pdf", "old");
  d.write("out/notes.txt", "the user's");
  OutputFolder f = OutputFolder::open(d.path() / "out");
  EXPECT_EQ(f.clear_previous(), 4);
  EXPECT_EQ(files_below(d.path() / "out"), (Files{"figures/mine.svg", "notes.txt"}));
  EXPECT_FALSE(fs::exists(d.path() / "out/sifs"));  // emptied, removed
  // The new run's files are listed; the user's untouched files are not; a user file the run
  // overwrote is the run's now.
  d.write("out/index.html", "new");
  d.write("out/figures/tap-y.svg", "new");
  d.write("out/figures/mine.svg", "overwritten by the run, longer");
  f.write_manifest();
  std::ifstream in(d.path() / "out/.chatterlab-files");
  std::string line;
  Files listed;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#') listed.push_back(line);
  }
  EXPECT_EQ(listed, (Files{"figures/mine.svg", "figures/tap-y.svg", "index.html"}));
}

TEST(OutputFolder, NeverLeavesTheFolder) {
  TempDir d;
  d.write("outside.txt", "keep");
  d.write("elsewhere/secret.txt", "keep");
  d.write("out/.chatterlab-files",
          "../outside.txt\n" + (d.path() / "outside.txt").string() +
              "\nfigures/../../outside.txt\nlinked/secret.txt\nlink-to-file\n.\n\n");
  fs::create_directory_symlink(d.path() / "elsewhere", d.path() / "out/linked");
  fs::create_symlink(d.path() / "outside.txt", d.path() / "out/link-to-file");
  OutputFolder f = OutputFolder::open(d.path() / "out");
  EXPECT_EQ(f.clear_previous(), 1);  // the link itself, not its target
  EXPECT_TRUE(fs::exists(d.path() / "outside.txt"));
  EXPECT_TRUE(fs::exists(d.path() / "elsewhere/secret.txt"));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(d.path() / "out/linked")));
  EXPECT_FALSE(fs::exists(fs::symlink_status(d.path() / "out/link-to-file")));
}

// A folder from a version without manifests: the known names, figures/ and the files its
// results.json names go; the rest stays.
TEST(OutputFolder, OlderChatterlabFolder) {
  TempDir d;
  d.write("out/results.json",
          "{\"format\": \"chatterlab-results/1\", \"campaign\": \"c\", \"tests\": {\"s\": "
          "{\"compensated_file\": \"s/compensated.csv\", \"note\": \"../outside.txt\"}}}\n");
  d.write("outside.txt", "keep");
  d.write("out/index.html", "old");
  d.write("out/report.css", "old");
  d.write("out/report.pdf", "old");
  d.write("out/figures/a/b.png", "old");
  d.write("out/s/compensated.csv", "old");
  d.write("out/s/readme.txt", "the user's");
  d.write("out/notes.txt", "the user's");
  OutputFolder f = OutputFolder::open(d.path() / "out");
  EXPECT_EQ(f.clear_previous(), 6);
  EXPECT_EQ(files_below(d.path() / "out"), (Files{"notes.txt", "s/readme.txt"}));
  EXPECT_TRUE(fs::exists(d.path() / "outside.txt"));
}

}  // namespace
}  // namespace chatterlab::app
