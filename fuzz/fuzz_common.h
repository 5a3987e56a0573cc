// Helpers shared by the fuzz targets: a per-process temporary folder for the readers that
// take a path, and the one exception a reader may throw for bad input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace chatterlab::fuzz {

// A folder of this process's own (removed at exit), created on first use under TMPDIR.
const std::filesystem::path& temp_dir();

// Writes `size` bytes to `name` inside temp_dir() and returns its path.
std::filesystem::path write_input(const std::string& name, const std::uint8_t* data,
                                  std::size_t size);

}  // namespace chatterlab::fuzz
