// Writing a file of the output with every step checked (issue 16: "every write checked").
#pragma once

#include <filesystem>
#include <string>

namespace chatterlab::app {

// Writes `text` to `path` and checks every step (open, write, close), throwing InputError
// "cannot write <path>: <reason>" on failure. Never writes through a symbolic link (O_NOFOLLOW:
// a link at `path` fails the write).
void write_file_checked(const std::filesystem::path& path, const std::string& text);

}  // namespace chatterlab::app
