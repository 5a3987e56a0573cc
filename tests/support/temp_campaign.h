// Writes small campaign folders into a fresh temporary directory for loader tests.
#pragma once

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace chatterlab::testing {

class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() /
            ("chatterlab-test-" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

  // Writes `text` to path()/relative, creating folders.
  std::filesystem::path write(const std::string& relative, const std::string& text) const {
    const auto p = path_ / relative;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

 private:
  std::filesystem::path path_;
};

inline const char* kCampaignYaml =
    "format: chatterlab-campaign/1\n"
    "name: unit-test\n"
    "tool: {teeth: 2, radius_mm: 6.35}\n";

}  // namespace chatterlab::testing
