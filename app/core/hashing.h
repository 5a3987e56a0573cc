#pragma once

#include <filesystem>
#include <string>

namespace chatterlab::app {

// Lower-case hex SHA-256 of a file's bytes (provenance: results.json "inputs_sha256").
// Throws InputError when the file cannot be read.
std::string sha256_file(const std::filesystem::path& file);

// Lower-case hex SHA-256 of bytes in memory (the nightly cache keys).
std::string sha256_text(const std::string& bytes);

}  // namespace chatterlab::app
