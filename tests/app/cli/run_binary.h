// Runs the chatterlab binary (CHATTERLAB_BINARY) through the shell with stdout and stderr in
// files of their own, for the tests of what the command line prints and returns.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace chatterlab::testing {

struct BinaryRun {
  int status = -1;  // the exit status; -1 when the binary did not exit normally
  std::string out;  // stdout
  std::string err;  // stderr
};

inline std::string quoted(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

inline std::string file_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// `args` is appended to the binary's path as it is (quote paths with quoted()); the captured
// streams go to `scratch`.
inline BinaryRun run_chatterlab(const std::string& args, const std::filesystem::path& scratch) {
  const auto out = scratch / "stdout.txt";
  const auto err = scratch / "stderr.txt";
  const std::string cmd = quoted(CHATTERLAB_BINARY) + " " + args + " > " + quoted(out) + " 2> " +
                          quoted(err) + " < /dev/null";
  const int rc = std::system(cmd.c_str());
  BinaryRun r;
  r.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.out = file_text(out);
  r.err = file_text(err);
  return r;
}

}  // namespace chatterlab::testing
