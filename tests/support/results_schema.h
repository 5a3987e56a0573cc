// Runs tests/support/validate_json_schema.py (Debian's python3-jsonschema) on one results.json
// against docs/results.schema.json, for the end-to-end tests of the kinds.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace chatterlab::testing {

struct SchemaCheck {
  bool valid = false;  // exit status 0 and the file reported ": valid"
  std::string output;  // what the validator printed (the errors of an invalid file)
};

inline SchemaCheck check_results_schema(const std::filesystem::path& results_json) {
  const std::filesystem::path source(CHATTERLAB_SOURCE_DIR);
  const std::string cmd =
      "/usr/bin/python3 '" + (source / "tests/support/validate_json_schema.py").string() + "' '" +
      (source / "docs/results.schema.json").string() + "' '" + results_json.string() + "' 2>&1";
  SchemaCheck c;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return c;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, pipe)) c.output += buf;
  const int rc = ::pclose(pipe);
  c.valid = WIFEXITED(rc) && WEXITSTATUS(rc) == 0 && c.output.find(": valid") != std::string::npos;
  return c;
}

}  // namespace chatterlab::testing
