// The command line: each command takes only its own options (an option of another command is
// an error naming both), `<command> --help` prints that command's usage, and values are checked.
#include "app/cli/command_line.h"

#include <gtest/gtest.h>

namespace chatterlab::app {
namespace {

ParsedCommandLine parse(const std::vector<std::string>& args) { return parse_command_line(args); }

TEST(CommandLine, ReadsEachCommandsOptions) {
  const auto r = parse({"report", "camp", "--out", "rep", "--no-pdf", "--jobs", "3"});
  EXPECT_EQ(r.error, "");
  EXPECT_EQ(r.line.command, "report");
  EXPECT_EQ(r.line.positional, std::vector<std::string>{"camp"});
  EXPECT_EQ(r.line.out, "rep");
  EXPECT_FALSE(r.line.pdf);
  EXPECT_EQ(r.line.jobs, 3);
  const auto s = parse({"simulate", "spec.yaml", "--results-only", "--out", "o"});
  EXPECT_EQ(s.error, "");
  EXPECT_TRUE(s.line.results_only);
}

TEST(CommandLine, OptionsOfOtherCommandsAndUnknownOptionsAreErrors) {
  EXPECT_EQ(parse({"validate", "camp", "--no-pdf"}).error,
            "option '--no-pdf' does not apply to validate");
  EXPECT_EQ(parse({"report", "camp", "--out", "r", "--results-only"}).error,
            "option '--results-only' does not apply to report");
  EXPECT_EQ(parse({"synth", "s.yaml", "--out", "c", "--jobs", "2"}).error,
            "option '--jobs' does not apply to synth");
  EXPECT_EQ(parse({"report", "camp", "--outt", "r"}).error, "unknown option '--outt'");
  EXPECT_EQ(parse({"report", "camp", "--out"}).error, "option '--out' needs a value");
  EXPECT_EQ(parse({"report", "camp", "--jobs", "two"}).error,
            "--jobs takes a whole number >= 0, got 'two'");
  EXPECT_EQ(parse({"report", "camp", "--jobs", "-1"}).error,
            "--jobs takes a whole number >= 0, got '-1'");
  EXPECT_EQ(parse({"nighty", "archive"}).error, "unknown command 'nighty'");
  EXPECT_EQ(parse({"nightly", "archive", "--out", "site", "--wait", "--no-pdf"}).error, "");
  EXPECT_EQ(parse({"compare", "a.json", "b.json", "--wait"}).error,
            "option '--wait' does not apply to compare");
  EXPECT_EQ(parse({"report", "camp", "--out", "r", "--json"}).error,
            "option '--json' does not apply to report");
  EXPECT_EQ(parse({"lobes", "spec.yaml", "--out", "o", "--results-only", "--jobs", "2"}).error, "");
  EXPECT_EQ(parse({"lobes", "spec.yaml", "--out", "o", "--single-file"}).error,
            "option '--single-file' does not apply to lobes");
  EXPECT_EQ(parse({}).error, "no command");
}

TEST(CommandLine, NightlyOnSlurmAndItsJobCommands) {
  const auto n = parse({"nightly", "archive", "--out", "site", "--slurm", "--partition", "batch",
                        "--time", "1:00:00", "--mem", "4G", "--slurm-wait", "--jobs", "2"});
  EXPECT_EQ(n.error, "");
  EXPECT_TRUE(n.line.slurm);
  EXPECT_TRUE(n.line.slurm_wait);
  EXPECT_EQ(n.line.partition, "batch");
  EXPECT_EQ(n.line.time, "1:00:00");
  EXPECT_EQ(n.line.mem, "4G");
  const auto t = parse({"nightly-task", "site", "--run", "12", "--task", "0"});
  EXPECT_EQ(t.error, "");
  EXPECT_EQ(t.line.run, 12);
  EXPECT_EQ(t.line.task, 0);
  EXPECT_EQ(parse({"nightly-task", "site", "--run", "0", "--task", "0"}).error,
            "--run takes a whole number >= 1, got '0'");
  EXPECT_EQ(parse({"nightly-task", "site", "--run", "3", "--task", "x"}).error,
            "--task takes a whole number >= 0, got 'x'");
  EXPECT_EQ(parse({"nightly-reduce", "site", "--run", "3", "--task", "1"}).error,
            "option '--task' does not apply to nightly-reduce");
  EXPECT_EQ(parse({"report", "camp", "--out", "r", "--slurm"}).error,
            "option '--slurm' does not apply to report");
}

TEST(CommandLine, QuietForTheCommandsThatPrintProgress) {
  for (const char* c : {"report", "simulate", "lobes", "synth"}) {
    const auto r = parse({c, "x", "--out", "o", "--quiet"});
    EXPECT_EQ(r.error, "") << c;
    EXPECT_TRUE(r.line.quiet) << c;
    EXPECT_NE(command_usage(c).find("--quiet"), std::string::npos) << c;
  }
  EXPECT_FALSE(parse({"report", "x", "--out", "o"}).line.quiet);
  EXPECT_EQ(parse({"validate", "camp", "--quiet"}).error,
            "option '--quiet' does not apply to validate");
}

TEST(CommandLine, UsageNamesTheExitStatuses) {
  for (const char* c : {"", "report", "validate", "simulate", "lobes", "synth"}) {
    const std::string u = command_usage(c);
    EXPECT_NE(u.find("exit status:\n  0  done\n  1  bad input"), std::string::npos) << c;
    EXPECT_NE(u.find("  3  internal error"), std::string::npos) << c;
    EXPECT_NE(u.find("  4  report: the report was written but no test was analysed"),
              std::string::npos)
        << c;
  }
}

TEST(CommandLine, HelpPerCommand) {
  const auto r = parse({"simulate", "--help"});
  EXPECT_EQ(r.error, "");
  EXPECT_TRUE(r.line.help);
  EXPECT_EQ(r.line.command, "simulate");
  const std::string u = command_usage("simulate");
  EXPECT_EQ(u.rfind("usage: chatterlab simulate <spec.yaml> --out <dir>", 0), 0u) << u;
  EXPECT_NE(u.find("--results-only"), std::string::npos);
  EXPECT_EQ(command_usage("validate").find("--no-pdf"), std::string::npos);
  EXPECT_TRUE(parse({"-h"}).line.help);
  EXPECT_EQ(command_usage("nope"), "");
  const std::string all = command_usage("");
  for (const char* c : {"report", "validate", "simulate", "synth"}) {
    EXPECT_NE(all.find(std::string("chatterlab ") + c), std::string::npos) << c;
  }
}

}  // namespace
}  // namespace chatterlab::app
