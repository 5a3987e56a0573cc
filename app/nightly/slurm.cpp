#include "app/nightly/slurm.h"

#include <chrono>
#include <thread>

#include "analysis/common/summary.h"
#include "app/core/checked_write.h"
#include "render/render_error.h"
#include "render/subprocess.h"

namespace chatterlab::app {

namespace fs = std::filesystem;

namespace {

std::string sbatch_lines(const std::string& name, const fs::path& log, int cpus,
                         const SlurmOptions& o) {
  std::string s = "#SBATCH --job-name=" + name + "\n#SBATCH --output=" + log.string() + "\n";
  s += "#SBATCH --cpus-per-task=" + std::to_string(cpus) + "\n";
  if (!o.partition.empty()) s += "#SBATCH --partition=" + o.partition + "\n";
  if (!o.time.empty()) s += "#SBATCH --time=" + o.time + "\n";
  if (!o.mem.empty()) s += "#SBATCH --mem=" + o.mem + "\n";
  return s;
}

// Runs a Slurm command; its stdout, or InputError with its stderr.
std::string run_slurm(const std::vector<std::string>& argv) {
  render::ProcessResult r;
  try {
    r = render::run_process(argv);
  } catch (const render::RenderError& e) {
    throw InputError(argv[0] + ": cannot be run (is Slurm installed and in PATH?): " + e.what());
  }
  if (r.exit_code != 0) {
    throw InputError(argv[0] + " failed (exit " + std::to_string(r.exit_code) +
                     "): " + render::tail_of(r.err, 600));
  }
  return r.out;
}

// sbatch --parsable prints "<id>" or "<id>;<cluster>".
std::string job_id(const std::string& out) {
  std::string id;
  for (char c : out) {
    if (c == ';' || c == '\n') break;
    id += c;
  }
  if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
    throw InputError("sbatch: unexpected answer '" + out + "' (expected a job id)");
  }
  return id;
}

}  // namespace

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') {
      q += "'\\''";
    } else {
      q += c;
    }
  }
  return q + "'";
}

void write_slurm_scripts(const fs::path& site, const fs::path& run_dir, std::int64_t run,
                         int task_count, int cpus, const SlurmOptions& options,
                         const fs::path& exe) {
  fs::create_directories(run_dir / "logs");
  const std::string run_text = std::to_string(run);
  const std::string head = "#!/bin/sh\n# chatterlab nightly --slurm, run " + run_text +
                           " of the site " + site.filename().string() +
                           " (docs/nightly.md#on-a-cluster-slurm)\n";
  if (task_count > 0) {
    std::string a = head + sbatch_lines("chatterlab-nightly-" + run_text,
                                        run_dir / "logs" / "task-%a.out", cpus, options);
    a += "#SBATCH --array=0-" + std::to_string(task_count - 1) + "\n";
    a += "exec " + shell_quote(exe.string()) + " nightly-task " + shell_quote(site.string()) +
         " --run " + run_text + " --task \"$SLURM_ARRAY_TASK_ID\"\n";
    write_file_checked(run_dir / "array.sh", a);
  }
  std::string r = head + sbatch_lines("chatterlab-nightly-" + run_text + "-reduce",
                                      run_dir / "logs" / "reduce.out", 1, options);
  r += "exec " + shell_quote(exe.string()) + " nightly-reduce " + shell_quote(site.string()) +
       " --run " + run_text + "\n";
  write_file_checked(run_dir / "reduce.sh", r);
}

SlurmJobs submit_slurm_scripts(const fs::path& run_dir, int task_count) {
  SlurmJobs jobs;
  const std::string chdir = "--chdir=" + run_dir.string();
  if (task_count > 0) {
    jobs.array_id =
        job_id(run_slurm({"sbatch", "--parsable", chdir, (run_dir / "array.sh").string()}));
  }
  std::vector<std::string> argv = {"sbatch", "--parsable", chdir};
  if (!jobs.array_id.empty()) argv.push_back("--dependency=afterany:" + jobs.array_id);
  argv.push_back((run_dir / "reduce.sh").string());
  try {
    jobs.reduce_id = job_id(run_slurm(argv));
  } catch (const InputError&) {
    // No reduce job: the array's results would never reach the site.
    if (!jobs.array_id.empty()) {
      try {
        run_slurm({"scancel", jobs.array_id});
      } catch (const InputError&) {
      }
    }
    throw;
  }
  return jobs;
}

bool slurm_job_active(const std::string& job_id) {
  render::ProcessResult r;
  try {
    r = render::run_process({"squeue", "-h", "-j", job_id, "-o", "%T"});
  } catch (const render::RenderError&) {
    return false;
  }
  if (r.exit_code != 0) return false;  // "Invalid job id specified": long gone
  return r.out.find_first_not_of(" \n") != std::string::npos;
}

void wait_for_slurm_job(const std::string& job_id) {
  while (slurm_job_active(job_id)) std::this_thread::sleep_for(std::chrono::milliseconds(500));
}

}  // namespace chatterlab::app
