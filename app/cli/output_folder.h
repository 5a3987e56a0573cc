// The --out folder of `report` and `simulate` (docs/cli.md#the-output-folder). A run into a
// folder that an earlier run wrote leaves no file of that run behind, and the program removes
// only files it wrote itself: it lists them in the folder's manifest, `.chatterlab-files`, and
// removes them at the start of the next run. A non-empty folder without that manifest or a
// chatterlab results.json is refused, never cleared.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace chatterlab::app {

inline constexpr const char* kManifestName = ".chatterlab-files";

class OutputFolder {
 public:
  // Checks `dir` before any work: absent, empty, or a chatterlab output folder (it holds the
  // manifest, or a results.json whose "format" starts with "chatterlab-"). Throws InputError
  // naming the folder otherwise.
  static OutputFolder open(const std::filesystem::path& dir);

  // Removes the files the previous run listed in the manifest (a folder written before
  // manifests existed: index.html, report.pdf, report.css, results.json, every file below
  // figures/ and the files the old results.json names) and the folders this empties; then
  // notes the files that remain (not the program's: they are kept and never listed). Only
  // paths inside the folder are touched; a symbolic link is removed, never followed. Returns
  // the number of files removed.
  int clear_previous();

  // Writes the manifest: every file below the folder that was created or changed since
  // clear_previous(). Does nothing when clear_previous() was not called.
  void write_manifest() const;

  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  bool had_manifest_ = false;
  bool cleared_ = false;
  // Files present after clearing, by relative path: their time and size then.
  std::map<std::string, std::pair<std::filesystem::file_time_type, std::uintmax_t>> kept_;
};

// Whether `file` is a results.json that chatterlab wrote (a JSON object whose "format" starts
// with "chatterlab-"); false for anything else, unreadable or not JSON.
bool is_chatterlab_results(const std::filesystem::path& file);

// The files below `dir` (regular files and symbolic links, relative with '/' separators,
// sorted), not entering linked folders. Exposed for tests.
std::vector<std::string> files_below(const std::filesystem::path& dir);

}  // namespace chatterlab::app
