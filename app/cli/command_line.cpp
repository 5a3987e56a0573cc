#include "app/cli/command_line.h"

#include <algorithm>
#include <array>

namespace chatterlab::app {
namespace {

struct OptionSpec {
  const char* name;
  bool takes_value;
  const char* help;
};

struct CommandSpec {
  const char* name;
  const char* synopsis;
  const char* what;
  std::vector<OptionSpec> options;
};

const std::vector<CommandSpec>& commands() {
  static const std::vector<CommandSpec> c = {
      {"report",
       "chatterlab report <campaign> --out <dir> [--no-pdf] [--single-file] [--jobs N] "
       "[--quiet]",
       "analyse every test of the campaign; write index.html, report.pdf, results.json",
       {{"--out", true,
         "the report folder: new, empty, or one chatterlab wrote (its previous files are "
         "removed)"},
        {"--no-pdf", false, "write no report.pdf"},
        {"--single-file", false,
         "also write report.html: the report in one file, stylesheet and figures inside it"},
        {"--jobs", true, "worker threads (0: one per hardware thread)"},
        {"--quiet", false, "no progress or summary on stdout; errors still on stderr"}}},
      {"validate",
       "chatterlab validate <campaign>",
       "list the tests found and every problem; exit 1 when any test is unusable (a kind of "
       "the format this version does not analyse is listed, not a problem)",
       {}},
      {"simulate",
       "chatterlab simulate <spec.yaml> --out <dir> [--no-pdf] [--results-only] [--jobs N] "
       "[--quiet]",
       "one milling simulation: bifurcation depth, Poincare maps, figures, results.json",
       {{"--out", true,
         "the output folder: new, empty, or one chatterlab wrote (its previous files are "
         "removed)"},
        {"--no-pdf", false, "write no PDF"},
        {"--results-only", false, "results.json only: no figures, HTML or PDF"},
        {"--jobs", true, "figure threads (0: one per hardware thread)"},
        {"--quiet", false, "no summary on stdout; errors still on stderr"}}},
      {"lobes",
       "chatterlab lobes <spec.yaml> --out <dir> [--no-pdf] [--results-only] [--jobs N] "
       "[--quiet]",
       "stability lobes by semi-discretization and the zero-order approximation: limit depth, "
       "boundary type and chatter frequency per speed, a figure, results.json",
       {{"--out", true,
         "the output folder: new, empty, or one chatterlab wrote (its previous files are "
         "removed)"},
        {"--no-pdf", false, "write no PDF"},
        {"--results-only", false, "results.json only: no figure, HTML or PDF"},
        {"--jobs", true, "threads over the speeds (0: one per hardware thread)"},
        {"--quiet", false, "no summary on stdout; errors still on stderr"}}},
      {"synth",
       "chatterlab synth <spec.yaml> --out <campaign> [--quiet]",
       "write a synthetic campaign with truth.yaml (spec format: docs/format/synth-spec.md)",
       {{"--out", true,
         "the campaign folder: new, empty, or one chatterlab wrote (its previous files are "
         "removed)"},
        {"--quiet", false, "no summary on stdout; warnings and errors still on stderr"}}},
      {"init",
       "chatterlab init <folder> [--write]",
       "look at the data files of a folder and propose campaign.yaml and test.yaml files "
       "(kinds, sample rates, column mapping; TODO for what it cannot tell); print them",
       {{"--write", false,
         "write the proposed files into the folder (an existing campaign.yaml or test.yaml is "
         "never overwritten)"}}},
      {"nightly",
       "chatterlab nightly <archive-root> --out <site> [--no-pdf] [--jobs N] [--wait] "
       "[--tolerances <yaml>] [--quiet]\n       [--slurm [--partition P] [--time T] [--mem M] "
       "[--slurm-wait]]",
       "run every campaign under the root whose inputs changed since the site's last run; "
       "write the site: index.html, nightly.json, campaigns/<name>/, history.sqlite "
       "(docs/nightly.md)",
       {{"--out", true,
         "the site folder: new, empty, or one chatterlab nightly wrote (it is updated in "
         "place)"},
        {"--no-pdf", false, "write no PDF (the campaigns' and the index's)"},
        {"--jobs", true, "worker threads inside a campaign (0: one per hardware thread)"},
        {"--wait", false, "when another nightly run holds the site, wait for it to end"},
        {"--tolerances", true,
         "tolerance rules for the regression flags (docs/nightly.md#tolerances)"},
        {"--quiet", false, "no progress or summary on stdout; errors still on stderr"},
        {"--slurm", false,
         "submit the campaigns to recompute as a Slurm job array, a task per campaign, and a "
         "reduce job that writes the site (docs/nightly.md#on-a-cluster-slurm)"},
        {"--partition", true, "with --slurm: the partition (default: the cluster's)"},
        {"--time", true, "with --slurm: each task's time limit, in Slurm's form (1:00:00)"},
        {"--mem", true, "with --slurm: each task's memory (4G)"},
        {"--slurm-wait", false,
         "with --slurm: wait for the reduce job and exit with the run's status"}}},
      {"nightly-task",
       "chatterlab nightly-task <site> --run N --task I",
       "run by the job array of nightly --slurm: report task I of run N into the site's "
       "slurm/run-N/out/",
       {{"--run", true, "the run of the site's history"},
        {"--task", true, "the task's index in the run's plan.json"}}},
      {"nightly-reduce",
       "chatterlab nightly-reduce <site> --run N",
       "run by the reduce job of nightly --slurm: put the tasks' reports into the site, write "
       "the history, index.html and nightly.json",
       {{"--run", true, "the run of the site's history"}}},
      {"compare",
       "chatterlab compare <a/results.json> <b/results.json> [--tolerances <yaml>] [--json] "
       "[--html <file>]\n       chatterlab compare <run-a> <run-b> --site <site> [--campaign "
       "<name>] [...]",
       "every number of two results.json files (or two runs of a nightly site's history) that "
       "moved beyond its tolerance, a to b; exit 1 when one is flagged (docs/nightly.md#compare)",
       {{"--site", true,
         "a and b are runs of this nightly site's history: a number, 'last' or 'last-N'"},
        {"--campaign", true, "with --site: compare this campaign alone (default: every one)"},
        {"--tolerances", true,
         "tolerance rules by key family (default: rel 1e-9; timings ignored; "
         "docs/nightly.md#tolerances)"},
        {"--json", false, "print the table as JSON instead of text"},
        {"--html", true, "also write the table as a standalone HTML page to this file"}}},
  };
  return c;
}

const CommandSpec* find_command(const std::string& name) {
  for (const auto& c : commands()) {
    if (name == c.name) return &c;
  }
  return nullptr;
}

bool is_help(const std::string& a) { return a == "--help" || a == "-h" || a == "help"; }

// The exit statuses of app/cli/exit_codes.h, for every usage text.
const char* const kExitStatusText =
    "exit status:\n"
    "  0  done\n"
    "  1  bad input: the campaign or spec cannot be read, --out refused, validate found a\n"
    "     problem, the PDF not written, a simulation that did not complete, init found no\n"
    "     data file\n"
    "  2  the command line does not parse\n"
    "  3  internal error (report: a test or group stopped on one; the report names it)\n"
    "  4  report: the report was written but no test was analysed (all skipped, or none)\n"
    "compare: 0 nothing flagged, 1 a number moved beyond its tolerance or vanished (or an\n"
    "  input cannot be read; stderr says which), 2 the command line does not parse\n"
    "nightly: 0 every campaign analysed and nothing flagged, 1 a campaign not read or with\n"
    "  nothing analysed, a flag, or the site or root refused, 3 an internal error\n";

}  // namespace

std::string command_usage(const std::string& command) {
  if (command.empty()) {
    std::string u = "usage:\n";
    for (const auto& c : commands()) {
      u += std::string("  ") + c.synopsis + "\n      " + c.what + "\n";
    }
    u += "  chatterlab --version | --help | <command> --help\n";
    return u + kExitStatusText;
  }
  const CommandSpec* c = find_command(command);
  if (c == nullptr) return "";
  std::string u = std::string("usage: ") + c->synopsis + "\n  " + c->what + "\n";
  if (!c->options.empty()) u += "options:\n";
  for (const auto& o : c->options) {
    u +=
        std::string("  ") + o.name + (o.takes_value ? " <value>" : "") + "\n      " + o.help + "\n";
  }
  return u + kExitStatusText;
}

ParsedCommandLine parse_command_line(const std::vector<std::string>& args) {
  ParsedCommandLine p;
  CommandLine& l = p.line;
  if (args.empty()) {
    p.error = "no command";
    return p;
  }
  if (is_help(args[0])) {
    l.help = true;
    return p;
  }
  if (args[0] == "--version") {
    l.version = true;
    return p;
  }
  l.command = args[0];
  const CommandSpec* cmd = find_command(l.command);
  if (cmd == nullptr) {
    p.error = "unknown command '" + l.command + "'";
    return p;
  }
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (is_help(a) && a != "help") {
      l.help = true;
      continue;
    }
    if (a.empty() || a[0] != '-') {
      l.positional.push_back(a);
      continue;
    }
    const auto o = std::find_if(cmd->options.begin(), cmd->options.end(),
                                [&](const OptionSpec& s) { return a == s.name; });
    if (o == cmd->options.end()) {
      const bool known_elsewhere =
          std::any_of(commands().begin(), commands().end(), [&](const CommandSpec& c) {
            return std::any_of(c.options.begin(), c.options.end(),
                               [&](const OptionSpec& s) { return a == s.name; });
          });
      p.error = known_elsewhere ? "option '" + a + "' does not apply to " + l.command
                                : "unknown option '" + a + "'";
      return p;
    }
    std::string value;
    if (o->takes_value) {
      if (i + 1 >= args.size()) {
        p.error = "option '" + a + "' needs a value";
        return p;
      }
      value = args[++i];
    }
    if (a == "--out") {
      l.out = value;
    } else if (a == "--no-pdf") {
      l.pdf = false;
    } else if (a == "--quiet") {
      l.quiet = true;
    } else if (a == "--write") {
      l.write = true;
    } else if (a == "--single-file") {
      l.single_file = true;
    } else if (a == "--site") {
      l.site = value;
    } else if (a == "--campaign") {
      l.campaign = value;
    } else if (a == "--wait") {
      l.wait = true;
    } else if (a == "--json") {
      l.json = true;
    } else if (a == "--html") {
      l.html = value;
    } else if (a == "--tolerances") {
      l.tolerances = value;
    } else if (a == "--results-only") {
      l.results_only = true;
    } else if (a == "--slurm") {
      l.slurm = true;
    } else if (a == "--slurm-wait") {
      l.slurm_wait = true;
    } else if (a == "--partition") {
      l.partition = value;
    } else if (a == "--time") {
      l.time = value;
    } else if (a == "--mem") {
      l.mem = value;
    } else if (a == "--run" || a == "--task") {
      std::size_t used = 0;
      long long n = -1;
      try {
        n = std::stoll(value, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != value.size() || n < (a == "--run" ? 1 : 0)) {
        p.error =
            a + " takes a whole number >= " + (a == "--run" ? "1" : "0") + ", got '" + value + "'";
        return p;
      }
      (a == "--run" ? l.run : l.task) = n;
    } else if (a == "--jobs") {
      std::size_t used = 0;
      int jobs = -1;
      try {
        jobs = std::stoi(value, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != value.size() || jobs < 0) {
        p.error = "--jobs takes a whole number >= 0, got '" + value + "'";
        return p;
      }
      l.jobs = jobs;
    }
  }
  return p;
}

}  // namespace chatterlab::app
