// The input boundary (issue 16): every file a test.yaml names (data.file, frf.file,
// inspections.file, ...) is resolved here, and nothing is read or hashed that this has not
// accepted. The rule (docs/format/campaign.md, "Files a test names"):
// - the path is relative to the test folder; an absolute path is refused;
// - `..` is allowed while the path stays inside the campaign root (a file shared one level up);
// - a symlink is followed only when its target, fully resolved, stays inside the campaign root;
// - the target is an existing regular file: never a folder, FIFO, socket or device (checked
//   with the file's status before anything opens it, so a FIFO never blocks).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace chatterlab::app {

struct TestSpec;

struct InputFileCheck {
  std::filesystem::path path;  // test folder / value, lexically normal (when problem is empty)
  std::string problem;         // "'<value>': is a FIFO, not a regular file"; empty: accepted
  bool ok() const { return problem.empty(); }
  // The problem without the quoted value in front of it ("is a FIFO, not a regular file"), for
  // a value the message names otherwise (campaign.yaml, a test.yaml).
  std::string reason() const {
    const std::size_t at = problem.find("': ");
    return at == std::string::npos ? problem : problem.substr(at + 3);
  }
};

// Checks `value` (a file key's value as written in a test.yaml in `test_folder`) against the
// rule above (an empty `campaign_root`: the test folder is the boundary). Never throws and
// never opens the file.
InputFileCheck check_input_file(const std::filesystem::path& campaign_root,
                                const std::filesystem::path& test_folder, const std::string& value);

// The same, throwing InputError "<yaml_label>: key '<key>' '<value>': <why>" on a problem;
// returns the path to open.
std::filesystem::path resolve_input_file(const std::filesystem::path& campaign_root,
                                         const std::filesystem::path& test_folder,
                                         const std::string& yaml_label, const std::string& key,
                                         const std::string& value);
// For a loaded test (its campaign root, folder and yaml label).
std::filesystem::path resolve_input_file(const TestSpec& t, const std::string& key,
                                         const std::string& value);

// The message for a key whose value has `problem` (as YamlReader::error words it).
std::string input_file_message(const std::string& yaml_label, const std::string& key,
                               const std::string& problem);

// The largest file a campaign may name (4 GiB): a larger one is refused before anything reads
// or hashes it (docs/format/campaign.md, "Files a test names"). A record of a few minutes at
// 100 kHz on a few channels is a few hundred megabytes as CSV; a file beyond this is a mistake
// (a disk image, a video) that would exhaust memory or take minutes to hash.
inline constexpr std::uintmax_t kMaxInputFileBytes = std::uintmax_t{4} << 30;

// Why `file` is not an existing regular file of at most kMaxInputFileBytes ("is a FIFO, not a
// regular file"; "file not found"; "is 5.4 GB, above the 4 GiB limit of an input file"), from
// its status (symlinks followed, nothing opened); empty when it is one.
std::string regular_file_problem(const std::filesystem::path& file);

// True when `file`, symlinks resolved, lies inside `campaign_root` and is a regular file: the
// only files provenance hashing reads.
bool regular_file_inside(const std::filesystem::path& campaign_root,
                         const std::filesystem::path& file);

}  // namespace chatterlab::app
