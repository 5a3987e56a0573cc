#pragma once

#include <filesystem>
#include <string>

namespace chatterlab::app {

// Lower-case hex SHA-256 of a file's bytes (provenance: results.json "inputs_sha256").
// Throws InputError when the file cannot be read.
std::string sha256_file(const std::filesystem::path& file);

}  // namespace chatterlab::app
