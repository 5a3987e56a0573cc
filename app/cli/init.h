// `chatterlab init <folder> [--write]` (docs/cli.md#init): looks at the data files of a folder
// (delimited text, UFF dataset 58, MATLAB .mat, FRF tables), through the project's own readers,
// and proposes the campaign.yaml and test.yaml files that describe them: the kind of each test
// guessed from its channel names, the sample rate from a time column (or the file's own
// abscissa step), the column mapping and the text dialect. Every guess carries its reason as a
// YAML comment; what could not be decided is a `# TODO` comment in place of its key, so that
// `chatterlab validate` then names it. Files are written only on request, only inside the
// folder, and an existing campaign.yaml or test.yaml is never overwritten.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace chatterlab::app {

// One file of the proposal.
struct InitFile {
  std::string path;     // relative to the folder, '/' separated ("tap-x/test.yaml")
  std::string content;  // the YAML text, comments included
  bool exists = false;  // a file of that name is already there: it is never overwritten
  bool written = false;
};

// What `init` found: a line per data file (its test and why, or why no test), and the files.
struct InitProposal {
  std::filesystem::path folder;
  std::vector<std::string> findings;  // "hits.csv: tap test 'hits' (...)"
  std::vector<InitFile> files;        // campaign.yaml first, then test.yaml files by path
  int data_files = 0;                 // data files looked at (described ones included)
  int tests = 0;                      // test.yaml files proposed (existing ones included)
};

// Looks at every data file below `folder` (hidden entries, linked folders and chatterlab report
// folders left out) and proposes the files. Writes nothing. Throws InputError when `folder` is
// not a folder.
InitProposal propose_campaign(const std::filesystem::path& folder);

// Writes every proposed file that does not exist yet (creating its test folder inside the
// folder); sets `written`. Throws InputError naming the file when one cannot be written.
void write_proposal(InitProposal& proposal);

// The command: prints the findings and each file (content, or that it exists and is kept),
// writes with `write`, and says what to run next. Returns the exit status: 0, or 1 when the
// folder holds no data file or cannot be read.
int run_init(const std::filesystem::path& folder, bool write, std::ostream& out);

}  // namespace chatterlab::app
