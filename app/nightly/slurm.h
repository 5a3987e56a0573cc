// `chatterlab nightly --slurm` (docs/nightly.md#on-a-cluster-slurm): the campaigns a night must
// recompute go to Slurm as one job array, a task per campaign, and a reduce job that depends on
// the array (afterany) puts their reports into the site and writes the history and the index.
// The job scripts are written into <site>/slurm/run-<N>/ for the record, with the plan they
// read (plan.json), the tasks' logs and their staged report folders.
//
// Submission runs Slurm's own commands (sbatch, squeue) found in PATH, without a shell; the
// configuration is Slurm's (SLURM_CONF or the system's).
#pragma once

#include <filesystem>
#include <ostream>
#include <string>

namespace chatterlab::app {

struct SlurmOptions {
  bool enabled = false;   // --slurm
  std::string partition;  // --partition (empty: the cluster's default partition)
  std::string time;       // --time, a task's limit in Slurm's form ("30", "1:00:00"; empty: the
                          // partition's default)
  std::string mem;        // --mem, a task's memory ("4G"; empty: the partition's default)
  bool wait = false;      // --slurm-wait: block until the reduce job has finished
};

struct SlurmJobs {
  std::string array_id;   // empty when no campaign needed a task
  std::string reduce_id;  // always submitted: it records the run and writes the index
};

// The job scripts for a run: <run_dir>/array.sh (tasks 0..task_count-1, each
// `<exe> nightly-task <site> --run <run> --task $SLURM_ARRAY_TASK_ID`) and reduce.sh
// (`<exe> nightly-reduce <site> --run <run>`), with the options as #SBATCH lines and the logs
// in <run_dir>/logs/. `cpus` is each task's --cpus-per-task (the report's worker threads).
void write_slurm_scripts(const std::filesystem::path& site, const std::filesystem::path& run_dir,
                         std::int64_t run, int task_count, int cpus, const SlurmOptions& options,
                         const std::filesystem::path& exe);

// Submits the scripts write_slurm_scripts wrote: the array (when task_count > 0), then the
// reduce job depending on it. @throws InputError with sbatch's message when a submission fails
SlurmJobs submit_slurm_scripts(const std::filesystem::path& run_dir, int task_count);

// Whether Slurm still lists the job (pending, running or completing). A job squeue does not
// know (finished long ago, or squeue not installed) is not active.
bool slurm_job_active(const std::string& job_id);

// Polls squeue until the job has left the queue.
void wait_for_slurm_job(const std::string& job_id);

// A path quoted for a POSIX shell: in single quotes, each ' written '\''.
std::string shell_quote(const std::string& s);

}  // namespace chatterlab::app
