// chatterlab: campaign folder -> HTML report, PDF and results.json (docs/architecture.md).
#include <chrono>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "app/cli/validate.h"
#include "app/core/campaign.h"
#include "app/report/report.h"
#include "app/simulate/simulate.h"
#include "app/synth/synth.h"

namespace {

const char* kUsage =
    "usage:\n"
    "  chatterlab report <campaign> --out <dir> [--no-pdf] [--jobs N]\n"
    "      analyse every test of the campaign; write index.html, report.pdf, results.json\n"
    "  chatterlab validate <campaign>\n"
    "      list the tests found and every problem; exit 1 when any test is unusable\n"
    "  chatterlab simulate <spec.yaml> --out <dir> [--no-pdf] [--results-only]\n"
    "      one milling simulation: bifurcation depth, Poincare maps, figures, results.json\n"
    "  chatterlab synth <spec.yaml> --out <campaign>\n"
    "      write a synthetic campaign with truth.yaml (spec format: docs/synth.md)\n"
    "  chatterlab --version | --help\n";

int usage_error(const std::string& what) {
  std::cerr << "chatterlab: " << what << "\n" << kUsage;
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::cout << kUsage;
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    std::cout << "chatterlab " << CHATTERLAB_VERSION << "\n";
    return 0;
  }
  const std::string cmd = args[0];
  std::vector<std::string> positional;
  std::string out;
  chatterlab::app::ReportOptions report_options;
  bool results_only = false;
  for (std::size_t i = 1; i < args.size(); ++i) {
    if (args[i] == "--out" && i + 1 < args.size()) {
      out = args[++i];
    } else if (args[i] == "--no-pdf") {
      report_options.pdf = false;
    } else if (args[i] == "--results-only") {
      results_only = true;
    } else if (args[i] == "--jobs" && i + 1 < args.size()) {
      try {
        report_options.jobs = std::stoi(args[++i]);
      } catch (const std::exception&) {
        return usage_error("--jobs takes a whole number");
      }
    } else if (!args[i].empty() && args[i][0] == '-') {
      return usage_error("unknown option '" + args[i] + "'");
    } else {
      positional.push_back(args[i]);
    }
  }
  try {
    if (cmd == "validate") {
      if (positional.size() != 1) return usage_error("validate takes one campaign folder");
      auto campaign = chatterlab::app::load_campaign(positional[0]);
      return chatterlab::app::validate_campaign(campaign, std::cout);
    }
    if (cmd == "report") {
      if (positional.size() != 1 || out.empty()) {
        return usage_error("report takes one campaign folder and --out <dir>");
      }
      return chatterlab::app::run_report(positional[0], out, report_options, std::cout);
    }
    if (cmd == "simulate") {
      if (positional.size() != 1 || out.empty()) {
        return usage_error("simulate takes one spec file and --out <dir>");
      }
      chatterlab::app::SimulateOptions so;
      so.pdf = report_options.pdf;
      so.report = !results_only;
      so.jobs = report_options.jobs;
      return chatterlab::app::run_simulate(positional[0], out, so, std::cout);
    }
    if (cmd == "synth") {
      if (positional.size() != 1 || out.empty()) {
        return usage_error("synth takes one spec file and --out <campaign>");
      }
      const auto s = chatterlab::app::synthesize_campaign(positional[0], out);
      for (const auto& w : s.warnings) std::cerr << "chatterlab synth: warning: " << w << "\n";
      std::cout << "synth: wrote campaign '" << s.campaign_name << "' with " << s.tests_written
                << " tests to " << out << "\n";
      return 0;
    }
  } catch (const chatterlab::InputError& e) {
    std::cerr << "chatterlab " << cmd << ": " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    // Not bad input: a bug or a broken invariant (exit status 3, as `report` uses for a test
    // that stopped on one).
    std::cerr << "chatterlab " << cmd << ": internal error: " << e.what() << "\n";
    return 3;
  }
  return usage_error("unknown command '" + cmd + "'");
}
