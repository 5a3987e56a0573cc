// The --out folder of `report`, `simulate` and `synth` (docs/cli.md#the-output-folder). A run
// writes into a new temporary folder beside --out and, once its output is complete, exchanges
// that folder with --out in one rename: a reader, or a run killed at any moment, sees either
// the previous output or the new one, never a mix. The files of the previous --out that the
// program did not write (not listed in its manifest, `.chatterlab-files`) are carried into the
// new folder; nothing of the previous run survives. A lock beside --out keeps a second run off
// the folder. A non-empty folder without that manifest or a chatterlab results.json is refused,
// never touched; so is an --out that is a symbolic link.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "app/core/checked_write.h"

namespace chatterlab::app {

inline constexpr const char* kManifestName = ".chatterlab-files";

class OutputFolder {
 public:
  // Checks `out` before any work and prepares the run: it must be absent, an empty folder or a
  // chatterlab output folder (it holds the manifest, or a results.json whose "format" starts
  // with "chatterlab-"), not a symbolic link, not the current folder or one holding it. Takes
  // the lock `.<name>.chatterlab-lock` beside it (a second run fails at once), removes the
  // temporary folders that killed runs left beside it, and creates a new, empty temporary
  // folder `.<name>.chatterlab-tmp-<pid>-<random>` there (the folders above `out` are created
  // when missing). Throws InputError naming the folder on any refusal.
  explicit OutputFolder(const std::filesystem::path& out);
  // Without commit(): removes the temporary folder (the previous --out stays as it was).
  // Releases the lock.
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  // --out as given, without a trailing '/'.
  const std::filesystem::path& dir() const { return dir_; }
  // The temporary folder to write into (beside dir(), in the same form: relative when dir() is).
  const std::filesystem::path& work() const { return work_; }

  // Puts the output written into work() in place of dir(): writes the manifest (every file
  // below work()), carries the previous folder's files that are not the program's (by hard
  // link, else by copy; a file of the new output of the same name wins), exchanges the two
  // folders in one rename (renameat2 RENAME_EXCHANGE; a plain rename when dir() is absent)
  // and removes the previous output. Throws InputError when a step before the exchange fails
  // (dir() is then as it was). Returns the number of files carried.
  int commit();

 private:
  std::filesystem::path dir_;   // as given
  std::filesystem::path work_;  // beside dir_
  std::string name_;            // dir_'s last component
  int lock_fd_ = -1;
  bool committed_ = false;
};

// The files of an output folder that chatterlab wrote, relative with '/' separators: those
// listed in its manifest, or for a folder written before manifests the known names
// (index.html, report.pdf, report.css, results.json), every file below figures/ and the files
// its results.json names. Paths that would leave the folder are dropped.
std::vector<std::string> chatterlab_files(const std::filesystem::path& dir);

// Whether `file` is a results.json that chatterlab wrote (a JSON object whose "format" starts
// with "chatterlab-"); false for anything else, unreadable or not JSON.
bool is_chatterlab_results(const std::filesystem::path& file);

// The files below `dir` (regular files and symbolic links, relative with '/' separators,
// sorted), not entering linked folders. Exposed for tests.
std::vector<std::string> files_below(const std::filesystem::path& dir);

}  // namespace chatterlab::app
