// One campaign of a nightly run reported into a folder: the step the local run takes in
// process and a Slurm task takes on a node (app/nightly/slurm.h), so both classify a campaign
// the same way.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "app/pipeline/pipeline.h"

namespace chatterlab::app {

struct ComputeOutcome {
  bool written = false;   // `dest` holds the new report (exchanged in one rename)
  int exit_code = 1;      // run_report's exit status (app/cli/exit_codes.h)
  bool internal = false;  // stopped on an exception that is not bad input (exit 3)
  std::string errors;     // what the run wrote to its error stream, and the exception

  nlohmann::json to_json() const;
  static ComputeOutcome from_json(const nlohmann::json& j);
};

// Reports `campaign` into `dest` (app/cli/output_folder.h: a temporary folder beside it,
// exchanged with it once complete). Bad input (InputError: the campaign that cannot be read, a
// lock held on `dest`) leaves `dest` as it was, so does any other exception, recorded as
// internal. Never throws.
// `cache`: the per-test cache of the run (nullptr: every test is computed).
ComputeOutcome compute_campaign(const std::filesystem::path& campaign,
                                const std::filesystem::path& dest, bool pdf, int jobs,
                                ResultCache* cache = nullptr);

// The folder of run `run` of a Slurm nightly: <site>/slurm/run-<run>/ (plan.json, the job
// scripts, logs/, out/).
std::filesystem::path slurm_run_dir(const std::filesystem::path& site, std::int64_t run);

// `chatterlab nightly-task <site> --run N --task I`, a task of the job array: reports the
// campaign plan.json lists as task I into out/<name>/ and writes out/<name>.json (the
// ComputeOutcome, written beside and renamed, so the reduce job reads it whole or not at all).
// The tests it restores come from <run_dir>/cache/<name>.bin, written at submission; what it
// computed and restored goes to out/<name>.cache (TaskCache, app/nightly/test_cache.h), before
// out/<name>.json.
// Returns 0 once that file is written, whatever the campaign's outcome (the reduce job judges
// it). @throws InputError when the plan cannot be read or has no task I
int run_nightly_task(const std::filesystem::path& site, std::int64_t run, long long task,
                     std::ostream& log);

}  // namespace chatterlab::app
