// Writing a file of the output with every step checked (issue 16: "every write checked").
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "analysis/common/summary.h"

namespace chatterlab::app {

// Writes `text` to `path` and checks every step (open, write, close), throwing WriteError
// "cannot write <path>: <reason>" on failure. Never writes through a symbolic link (O_NOFOLLOW:
// a link at `path` fails the write).
void write_file_checked(const std::filesystem::path& path, const std::string& text);

// A file of the output that could not be opened or written whole (a full disk, a file size
// limit): unlike a test's own problem, it fails the run (exit 1), and the previous report stays.
class WriteError : public InputError {
 public:
  using InputError::InputError;
};

// `path` opened for writing (binary, truncated), or WriteError "cannot write <path>: <reason>".
std::ofstream open_for_writing(const std::filesystem::path& path);

// Closes `out` and checks that every byte written to it reached the file (the last buffered
// block is written only at the close, so a check before it misses that block's failure), or
// WriteError "cannot write <path>: <reason>".
void close_checked(std::ofstream& out, const std::filesystem::path& path);

}  // namespace chatterlab::app
