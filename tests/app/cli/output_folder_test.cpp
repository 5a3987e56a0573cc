// The --out folder (docs/cli.md#the-output-folder): a non-empty folder that is not chatterlab's,
// a symbolic link or the current folder is refused untouched; the output is written into a new
// temporary folder beside --out that replaces it on commit (the previous output gone, the
// user's files carried over, nothing outside the folder touched, links never followed); until
// then --out is as it was; a lock keeps a second run off; every write is checked.
#include "app/cli/output_folder.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "analysis/common/summary.h"
#include "tests/support/output_files.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::Files;
using chatterlab::testing::manifest_lines;
using chatterlab::testing::names_in;
using chatterlab::testing::TempDir;

std::string text_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

template <typename F>
std::string input_error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST(OutputFolder, AnAbsentFolderIsWrittenBesideAndMovedIntoPlace) {
  TempDir d;
  const fs::path out = d.path() / "sub" / "new";
  {
    OutputFolder f(out.string() + "/");
    EXPECT_EQ(f.dir(), out);
    EXPECT_EQ(f.work().parent_path(), d.path() / "sub");
    EXPECT_EQ(f.work().filename().string().rfind(".new.chatterlab-tmp-", 0), 0u) << f.work();
    EXPECT_TRUE(fs::is_directory(f.work()));
    EXPECT_TRUE(fs::is_empty(f.work()));
    EXPECT_FALSE(fs::exists(out));  // nothing there until commit
    std::ofstream(f.work() / "index.html") << "new";
    EXPECT_EQ(f.commit(), 0);
  }
  EXPECT_EQ(files_below(out), (Files{".chatterlab-files", "index.html"}));
  EXPECT_EQ(manifest_lines(out), (Files{"index.html"}));
  // Beside it only the lock file.
  EXPECT_EQ(names_in(d.path() / "sub"), (Files{".new.chatterlab-lock", "new"}));
}

TEST(OutputFolder, WithoutCommitThePreviousOutputStaysAndTheTemporaryFolderGoes) {
  TempDir d;
  d.write("out/.chatterlab-files", "# header\nindex.html\n");
  d.write("out/index.html", "old");
  {
    OutputFolder f(d.path() / "out");
    std::ofstream(f.work() / "index.html") << "half";
  }
  EXPECT_EQ(text_of(d.path() / "out/index.html"), "old");
  EXPECT_EQ(names_in(d.path()), (Files{".out.chatterlab-lock", "out"}));
}

TEST(OutputFolder, RefusesAForeignFolderAndTouchesNothing) {
  TempDir d;
  d.write("mine/results.json", "{\"format\": \"someone-else/1\"}\n");
  d.write("mine/figures/plot.svg", "<svg/>");
  const std::string e = input_error_of([&] { OutputFolder f(d.path() / "mine"); });
  EXPECT_NE(e.find("is not a chatterlab output folder"), std::string::npos) << e;
  EXPECT_EQ(files_below(d.path() / "mine"), (Files{"figures/plot.svg", "results.json"}));
}

TEST(OutputFolder, RefusesALinkAndTheCurrentFolder) {
  TempDir d;
  d.write("real/.chatterlab-files", "# header\nindex.html\n");
  d.write("real/index.html", "old");
  fs::create_directory_symlink(d.path() / "real", d.path() / "link");
  const std::string e = input_error_of([&] { OutputFolder f(d.path() / "link"); });
  EXPECT_NE(e.find("is a symbolic link"), std::string::npos) << e;
  EXPECT_EQ(files_below(d.path() / "real"), (Files{".chatterlab-files", "index.html"}));

  const fs::path cwd = fs::current_path();
  fs::current_path(d.path() / "real");
  const std::string dot = input_error_of([&] { OutputFolder f("."); });
  const std::string up = input_error_of([&] { OutputFolder f(d.path()); });
  fs::current_path(cwd);
  EXPECT_NE(dot.find("--out .: is the current folder or holds it"), std::string::npos) << dot;
  EXPECT_NE(up.find("is the current folder or holds it"), std::string::npos) << up;
}

TEST(OutputFolder, CommitReplacesThePreviousOutputAndKeepsTheUsersFiles) {
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
  d.write("out/deep/er/own.txt", "the user's");
  fs::permissions(d.path() / "out", fs::perms(0750));
  {
    OutputFolder f(d.path() / "out");
    EXPECT_EQ(fs::status(f.work()).permissions() & fs::perms::all, fs::perms(0750));
    d.write(fs::relative(f.work(), d.path()).string() + "/index.html", "new");
    d.write(fs::relative(f.work(), d.path()).string() + "/figures/tap-y.svg", "new");
    d.write(fs::relative(f.work(), d.path()).string() + "/figures/mine.svg", "the run's");
    // The previous output is untouched until commit.
    EXPECT_EQ(text_of(d.path() / "out/index.html"), "old");
    EXPECT_EQ(f.commit(), 2);  // notes.txt and deep/er/own.txt
  }
  const fs::path out = d.path() / "out";
  EXPECT_EQ(files_below(out), (Files{".chatterlab-files", "deep/er/own.txt", "figures/mine.svg",
                                     "figures/tap-y.svg", "index.html", "notes.txt"}));
  EXPECT_EQ(text_of(out / "index.html"), "new");
  EXPECT_EQ(text_of(out / "notes.txt"), "the user's");
  EXPECT_EQ(text_of(out / "figures/mine.svg"), "the run's");  // the new output's file wins
  // The manifest lists what the run wrote, not the user's files.
  EXPECT_EQ(manifest_lines(out), (Files{"figures/mine.svg", "figures/tap-y.svg", "index.html"}));
  EXPECT_EQ(names_in(d.path()), (Files{".out.chatterlab-lock", "out"}));
}

TEST(OutputFolder, NeverLeavesTheFolderNorFollowsALink) {
  TempDir d;
  d.write("outside.txt", "keep");
  d.write("elsewhere/secret.txt", "keep");
  d.write("out/.chatterlab-files",
          "../outside.txt\n" + (d.path() / "outside.txt").string() +
              "\nfigures/../../outside.txt\nlinked/secret.txt\nchatterlabs-link\n.\n\n");
  fs::create_directory_symlink(d.path() / "elsewhere", d.path() / "out/linked");
  fs::create_symlink(d.path() / "outside.txt", d.path() / "out/link-to-file");
  fs::create_symlink(d.path() / "outside.txt", d.path() / "out/chatterlabs-link");
  {
    OutputFolder f(d.path() / "out");
    std::ofstream(f.work() / "index.html") << "new";
    f.commit();
  }
  EXPECT_EQ(text_of(d.path() / "outside.txt"), "keep");
  EXPECT_EQ(text_of(d.path() / "elsewhere/secret.txt"), "keep");
  // The user's links are carried as links; the listed one is gone.
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(d.path() / "out/linked")));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(d.path() / "out/link-to-file")));
  EXPECT_FALSE(fs::exists(fs::symlink_status(d.path() / "out/chatterlabs-link")));
  EXPECT_EQ(files_below(d.path() / "elsewhere"), (Files{"secret.txt"}));
}

// A folder from a version without manifests: the known names, figures/ and the files its
// results.json names are the program's; the rest is carried.
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
  EXPECT_EQ(chatterlab_files(d.path() / "out"),
            (Files{".chatterlab-files", "figures/a/b.png", "index.html", "report.css", "report.pdf",
                   "results.json", "s/compensated.csv"}));
  {
    OutputFolder f(d.path() / "out");
    EXPECT_EQ(f.commit(), 2);
  }
  EXPECT_EQ(files_below(d.path() / "out"),
            (Files{".chatterlab-files", "notes.txt", "s/readme.txt"}));
  EXPECT_EQ(text_of(d.path() / "outside.txt"), "keep");
}

TEST(OutputFolder, ASecondRunOnTheFolderIsRefusedWhileTheFirstHoldsTheLock) {
  TempDir d;
  const fs::path out = d.path() / "out";
  {
    OutputFolder first(out);
    const std::string e = input_error_of([&] { OutputFolder second(out); });
    EXPECT_NE(e.find("--out " + out.string() + ": another chatterlab run is writing this folder"),
              std::string::npos)
        << e;
    EXPECT_TRUE(fs::is_directory(first.work()));  // the second run did not remove it
  }
  OutputFolder again(out);  // released
  again.commit();
  EXPECT_TRUE(fs::is_directory(out));
}

TEST(OutputFolder, TemporaryFoldersOfKilledRunsAreRemoved) {
  TempDir d;
  d.write(".out.chatterlab-tmp-1-dead/index.html", "half");
  d.write(".out.chatterlab-tmp-2-dead/figures/a.svg", "half");
  d.write(".other.chatterlab-tmp-3-dead/index.html", "another folder's run");
  d.write("elsewhere/keep.txt", "keep");
  fs::create_directory_symlink(d.path() / "elsewhere", d.path() / ".out.chatterlab-tmp-4-link");
  OutputFolder f(d.path() / "out");
  f.commit();
  EXPECT_EQ(names_in(d.path()), (Files{".other.chatterlab-tmp-3-dead", ".out.chatterlab-lock",
                                       ".out.chatterlab-tmp-4-link", "elsewhere", "out"}));
  EXPECT_EQ(text_of(d.path() / "elsewhere/keep.txt"), "keep");
}

TEST(WriteFileChecked, WritesAndFailsNamingTheFile) {
  TempDir d;
  write_file_checked(d.path() / "a.txt", "hello\n");
  EXPECT_EQ(text_of(d.path() / "a.txt"), "hello\n");
  write_file_checked(d.path() / "a.txt", "hi\n");  // truncated
  EXPECT_EQ(text_of(d.path() / "a.txt"), "hi\n");
  // A full device: the write fails (ENOSPC).
  if (fs::exists("/dev/full")) {
    const std::string e =
        input_error_of([] { write_file_checked("/dev/full", std::string(1 << 16, 'x')); });
    EXPECT_NE(e.find("cannot write /dev/full: "), std::string::npos) << e;
  }
  // No such folder.
  const std::string missing =
      input_error_of([&] { write_file_checked(d.path() / "no/such/x.json", "{}"); });
  EXPECT_NE(missing.find("cannot write " + (d.path() / "no/such/x.json").string()),
            std::string::npos)
      << missing;
  // Never through a link.
  d.write("target.txt", "keep");
  fs::create_symlink(d.path() / "target.txt", d.path() / "link.txt");
  const std::string link =
      input_error_of([&] { write_file_checked(d.path() / "link.txt", "through"); });
  EXPECT_NE(link.find("cannot write "), std::string::npos) << link;
  EXPECT_EQ(text_of(d.path() / "target.txt"), "keep");
}

}  // namespace
}  // namespace chatterlab::app
