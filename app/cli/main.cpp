// chatterlab: campaign folder -> HTML report, PDF and results.json (docs/architecture.md).
#include <chrono>
#include <filesystem>
#include <functional>
#include <iostream>
#include <sstream>
#include <streambuf>
#include <string>
#include <utility>
#include <vector>

#include "analysis/common/summary.h"
#include "app/cli/command_line.h"
#include "app/cli/exit_codes.h"
#include "app/cli/init.h"
#include "app/cli/output_folder.h"
#include "app/cli/validate.h"
#include "app/core/allocator.h"
#include "app/core/campaign.h"
#include "app/core/checked_write.h"
#include "app/lobes/lobes_run.h"
#include "app/nightly/compare.h"
#include "app/nightly/compute.h"
#include "app/nightly/history.h"
#include "app/nightly/nightly.h"
#include "app/report/report.h"
#include "app/simulate/simulate.h"
#include "app/synth/synth.h"

namespace {

int usage_error(const std::string& what, const std::string& command) {
  std::cerr << "chatterlab: " << what << "\n" << chatterlab::app::command_usage(command);
  return chatterlab::app::kExitUsage;
}

// A stream buffer that passes on what it is given a line at a time, with every `from` replaced
// by `with`: the commands write into the temporary folder beside --out
// (app/cli/output_folder.h), and their messages name --out itself. The line that says what was
// written ("...; wrote out/index.html, results.json ...") and every line after it are held
// until release(): they are passed on then, the "wrote" line only when the output did replace
// --out (not when that failed).
class RewritingBuf : public std::streambuf {
 public:
  RewritingBuf(std::ostream& to, std::string from, std::string with)
      : to_(to), from_(std::move(from)), with_(std::move(with)) {}
  ~RewritingBuf() override {
    emit();
    release(false);
  }
  RewritingBuf(const RewritingBuf&) = delete;
  RewritingBuf& operator=(const RewritingBuf&) = delete;

  void release(bool replaced) {
    emit();
    for (const auto& l : held_) {
      if (replaced || l.find("; wrote ") == std::string::npos) to_ << l;
    }
    held_.clear();
    holding_ = false;
    to_.flush();
  }

  static std::string rewrite(std::string s, const std::string& from, const std::string& with) {
    if (from.empty()) return s;
    for (std::size_t at = s.find(from); at != std::string::npos;
         at = s.find(from, at + with.size())) {
      s.replace(at, from.size(), with);
    }
    return s;
  }

 protected:
  int overflow(int c) override {
    if (c == traits_type::eof()) return 0;
    line_ += static_cast<char>(c);
    if (c == '\n') emit();
    return c;
  }
  int sync() override {
    emit();
    to_.flush();
    return 0;
  }

 private:
  void emit() {
    if (line_.empty()) return;
    std::string l = rewrite(line_, from_, with_);
    line_.clear();
    holding_ = holding_ || l.find("; wrote ") != std::string::npos;
    if (holding_) {
      held_.push_back(std::move(l));
    } else {
      to_ << l;
    }
  }

  std::ostream& to_;
  std::string from_, with_, line_;
  bool holding_ = false;
  std::vector<std::string> held_;
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
  chatterlab::app::configure_allocator();  // docs/performance.md#allocator
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
  // The temporary folder a command writes into and --out, as messages show them.
  std::string work_shown, out_shown;
  try {
    if (cmd == "validate") {
      if (positional.size() != 1) return usage_error("validate takes one campaign folder", cmd);
      auto campaign = chatterlab::app::load_campaign(positional[0]);
      return chatterlab::app::validate_campaign(campaign, std::cout);
    }
    if (cmd == "compare") {
      if (positional.size() != 2) {
        return usage_error("compare takes two results.json files, or two runs with --site", cmd);
      }
      if (!line.campaign.empty() && line.site.empty()) {
        return usage_error("--campaign goes with --site", cmd);
      }
      const chatterlab::app::CompareOptions options =
          line.tolerances.empty() ? chatterlab::app::CompareOptions{}
                                  : chatterlab::app::load_tolerances(line.tolerances);
      nlohmann::json a, b;
      std::string a_label = positional[0], b_label = positional[1];
      if (line.site.empty()) {
        a = chatterlab::app::read_json_file(positional[0]);
        b = chatterlab::app::read_json_file(positional[1]);
      } else {
        const std::filesystem::path db_file = std::filesystem::path(line.site) / "history.sqlite";
        if (!std::filesystem::is_regular_file(db_file)) {
          throw chatterlab::InputError("--site " + line.site +
                                       ": no history.sqlite (not a chatterlab nightly site)");
        }
        chatterlab::app::SiteDb db(db_file);
        const std::int64_t ra = chatterlab::app::resolve_run(db, positional[0]);
        const std::int64_t rb = chatterlab::app::resolve_run(db, positional[1]);
        a = chatterlab::app::run_results(db, ra, line.campaign);
        b = chatterlab::app::run_results(db, rb, line.campaign);
        const std::string what = line.campaign.empty() ? "" : " " + line.campaign;
        a_label = line.site + " run " + std::to_string(ra) + what;
        b_label = line.site + " run " + std::to_string(rb) + what;
      }
      chatterlab::app::Comparison c = chatterlab::app::compare_results(a, b, options);
      c.a_label = a_label;
      c.b_label = b_label;
      if (!line.html.empty()) {
        chatterlab::app::write_file_checked(line.html, chatterlab::app::comparison_html(c));
      }
      if (line.json) {
        std::cout << chatterlab::app::comparison_json(c).dump(1) << "\n";
      } else {
        log << chatterlab::app::comparison_text(c);
      }
      return c.flags() > 0 ? chatterlab::app::kExitFlagged : chatterlab::app::kExitOk;
    }
    if (cmd == "nightly") {
      if (positional.size() != 1 || out.empty()) {
        return usage_error("nightly takes one archive root and --out <site>", cmd);
      }
      if (!line.slurm &&
          (!line.partition.empty() || !line.time.empty() || !line.mem.empty() || line.slurm_wait)) {
        return usage_error("--partition, --time, --mem and --slurm-wait go with --slurm", cmd);
      }
      chatterlab::app::NightlyOptions no;
      no.pdf = line.pdf;
      no.jobs = line.jobs;
      no.wait = line.wait;
      no.slurm.enabled = line.slurm;
      no.slurm.partition = line.partition;
      no.slurm.time = line.time;
      no.slurm.mem = line.mem;
      no.slurm.wait = line.slurm_wait;
      no.errors = &std::cerr;
      if (!line.tolerances.empty()) {
        no.tolerances = chatterlab::app::load_tolerances(line.tolerances);
        no.tolerances_file = line.tolerances;
      }
      return chatterlab::app::run_nightly(positional[0], out, no, log);
    }
    if (cmd == "nightly-task") {
      if (positional.size() != 1 || line.run < 1 || line.task < 0) {
        return usage_error("nightly-task takes one site, --run N and --task I", cmd);
      }
      return chatterlab::app::run_nightly_task(positional[0], line.run, line.task, log);
    }
    if (cmd == "nightly-reduce") {
      if (positional.size() != 1 || line.run < 1) {
        return usage_error("nightly-reduce takes one site and --run N", cmd);
      }
      chatterlab::app::NightlyOptions no;
      no.errors = &std::cerr;
      return chatterlab::app::run_nightly_reduce(positional[0], line.run, no, log);
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
            ": is the campaign folder or holds it; the report would replace the campaign's "
            "files: choose another --out");
      }
      if (out_holds(positional[0], out)) {
        throw chatterlab::InputError(
            "--out " + out +
            ": is inside the campaign folder; the report would be written into the campaign it "
            "reads: choose a folder outside it");
      }
      // Refused before any work when --out is not ours; the report is written into a
      // temporary folder that replaces --out once it is complete.
      chatterlab::app::OutputFolder folder(out);
      work_shown = folder.work().string();
      out_shown = folder.dir().string();
      RewritingBuf log_buf(log, work_shown, out_shown), err_buf(std::cerr, work_shown, out_shown);
      std::ostream log_out(&log_buf), err_out(&err_buf);
      report_options.progress = !line.quiet;
      report_options.errors = &err_out;
      // A campaign that cannot be read at all returns before writing: --out stays as it was.
      bool written = false;
      report_options.before_writing = [&written] { written = true; };
      const int rc =
          chatterlab::app::run_report(positional[0], folder.work(), report_options, log_out);
      if (written) folder.commit();
      log_buf.release(true);
      return rc;
    }
    // simulate and lobes: refused before any work when --out is not ours; the output is written
    // into a temporary folder that replaces --out once the run returned (a run that diverged or
    // whose PDF failed still wrote its report, exit 1); a spec error (an exception) leaves --out
    // as it was. Quiet: the summary is dropped, and what the run said goes to stderr when it
    // failed (it names the PDF error or the divergence there).
    const auto run_spec_command =
        [&](const std::function<int(const std::filesystem::path&, std::ostream&)>& run) {
          chatterlab::app::OutputFolder folder(out);
          work_shown = folder.work().string();
          out_shown = folder.dir().string();
          std::ostringstream held;
          int rc = 0;
          {
            RewritingBuf buf(line.quiet ? static_cast<std::ostream&>(held) : std::cout, work_shown,
                             out_shown);
            std::ostream run_log(&buf);
            rc = run(folder.work(), run_log);
            folder.commit();
            buf.release(true);
          }
          if (line.quiet && rc != 0) std::cerr << held.str();
          return rc;
        };
    if (cmd == "simulate") {
      if (positional.size() != 1 || out.empty()) {
        return usage_error("simulate takes one spec file and --out <dir>", cmd);
      }
      chatterlab::app::SimulateOptions so;
      so.pdf = report_options.pdf;
      so.report = !results_only;
      so.jobs = report_options.jobs;
      so.warnings = &std::cerr;
      return run_spec_command([&](const std::filesystem::path& work, std::ostream& run_log) {
        return chatterlab::app::run_simulate(positional[0], work, so, run_log);
      });
    }
    if (cmd == "lobes") {
      if (positional.size() != 1 || out.empty()) {
        return usage_error("lobes takes one spec file and --out <dir>", cmd);
      }
      chatterlab::app::LobesRunOptions lo;
      lo.pdf = report_options.pdf;
      lo.report = !results_only;
      lo.jobs = report_options.jobs;
      lo.warnings = &std::cerr;
      return run_spec_command([&](const std::filesystem::path& work, std::ostream& run_log) {
        return chatterlab::app::run_lobes(positional[0], work, lo, run_log);
      });
    }
    if (cmd == "synth") {
      if (positional.size() != 1 || out.empty()) {
        return usage_error("synth takes one spec file and --out <campaign>", cmd);
      }
      // As report and simulate: a folder that is not chatterlab's is refused before any work;
      // the campaign is written into a temporary folder that replaces --out once complete (a
      // bad spec changes nothing).
      chatterlab::app::OutputFolder folder(out);
      work_shown = folder.work().string();
      out_shown = folder.dir().string();
      const auto s = chatterlab::app::synthesize_campaign(positional[0], folder.work());
      folder.commit();
      for (const auto& w : s.warnings) {
        std::cerr << "chatterlab synth: warning: "
                  << RewritingBuf::rewrite(w, work_shown, out_shown) << "\n";
      }
      log << "synth: wrote campaign '" << s.campaign_name << "' with " << s.tests_written
          << " tests to " << out << "\n";
      return chatterlab::app::kExitOk;
    }
  } catch (const chatterlab::InputError& e) {
    std::cerr << "chatterlab " << cmd << ": "
              << RewritingBuf::rewrite(e.what(), work_shown, out_shown) << "\n";
    return chatterlab::app::kExitInputError;
  } catch (const std::exception& e) {
    // Not bad input: a bug or a broken invariant (exit status 3, as `report` uses for a test
    // that stopped on one).
    std::cerr << "chatterlab " << cmd
              << ": internal error: " << RewritingBuf::rewrite(e.what(), work_shown, out_shown)
              << "\n";
    return chatterlab::app::kExitInternalError;
  }
  return usage_error("unknown command '" + cmd + "'", "");
}
