// What an output folder holds, for the tests of app/cli/output_folder.h: its entries and the
// lines of its manifest, read directly (not through the code under test).
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "app/cli/output_folder.h"

namespace chatterlab::testing {

using Files = std::vector<std::string>;

// The entries of a folder (names, sorted), links not followed.
inline Files names_in(const std::filesystem::path& dir) {
  Files out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    out.push_back(e.path().filename().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The paths the folder's manifest lists (comment and empty lines left out), in file order.
inline Files manifest_lines(const std::filesystem::path& dir) {
  std::ifstream in(dir / app::kManifestName);
  Files listed;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') listed.push_back(line);
  }
  return listed;
}

}  // namespace chatterlab::testing
