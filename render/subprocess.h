// Running an external tool (gnuplot, WeasyPrint) without a shell and capturing its output.
#pragma once

#include <string>
#include <vector>

namespace chatterlab::render {

struct ProcessResult {
  int exit_code = -1;  // the tool's exit status; 128 + N when killed by signal N
  std::string out;     // everything it wrote to stdout
  std::string err;     // everything it wrote to stderr
};

// Runs argv[0] (searched in PATH) with arguments argv[1..], stdin from /dev/null, and
// waits for it. posix_spawn, not fork, so that it is safe from a multithreaded pipeline.
// Throws RenderError when the program cannot be started (e.g. not installed); a program
// that starts and fails is reported through exit_code, not thrown.
ProcessResult run_process(const std::vector<std::string>& argv);

// The last `max_chars` characters of a tool's stderr, trimmed, for an error message.
std::string tail_of(const std::string& text, std::size_t max_chars = 2000);

}  // namespace chatterlab::render
