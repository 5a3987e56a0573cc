// chatterlab: campaign folder -> HTML report, PDF and results.json (docs/architecture.md).
#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "app/cli/command_line.h"
#include "app/cli/exit_codes.h"
#include "app/cli/init.h"
#include "app/cli/output_folder.h"
#include "app/cli/validate.h"
#include "app/core/campaign.h"
#include "app/report/report.h"
#include "app/simulate/simulate.h"
#include "app/synth/synth.h"

namespace {

int usage_error(const std::string& what, const std::string& command) {
  std::cerr << "chatterlab: " << what << "\n" << chatterlab::app::command_usage(command);
  return chatterlab::app::kExitUsage;
}

// Writes the output folder's manifest when the command ends, also through an exception: a
// folder left half-written is still recognised (and cleared) as chatterlab's by the next run.
struct ManifestOnExit {
  const chatterlab::app::OutputFolder& folder;
  ~ManifestOnExit() {
    try {
      folder.write_manifest();
    } catch (...) {
    }
  }
};

// Whether `out` is the folder `campaign` or one of its parents.
bool out_holds(const std::filesystem::path& out, const std::filesystem::path& campaign) {
  std::error_code ec;
  const auto o = std::filesystem::weakly_canonical(std::filesystem::absolute(out), ec);
  const auto c = std::filesystem::weakly_canonical(std::filesystem::absolute(campaign), ec);
  if (ec) return false;
  const auto r = c.lexically_relative(o);
  return !r.empty() && *r.begin() != "..";
}

}  // namespace

int main(int argc, char** argv) {
  using chatterlab::app::command_usage;
  const std::vector<std::string> args(argv + 1, argv + argc);
  const chatterlab::app::ParsedCommandLine parsed = chatterlab::app::parse_command_line(args);
  const chatterlab::app::CommandLine& line = parsed.line;
  const std::string& cmd = line.command;
  if (!parsed.error.empty()) {
    // The command's own usage when it is known, else every command's.
    return usage_error(parsed.error, command_usage(cmd).empty() ? "" : cmd);
  }
  if (line.help) {
    std::cout << command_usage(cmd);
    return 0;
  }
  if (line.version) {
    std::cout << "chatterlab " << CHATTERLAB_VERSION << "\n";
    return 0;
  }
  const std::vector<std::string>& positional = line.positional;
  const std::string& out = line.out;
  chatterlab::app::ReportOptions report_options;
  report_options.pdf = line.pdf;
  report_options.jobs = line.jobs;
  report_options.single_file = line.single_file;
  const bool results_only = line.results_only;
  // --quiet: stdout gets nothing (a stream without a buffer drops what it is given).
  std::ostream quiet_stream(nullptr);
  std::ostream& log = line.quiet ? quiet_stream : std::cout;
  try {
    if (cmd == "validate") {
      if (positional.size() != 1) return usage_error("validate takes one campaign folder", cmd);
      auto campaign = chatterlab::app::load_campaign(positional[0]);
      return chatterlab::app::validate_campaign(campaign, std::cout);
    }
    if (cmd == "init") {
      if (positional.size() != 1) return usage_error("init takes one folder", cmd);
      return chatterlab::app::run_init(positional[0], line.write, std::cout);
    }
    if (cmd == "report") {
      if (positional.size() != 1 || out.empty()) {
        return usage_error("report takes one campaign folder and --out <dir>", cmd);
      }
      if (out_holds(out, positional[0])) {
        throw chatterlab::InputError(
            "--out " + out +
            ": is the campaign folder or holds it; the report would remove the campaign's "
            "files (a synth campaign lists them as chatterlab's): choose another --out");
      }
      // Refused before any work when --out is not ours; the previous run's files go once
      // the campaign was read.
      auto folder = chatterlab::app::OutputFolder::open(out);
      report_options.progress = !line.quiet;
      report_options.errors = &std::cerr;
      report_options.before_writing = [&folder] { folder.clear_previous(); };
      const ManifestOnExit manifest{folder};
      return chatterlab::app::run_report(positional[0], out, report_options, log);
    }
    if (cmd == "simulate") {
      if (positional.size() != 1 || out.empty()) {
        return usage_error("simulate takes one spec file and --out <dir>", cmd);
      }
      chatterlab::app::SimulateOptions so;
      so.pdf = report_options.pdf;
      so.report = !results_only;
      so.jobs = report_options.jobs;
      auto folder = chatterlab::app::OutputFolder::open(out);
      folder.clear_previous();
      const ManifestOnExit manifest{folder};
      // Quiet: the summary is dropped, and what run_simulate said goes to stderr when it
      // failed (it names the PDF error or the divergence there).
      std::ostringstream held;
      const int rc = chatterlab::app::run_simulate(
          positional[0], out, so, line.quiet ? static_cast<std::ostream&>(held) : std::cout);
      if (line.quiet && rc != 0) std::cerr << held.str();
      return rc;
    }
    if (cmd == "synth") {
      if (positional.size() != 1 || out.empty()) {
        return usage_error("synth takes one spec file and --out <campaign>", cmd);
      }
      // As report and simulate: a folder that is not chatterlab's is refused before any work;
      // the earlier run's files go once the spec has been read (a bad spec changes nothing).
      auto folder = chatterlab::app::OutputFolder::open(out);
      const ManifestOnExit manifest{folder};
      const auto s = chatterlab::app::synthesize_campaign(positional[0], out,
                                                          [&folder] { folder.clear_previous(); });
      for (const auto& w : s.warnings) std::cerr << "chatterlab synth: warning: " << w << "\n";
      log << "synth: wrote campaign '" << s.campaign_name << "' with " << s.tests_written
          << " tests to " << out << "\n";
      return chatterlab::app::kExitOk;
    }
  } catch (const chatterlab::InputError& e) {
    std::cerr << "chatterlab " << cmd << ": " << e.what() << "\n";
    return chatterlab::app::kExitInputError;
  } catch (const std::exception& e) {
    // Not bad input: a bug or a broken invariant (exit status 3, as `report` uses for a test
    // that stopped on one).
    std::cerr << "chatterlab " << cmd << ": internal error: " << e.what() << "\n";
    return chatterlab::app::kExitInternalError;
  }
  return usage_error("unknown command '" + cmd + "'", "");
}
