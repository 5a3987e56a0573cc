// `chatterlab nightly <archive-root> --out <site>` (docs/nightly.md): finds every campaign under
// the root (a folder holding campaign.yaml; campaigns do not nest), runs each whose inputs
// changed since the site's last run, and writes the site:
//   <site>/index.html, report.pdf   every campaign: status, last change, skipped tests and why,
//                                   headline identified values, regression flags
//   <site>/nightly.json             this run, for machines (EXPERIMENT_FORMAT section 8)
//   <site>/campaigns/<name>/        each campaign's report folder
//   <site>/history.sqlite           cache keys and run history (app/nightly/site_db.h)
// Each report folder is written into a temporary folder and exchanged with the previous one in
// one rename (app/cli/output_folder.h); the database is written in transactions after it; a
// lock keeps a second run off the site. A run killed at any moment leaves a usable site.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "app/nightly/compare.h"
#include "app/nightly/slurm.h"

namespace chatterlab::app {

struct NightlyOptions {
  bool pdf = true;    // each campaign's report.pdf and the site's
  int jobs = 0;       // worker threads inside a campaign (0: one per hardware thread)
  bool wait = false;  // another run holds the site: wait for it instead of refusing
  // Regression flags: each recomputed campaign's results.json against its previous one.
  CompareOptions tolerances;
  std::filesystem::path tolerances_file;  // where `tolerances` came from (a --slurm run copies
                                          // it for its reduce job)
  SlurmOptions slurm;                     // --slurm and its options
  std::ostream* errors = nullptr;         // where a campaign's errors go (nullptr: the log)
};

// A campaign found under the archive root.
struct ArchiveCampaign {
  std::string path;  // relative to the root, '/' separated ("." for the root itself)
  std::filesystem::path folder;
};

// Every folder holding campaign.yaml under `root`, sorted by path, not entering a campaign
// (campaigns do not nest), symbolic links or `skip` (the site when it lies inside the root).
std::vector<ArchiveCampaign> find_campaigns(const std::filesystem::path& root,
                                            const std::filesystem::path& skip = {});

// Returns the exit status (docs/nightly.md#exit-status): 0 when every campaign was read and no
// regression was flagged; 1 when a campaign could not be read or a flag was raised; 3 when a
// campaign stopped on an internal error.
// @throws InputError when the root or the site is refused (nothing is written then)
// With options.slurm.enabled the run is planned under the site's lock, its campaigns to
// recompute submitted as a job array with a reduce job (app/nightly/slurm.h), and the call
// returns 0 once they are queued; with options.slurm.wait it waits for the reduce job and
// returns the run's exit status as above.
int run_nightly(const std::filesystem::path& root, const std::filesystem::path& site,
                const NightlyOptions& options, std::ostream& log);

// `chatterlab nightly-reduce <site> --run N`, the reduce job of a --slurm run: waits for the
// site's lock, puts the reports the tasks staged into the site, writes the history, the index
// and nightly.json as a local run does, and <site>/slurm/run-N/reduce.json with the exit
// status (returned as well). A task that did not finish makes its campaign an internal error
// that keeps its previous report. @throws InputError when run N is not waiting for its reduce
int run_nightly_reduce(const std::filesystem::path& site, std::int64_t run,
                       const NightlyOptions& options, std::ostream& log);

}  // namespace chatterlab::app
