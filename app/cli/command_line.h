// The command line of `chatterlab`: the commands, the options each accepts, and their usage
// text (`chatterlab <command> --help`). An option a command does not take is an error naming
// both, not a silent no-op.
#pragma once

#include <string>
#include <vector>

namespace chatterlab::app {

struct CommandLine {
  std::string command;  // report | validate | simulate | synth | init | compare | nightly |
                        // nightly-task | nightly-reduce; empty
                        // for --help /
                        // --version
  std::vector<std::string> positional;
  std::string out;            // --out
  bool pdf = true;            // --no-pdf
  bool results_only = false;  // --results-only
  bool single_file = false;   // --single-file (report): also report.html, self-contained
  int jobs = 0;               // --jobs N (0: one thread per hardware thread)
  bool quiet = false;         // --quiet: nothing on stdout; errors still on stderr
  bool write = false;         // --write (init): write the proposed files
  bool json = false;          // --json (compare): the table as JSON on stdout
  std::string html;           // --html <file> (compare): also the table as an HTML page
  std::string tolerances;     // --tolerances <yaml> (compare, nightly): tolerance rules
  bool wait = false;          // --wait (nightly): queue behind a run that holds the site
  std::string site;           // --site <site> (compare): a and b are runs of its history
  std::string campaign;       // --campaign <name> (compare --site): that campaign alone
  bool slurm = false;         // --slurm (nightly): submit to Slurm (app/nightly/slurm.h)
  bool slurm_wait = false;    // --slurm-wait (nightly --slurm): wait for the reduce job
  std::string partition;      // --partition <p> (nightly --slurm)
  std::string time;           // --time <limit> (nightly --slurm): each task's time limit
  std::string mem;            // --mem <size> (nightly --slurm): each task's memory
  long long run = -1;         // --run N (nightly-task, nightly-reduce)
  long long task = -1;        // --task I (nightly-task)
  bool help = false;          // --help / -h: the usage of `command` (or of every command)
  bool version = false;       // --version
};

struct ParsedCommandLine {
  CommandLine line;
  std::string error;  // empty when the line is valid; else what is wrong, naming the option
};

// The arguments after the program name.
ParsedCommandLine parse_command_line(const std::vector<std::string>& args);

// The usage of one command ("" for an unknown one), or of every command when `command` is
// empty; both end with the exit statuses (app/cli/exit_codes.h).
std::string command_usage(const std::string& command);

}  // namespace chatterlab::app
