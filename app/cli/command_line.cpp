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
       "chatterlab report <campaign> --out <dir> [--no-pdf] [--jobs N]",
       "analyse every test of the campaign; write index.html, report.pdf, results.json",
       {{"--out", true, "the report folder (created)"},
        {"--no-pdf", false, "write no report.pdf"},
        {"--jobs", true, "worker threads (0: one per hardware thread)"}}},
      {"validate",
       "chatterlab validate <campaign>",
       "list the tests found and every problem; exit 1 when any test is unusable",
       {}},
      {"simulate",
       "chatterlab simulate <spec.yaml> --out <dir> [--no-pdf] [--results-only] [--jobs N]",
       "one milling simulation: bifurcation depth, Poincare maps, figures, results.json",
       {{"--out", true, "the output folder (created)"},
        {"--no-pdf", false, "write no PDF"},
        {"--results-only", false, "results.json only: no figures, HTML or PDF"},
        {"--jobs", true, "figure threads (0: one per hardware thread)"}}},
      {"synth",
       "chatterlab synth <spec.yaml> --out <campaign>",
       "write a synthetic campaign with truth.yaml (spec format: docs/format/synth-spec.md)",
       {{"--out", true, "the campaign folder (created)"}}},
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

}  // namespace

std::string command_usage(const std::string& command) {
  if (command.empty()) {
    std::string u = "usage:\n";
    for (const auto& c : commands()) {
      u += std::string("  ") + c.synopsis + "\n      " + c.what + "\n";
    }
    u += "  chatterlab --version | --help | <command> --help\n";
    return u;
  }
  const CommandSpec* c = find_command(command);
  if (c == nullptr) return "";
  std::string u = std::string("usage: ") + c->synopsis + "\n  " + c->what + "\n";
  if (!c->options.empty()) u += "options:\n";
  for (const auto& o : c->options) {
    u +=
        std::string("  ") + o.name + (o.takes_value ? " <value>" : "") + "\n      " + o.help + "\n";
  }
  return u;
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
    } else if (a == "--results-only") {
      l.results_only = true;
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
