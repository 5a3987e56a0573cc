// The --out folder as the chatterlab binary uses it (docs/cli.md#the-output-folder, issue 16
// "Output"): a report killed with SIGKILL at a random moment leaves either the previous report
// or the new one, never a mix, and nothing outside --out but the temporary folder and the lock
// beside it; a report whose results.json, or a file of a test, cannot be written fails naming it
// and leaves the previous report as it was; a second run on a locked folder, an --out inside the
// campaign and an --out that is a symbolic link are refused; two tests whose ids give the same
// figure stem get a figure file each.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "app/cli/exit_codes.h"
#include "app/cli/output_folder.h"
#include "tests/app/cli/run_binary.h"
#include "tests/support/output_files.h"
#include "tests/support/synth_spec.h"
#include "tests/support/temp_campaign.h"

extern char** environ;

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::BinaryRun;
using chatterlab::testing::file_text;
using chatterlab::testing::Files;
using chatterlab::testing::manifest_lines;
using chatterlab::testing::names_in;
using chatterlab::testing::quoted;
using chatterlab::testing::TempDir;
using nlohmann::json;

BinaryRun run(const std::string& args, const TempDir& d) {
  return chatterlab::testing::run_chatterlab(args, d.path());
}

// Sets campaign.yaml's `name:` line.
void rename_campaign(const fs::path& campaign, const std::string& name) {
  std::ifstream in(campaign / "campaign.yaml");
  std::string text, line;
  while (std::getline(in, line))
    text += (line.rfind("name:", 0) == 0 ? "name: " + name : line) + "\n";
  in.close();
  std::ofstream(campaign / "campaign.yaml") << text;
}

// `chatterlab report <campaign> --out <out> --quiet` (with --no-pdf unless `pdf`) as a child in
// a process group of its own (its helpers, such as WeasyPrint, are in that group), its streams
// on /dev/null.
pid_t spawn_report(const fs::path& campaign, const fs::path& out, bool pdf) {
  const std::string bin = CHATTERLAB_BINARY, c = campaign.string(), o = out.string();
  std::vector<char*> argv = {const_cast<char*>(bin.c_str()), const_cast<char*>("report"),
                             const_cast<char*>(c.c_str()),   const_cast<char*>("--out"),
                             const_cast<char*>(o.c_str()),   const_cast<char*>("--quiet"),
                             const_cast<char*>("--jobs"),    const_cast<char*>("2")};
  if (!pdf) argv.push_back(const_cast<char*>("--no-pdf"));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attr, 0);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, bin.c_str(), &actions, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  return rc == 0 ? pid : -1;
}

// `chatterlab report <campaign> --out <out> --no-pdf` under a file size limit of `kib` KiB
// (bash's ulimit -f), SIGXFSZ ignored so that a write past it fails with EFBIG; its output in
// stdout.txt and stderr.txt of `d`, the command in run.sh. Returns the exit status.
int report_under_file_limit(const TempDir& d, const fs::path& campaign, const fs::path& out,
                            std::uintmax_t kib) {
  const std::string cmd = "trap '' XFSZ; ulimit -f " + std::to_string(kib) + "; exec " +
                          quoted(CHATTERLAB_BINARY) + " report " + quoted(campaign) + " --out " +
                          quoted(out) + " --no-pdf > " + quoted(d.path() / "stdout.txt") + " 2> " +
                          quoted(d.path() / "stderr.txt");
  std::ofstream(d.path() / "run.sh") << cmd << "\n";
  const int rc = std::system(("bash " + quoted(d.path() / "run.sh")).c_str());
  EXPECT_TRUE(WIFEXITED(rc)) << rc;
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// A first, complete report of `campaign` into `out`: its results.json and files, which a failed
// run after it must leave as they are.
struct Previous {
  std::string results_json;
  Files files;
};
Previous first_report(const TempDir& d, const fs::path& campaign, const fs::path& out) {
  const BinaryRun first =
      run("report " + quoted(campaign) + " --out " + quoted(out) + " --no-pdf --quiet", d);
  EXPECT_EQ(first.status, kExitOk) << first.err;
  return {file_text(out / "results.json"), files_below(out)};
}

// One synth campaign for the suite (2 tap tests, 3 dyno-slot tests, the dyno-slot group).
class CliOut : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    chatterlab::testing::SynthSpecText spec;
    spec.tap_hits = 2;
    spec.dyno_duration_s = 0.5;
    dir_->write("spec.yaml", spec.text());
    const BinaryRun s = chatterlab::testing::run_chatterlab(
        "synth " + quoted(dir_->path() / "spec.yaml") + " --out " + quoted(campaign()) + " --quiet",
        dir_->path());
    ASSERT_EQ(s.status, 0) << s.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path campaign() { return dir_->path() / "campaign"; }
  // A copy of the campaign in `d`, to change.
  static fs::path copy_campaign(const TempDir& d) {
    const fs::path c = d.path() / "campaign";
    fs::copy(campaign(), c, fs::copy_options::recursive);
    fs::remove(c / kManifestName);
    return c;
  }

  static TempDir* dir_;
};
TempDir* CliOut::dir_ = nullptr;

// How a report is killed in KillReportsAtRandomMoments.
struct KillPlan {
  bool pdf = false;         // the report writes report.pdf (WeasyPrint, a child process)
  bool whole_group = true;  // SIGKILL to the report's process group, else to its process only
  int kills = 8;            // runs killed, each after a delay drawn from the seed
  std::uint32_t seed = 20261202;
  // Every second kill waits for the run's WeasyPrint to start (its .print.html in the run's
  // temporary folder) and lands a delay of up to 0.3 times the first run's time after it, so
  // that kills land in the PDF's writing however long the runs take.
  bool every_second_in_pdf = false;
};

// What KillReportsAtRandomMoments saw, for the test to assert and print.
struct KillCounts {
  double first_run_s = 0;
  int kept_previous = 0;   // kills after which --out held the previous report
  int got_new = 0;         // kills after which it held the new one (the run had committed)
  int killed_writing = 0;  // kills that left a temporary folder beside --out (a run under way)
  int killed_in_pdf = 0;   // of those, kills while WeasyPrint was writing (.print.html there)
};

// Reports a copy of the campaign into an --out holding a file of the user's, then starts
// `plan.kills` reports of the campaign under a new name each and kills each one after a random
// delay of 0.3 to 1.3 times the first run's time; after each kill, --out must be the previous
// report or the new one, whole (the manifest's files and nothing else, results.json and
// index.html naming the same campaign), the user's file kept, nothing beside --out but the lock
// and temporary folders, the campaign unchanged. When only the report's process is killed, its
// helpers (WeasyPrint) may outlive it: --out is checked again once they are killed too. A last
// run to its end must clear the temporary folders.
KillCounts KillReportsAtRandomMoments(const KillPlan& plan, const fs::path& campaign_copy,
                                      const fs::path& out) {
  const fs::path& c = campaign_copy;
  const fs::path beside = out.parent_path();  // nothing else in it
  const Files campaign_files = files_below(c);
  const std::string pdf_arg = plan.pdf ? "" : " --no-pdf";
  KillCounts n;

  rename_campaign(c, "kill-0");
  const auto t0 = std::chrono::steady_clock::now();
  const BinaryRun first = chatterlab::testing::run_chatterlab(
      "report " + quoted(c) + " --out " + quoted(out) + pdf_arg + " --quiet --jobs 2",
      c.parent_path());
  n.first_run_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(first.status, kExitOk) << first.err;
  if (first.status != kExitOk) return n;
  EXPECT_EQ(fs::exists(out / "report.pdf"), plan.pdf);
  std::ofstream(out / "notes.txt") << "the user's\n";
  std::string previous_json = file_text(out / "results.json");
  std::string previous_name = "kill-0";
  Files previous_files = files_below(out);

  // --out after a kill: the previous report or the new one, whole.
  const auto check_out = [&](const std::string& name, bool update) {
    EXPECT_TRUE(fs::is_directory(fs::symlink_status(out)));
    EXPECT_EQ(file_text(out / "notes.txt"), "the user's\n");
    Files files = files_below(out);
    // Every file of the manifest present, and nothing else but the manifest and the user's.
    Files expected = manifest_lines(out);
    expected.push_back(kManifestName);
    expected.push_back("notes.txt");
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(files, expected);
    EXPECT_EQ(fs::exists(out / "report.pdf"), plan.pdf);
    const std::string results = file_text(out / "results.json");
    const std::string index = file_text(out / "index.html");
    if (results == previous_json) {
      if (update) ++n.kept_previous;
      EXPECT_EQ(files, previous_files);
      EXPECT_NE(index.find(previous_name), std::string::npos);
    } else {
      EXPECT_TRUE(update) << "--out changed after the kill, while the report's helpers ran on";
      ++n.got_new;
      const json j = json::parse(results);
      EXPECT_EQ(j.value("campaign", ""), name);
      EXPECT_NE(index.find(name), std::string::npos);
      EXPECT_EQ(index.find(previous_name), std::string::npos);
      previous_json = results;
      previous_name = name;
      previous_files = files;
    }
  };

  std::mt19937 rng(plan.seed);
  std::uniform_real_distribution<double> delay(0.3 * n.first_run_s, 1.3 * n.first_run_s);
  const std::string out_name = out.filename().string();
  for (int i = 1; i <= plan.kills; ++i) {
    SCOPED_TRACE("kill " + std::to_string(i));
    const std::string name = "kill-" + std::to_string(i);
    rename_campaign(c, name);
    // This run's temporary folder is one not beside --out before it starts (an earlier killed
    // run's stays until this one removes it).
    const Files before = names_in(beside);
    const std::string temp_prefix = "." + out_name + ".chatterlab-tmp-";
    const auto this_runs_temp = [&](const std::string& t) {
      return t.rfind(temp_prefix, 0) == 0 &&
             std::find(before.begin(), before.end(), t) == before.end();
    };
    const pid_t pid = spawn_report(c, out, plan.pdf);
    EXPECT_GT(pid, 0);
    if (pid <= 0) return n;
    const double wait_s = delay(rng);  // drawn for every kill, so the sequence stays the seed's
    if (plan.every_second_in_pdf && i % 2 == 0) {
      bool printing = false;
      const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
      while (!printing && std::chrono::steady_clock::now() < until) {
        for (const auto& t : names_in(beside)) {
          printing = printing || (this_runs_temp(t) && fs::exists(beside / t / ".print.html"));
        }
        if (!printing) std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
      EXPECT_TRUE(printing) << "the run's WeasyPrint did not start within 120 s";
      std::this_thread::sleep_for(
          std::chrono::duration<double>((wait_s / n.first_run_s - 0.3) * 0.3 * n.first_run_s));
    } else {
      std::this_thread::sleep_for(std::chrono::duration<double>(wait_s));
    }
    ::kill(plan.whole_group ? -pid : pid, SIGKILL);
    // Waited for but not reaped until the end of this kill's checks, so that its process group
    // id stays its own while its helpers are killed below.
    siginfo_t ended{};
    EXPECT_EQ(::waitid(P_PID, static_cast<id_t>(pid), &ended, WEXITED | WNOWAIT), 0);

    // Beside --out: only the lock and temporary folders, which the next run removes.
    bool left_temp = false, in_pdf = false;
    for (const auto& t : names_in(beside)) {
      const bool temp = t.rfind(temp_prefix, 0) == 0;
      left_temp = left_temp || this_runs_temp(t);
      in_pdf = in_pdf || (this_runs_temp(t) && fs::exists(beside / t / ".print.html"));
      EXPECT_TRUE(t == out_name || t == "." + out_name + ".chatterlab-lock" || temp) << t;
    }
    check_out(name, true);
    if (!plan.whole_group) {
      // The helpers of the killed report, if any still run, end now; --out is as it was.
      ::kill(-pid, SIGKILL);
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      check_out(name, false);
    }
    int status = 0;
    EXPECT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_EQ(files_below(c), campaign_files);  // nothing written into the campaign
    if (left_temp) ++n.killed_writing;
    if (in_pdf) ++n.killed_in_pdf;
  }

  // A run to its end: the stale temporary folders are gone, the report is the new one.
  rename_campaign(c, "kill-end");
  const BinaryRun last = chatterlab::testing::run_chatterlab(
      "report " + quoted(c) + " --out " + quoted(out) + pdf_arg + " --quiet --jobs 2",
      c.parent_path());
  EXPECT_EQ(last.status, kExitOk) << last.err;
  EXPECT_EQ(names_in(beside), (Files{"." + out_name + ".chatterlab-lock", out_name}));
  EXPECT_EQ(json::parse(file_text(out / "results.json")).value("campaign", ""), "kill-end");
  EXPECT_EQ(file_text(out / "notes.txt"), "the user's\n");
  return n;
}

TEST_F(CliOut, KilledReportLeavesThePreviousOrTheNewOneNeverAMix) {
  TempDir src, dst;  // the campaign, and the parent of --out
  const KillCounts n =
      KillReportsAtRandomMoments(KillPlan{}, copy_campaign(src), dst.path() / "out");
  std::cout << "SIGKILL: one run " << n.first_run_s << " s; " << n.kept_previous
            << " kills left the previous report, " << n.got_new << " the new one; "
            << n.killed_writing << " left a temporary folder beside --out\n";
  // At least one kill landed while the run was under way (its temporary folder left behind).
  // The delays come from a fixed seed: 1.04, 1.22, 0.59, 0.36, 1.01, 0.85, 0.99 and 0.51 of
  // the first run's time; all eight miss only if the runs took under 36 % of the first.
  EXPECT_GE(n.killed_writing, 1);
}

// The report as users run it, with its PDF, killed as `kill -9 <pid>` kills it: the report's
// process only, while WeasyPrint, its child, may go on writing report.pdf into the report's
// temporary folder. --out is the previous report or the new one, with its PDF, and stays so once
// WeasyPrint is killed as well. Every second kill lands while WeasyPrint writes.
TEST_F(CliOut, KilledReportWithItsPdfLeavesThePreviousOrTheNewOne) {
  TempDir src, dst;
  KillPlan plan;
  plan.pdf = true;
  plan.whole_group = false;
  plan.kills = 6;
  plan.seed = 20261205;
  plan.every_second_in_pdf = true;
  const KillCounts n = KillReportsAtRandomMoments(plan, copy_campaign(src), dst.path() / "out");
  std::cout << "SIGKILL with the PDF: one run " << n.first_run_s << " s; " << n.kept_previous
            << " kills left the previous report, " << n.got_new << " the new one; "
            << n.killed_writing << " left a temporary folder beside --out, " << n.killed_in_pdf
            << " while WeasyPrint was writing\n";
  EXPECT_GE(n.killed_writing, 1);
  EXPECT_GE(n.killed_in_pdf, 1);
}

// results.json that cannot be written (a file size limit, SIGXFSZ ignored: the write fails with
// EFBIG): exit 1 naming the file under --out, nothing said to be written, the previous report
// as it was, no temporary folder left.
TEST_F(CliOut, AFailedWriteLeavesThePreviousReport) {
  TempDir d;
  // The dyno-slot tests only: the tap tests' own files (frf.csv, 2 MB) come before results.json
  // and would fail first (AFileCutByTheLastBufferedWriteFailsTheRun).
  const fs::path c = copy_campaign(d);
  fs::remove_all(c / "tap");
  const fs::path out = d.path() / "o";
  const Previous before = first_report(d, c, out);
  ASSERT_GT(before.results_json.size(), 4096u);

  EXPECT_EQ(report_under_file_limit(d, c, out, 4), kExitInputError);
  const std::string err = file_text(d.path() / "stderr.txt");
  EXPECT_NE(err.find("chatterlab report: cannot write " + (out / "results.json").string() + ": "),
            std::string::npos)
      << err;
  EXPECT_EQ(file_text(d.path() / "stdout.txt").find("wrote"), std::string::npos);
  EXPECT_EQ(file_text(out / "results.json"), before.results_json);
  EXPECT_EQ(files_below(out), before.files);
  EXPECT_EQ(names_in(d.path()),
            (Files{".o.chatterlab-lock", "campaign", "o", "run.sh", "stderr.txt", "stdout.txt"}));
}

// A test's own file that cannot be written whole (tap/x/frf.csv, the largest file of the report,
// under a file size limit of a whole number of the stream's 8 KiB blocks, below the file's
// size: the stream writes its last, partial block only when it is closed): exit 1 naming the file,
// nothing said to be written, the previous report as it was. Before the stream was checked after
// its close, the run ended "ok" with the file cut at the limit.
TEST_F(CliOut, AFileCutByTheLastBufferedWriteFailsTheRun) {
  TempDir d;
  const fs::path out = d.path() / "o";
  const Previous before = first_report(d, campaign(), out);
  const fs::path frf = out / "tap" / "x" / "frf.csv";
  const std::uintmax_t size = fs::file_size(frf);
  const std::uintmax_t limit = size / 8192 * 8192;  // whole blocks of the stream's 8 KiB buffer
  ASSERT_GT(size, limit);
  std::uintmax_t others = 0;  // every other file must fit under the limit
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    if (e.is_regular_file() && e.path() != frf) others = std::max(others, e.file_size());
  }
  ASSERT_LT(others, limit);

  EXPECT_EQ(report_under_file_limit(d, campaign(), out, limit / 1024), kExitInputError);
  const std::string err = file_text(d.path() / "stderr.txt");
  EXPECT_NE(err.find("chatterlab report: cannot write " + frf.string() + ": File too large"),
            std::string::npos)
      << err;
  EXPECT_EQ(file_text(d.path() / "stdout.txt").find("wrote"), std::string::npos);
  EXPECT_EQ(file_text(out / "results.json"), before.results_json);
  EXPECT_EQ(files_below(out), before.files);
  EXPECT_EQ(fs::file_size(frf), size);
}

// A campaign or spec that cannot be read: exit 1, the previous output as it was, no temporary
// folder left beside it.
TEST_F(CliOut, AnUnreadableCampaignOrSpecLeavesThePreviousOutput) {
  TempDir d;
  const fs::path out = d.path() / "o";
  const Previous previous = first_report(d, campaign(), out);
  const std::string& before = previous.results_json;
  const Files& before_files = previous.files;
  fs::create_directories(d.path() / "nothing");
  const BinaryRun none =
      run("report " + quoted(d.path() / "nothing") + " --out " + quoted(out) + " --no-pdf", d);
  EXPECT_EQ(none.status, kExitInputError);
  d.write("bad.yaml", "format: chatterlab-simulation/1\n");
  const BinaryRun sim =
      run("simulate " + quoted(d.path() / "bad.yaml") + " --out " + quoted(out), d);
  EXPECT_EQ(sim.status, kExitInputError);
  d.write("bad-synth.yaml", "format: chatterlab-synth/1\n");
  const BinaryRun syn =
      run("synth " + quoted(d.path() / "bad-synth.yaml") + " --out " + quoted(out), d);
  EXPECT_EQ(syn.status, kExitInputError);
  EXPECT_EQ(file_text(out / "results.json"), before);
  EXPECT_EQ(files_below(out), before_files);
  EXPECT_EQ(names_in(d.path()), (Files{".o.chatterlab-lock", "bad-synth.yaml", "bad.yaml",
                                       "nothing", "o", "stderr.txt", "stdout.txt"}));
}

// A user's file that cannot be carried into the new output (a folder of that name is where
// the new report writes a file): the run fails before the exchange, does not say it wrote the
// report, and leaves the previous one.
TEST_F(CliOut, AFailedExchangeIsNotReportedAsWritten) {
  TempDir d;
  const fs::path out = d.path() / "o";
  const BinaryRun first =
      run("report " + quoted(campaign()) + " --out " + quoted(out) + " --no-pdf --quiet", d);
  ASSERT_EQ(first.status, kExitOk) << first.err;
  const std::string before = file_text(out / "results.json");
  fs::remove(out / "results.csv");
  d.write("o/results.csv/mine.txt", "the user's\n");  // not listed: the user's
  const Files before_files = files_below(out);
  const BinaryRun r =
      run("report " + quoted(campaign()) + " --out " + quoted(out) + " --no-pdf", d);
  EXPECT_EQ(r.status, kExitInputError);
  EXPECT_NE(r.err.find("cannot keep your file results.csv/mine.txt"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("report: 5 tests found"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("wrote"), std::string::npos) << r.out;
  EXPECT_EQ(file_text(out / "results.json"), before);
  EXPECT_EQ(files_below(out), before_files);
  EXPECT_EQ(names_in(d.path()), (Files{".o.chatterlab-lock", "o", "stderr.txt", "stdout.txt"}));
}

TEST_F(CliOut, ASecondRunOnALockedFolderIsRefusedAtOnce) {
  TempDir d;
  const fs::path out = d.path() / "o";
  const int fd = ::open((d.path() / ".o.chatterlab-lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);  // as a running report holds it
  const BinaryRun r =
      run("report " + quoted(campaign()) + " --out " + quoted(out) + " --no-pdf --quiet", d);
  ::close(fd);
  EXPECT_EQ(r.status, kExitInputError);
  EXPECT_NE(r.err.find("chatterlab report: --out " + out.string() +
                       ": another chatterlab run is writing this folder"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out));
  const BinaryRun after =
      run("report " + quoted(campaign()) + " --out " + quoted(out) + " --no-pdf --quiet", d);
  EXPECT_EQ(after.status, kExitOk) << after.err;
}

TEST_F(CliOut, AnOutInsideTheCampaignOrALinkIsRefused) {
  TempDir d;
  const fs::path c = copy_campaign(d);
  const Files before = files_below(c);
  const BinaryRun inside =
      run("report " + quoted(c) + " --out " + quoted(c / "reports/r") + " --no-pdf --quiet", d);
  EXPECT_EQ(inside.status, kExitInputError);
  EXPECT_NE(inside.err.find("is inside the campaign folder"), std::string::npos) << inside.err;
  EXPECT_EQ(files_below(c), before);
  EXPECT_FALSE(fs::exists(c / "reports"));

  const BinaryRun first =
      run("report " + quoted(c) + " --out " + quoted(d.path() / "real") + " --no-pdf --quiet", d);
  ASSERT_EQ(first.status, kExitOk) << first.err;
  const std::string results = file_text(d.path() / "real/results.json");
  fs::create_directory_symlink(d.path() / "real", d.path() / "link");
  const BinaryRun link =
      run("report " + quoted(c) + " --out " + quoted(d.path() / "link") + " --no-pdf --quiet", d);
  EXPECT_EQ(link.status, kExitInputError);
  EXPECT_NE(link.err.find("is a symbolic link"), std::string::npos) << link.err;
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(d.path() / "link")));
  EXPECT_EQ(file_text(d.path() / "real/results.json"), results);
}

// Test ids "tap/x" and "tap-x" both give the stem figures/tap-tap-x-: each gets its own files,
// and its own anchor in the report.
TEST_F(CliOut, TwoTestsWhoseIdsGiveOneFigureStemGetAFileEach) {
  TempDir d;
  const fs::path c = copy_campaign(d);
  fs::copy(c / "tap/x", c / "tap-x", fs::copy_options::recursive);
  const BinaryRun r =
      run("report " + quoted(c) + " --out " + quoted(d.path() / "o") + " --no-pdf --quiet", d);
  ASSERT_EQ(r.status, kExitOk) << r.err;
  const fs::path o = d.path() / "o";
  EXPECT_TRUE(fs::exists(o / "figures/tap-tap-x-frf.svg"));
  EXPECT_TRUE(fs::exists(o / "figures/tap-tap-x-frf-2.svg"));
  EXPECT_TRUE(fs::exists(o / "figures/tap-tap-x-frf-2.csv"));
  // Each test's results name a different figure.
  const json j = json::parse(file_text(o / "results.json"));
  std::vector<std::string> frf_files;
  const std::function<void(const json&)> collect = [&](const json& v) {
    if (v.is_string()) {
      const std::string s = v.get<std::string>();
      if (s.rfind("figures/tap-tap-x-frf", 0) == 0) frf_files.push_back(s);
    } else if (v.is_structured()) {
      for (const auto& e : v) collect(e);
    }
  };
  collect(j);
  std::sort(frf_files.begin(), frf_files.end());
  EXPECT_TRUE(std::adjacent_find(frf_files.begin(), frf_files.end()) == frf_files.end());
  EXPECT_NE(std::find(frf_files.begin(), frf_files.end(), "figures/tap-tap-x-frf-2.svg"),
            frf_files.end());
  const std::string index = file_text(o / "index.html");
  EXPECT_NE(index.find("id=\"test-tap-x\""), std::string::npos);
  EXPECT_NE(index.find("id=\"test-tap-x-2\""), std::string::npos);
}

}  // namespace
}  // namespace chatterlab::app
