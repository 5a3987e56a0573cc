#include "app/nightly/compute.h"

#include <sstream>

#include "analysis/common/summary.h"
#include "app/cli/exit_codes.h"
#include "app/cli/output_folder.h"
#include "app/core/archive.h"
#include "app/core/checked_write.h"
#include "app/nightly/compare.h"
#include "app/nightly/test_cache.h"
#include "app/report/report.h"

namespace chatterlab::app {

nlohmann::json ComputeOutcome::to_json() const {
  return {
      {"written", written}, {"exit_code", exit_code}, {"internal", internal}, {"errors", errors}};
}

ComputeOutcome ComputeOutcome::from_json(const nlohmann::json& j) {
  ComputeOutcome o;
  o.written = j.at("written").get<bool>();
  o.exit_code = j.at("exit_code").get<int>();
  o.internal = j.at("internal").get<bool>();
  o.errors = j.at("errors").get<std::string>();
  return o;
}

ComputeOutcome compute_campaign(const std::filesystem::path& campaign,
                                const std::filesystem::path& dest, bool pdf, int jobs,
                                ResultCache* cache) {
  ComputeOutcome o;
  std::ostringstream run_log, run_err;
  ReportOptions ro;
  ro.pdf = pdf;
  ro.jobs = jobs;
  ro.errors = &run_err;
  ro.cache = cache;
  bool started = false;
  ro.before_writing = [&started] { started = true; };
  try {
    OutputFolder out(dest);
    o.exit_code = run_report(campaign, out.work(), ro, run_log);
    if (started) {
      out.commit();
      o.written = true;
    }
  } catch (const InputError& e) {
    run_err << e.what() << "\n";
    o.exit_code = kExitInputError;
  } catch (const std::exception& e) {
    run_err << "INTERNAL ERROR: " << e.what() << "\n";
    o.exit_code = kExitInternalError;
    o.internal = true;
  }
  o.errors = run_err.str();
  return o;
}

std::filesystem::path slurm_run_dir(const std::filesystem::path& site, std::int64_t run) {
  return site / "slurm" / ("run-" + std::to_string(run));
}

int run_nightly_task(const std::filesystem::path& site, std::int64_t run, long long task,
                     std::ostream& log) {
  const std::filesystem::path dir = slurm_run_dir(site, run);
  const nlohmann::json plan = read_json_file(dir / "plan.json");
  const nlohmann::json& tasks = plan.at("tasks");
  if (task < 0 || task >= static_cast<long long>(tasks.size())) {
    throw InputError((dir / "plan.json").string() + ": no task " + std::to_string(task) + " (" +
                     std::to_string(tasks.size()) + " tasks)");
  }
  const nlohmann::json& t = tasks[static_cast<std::size_t>(task)];
  const std::string name = t.at("name").get<std::string>();
  const std::filesystem::path out = dir / "out";
  std::filesystem::create_directories(out);
  log << "nightly-task " << task << ": " << t.at("path").get<std::string>() << " (" << name << ")"
      << std::endl;
  std::map<std::string, SiteResultCache::Stored> stored;
  const std::filesystem::path stored_file = dir / "cache" / (name + ".bin");
  if (std::filesystem::is_regular_file(stored_file)) {
    try {
      from_bytes(read_file_bytes(stored_file), stored);
    } catch (const InputError& e) {  // damaged: every test computed
      log << "nightly-task " << task << ": " << e.what() << "\n";
      stored.clear();
    }
  }
  SiteResultCache cache(t.at("keys").get<std::map<std::string, std::string>>(), std::move(stored));
  const ComputeOutcome o =
      compute_campaign(t.at("folder").get<std::string>(), out / name, plan.at("pdf").get<bool>(),
                       plan.at("jobs").get<int>(), &cache);
  TaskCache handed{cache.kept(), cache.restored()};
  const std::filesystem::path cache_tmp = out / ("." + name + ".cache.tmp");
  write_file_checked(cache_tmp, to_bytes(handed));
  std::filesystem::rename(cache_tmp, out / (name + ".cache"));
  const std::filesystem::path tmp = out / ("." + name + ".json.tmp");
  write_file_checked(tmp, o.to_json().dump(1) + "\n");
  std::filesystem::rename(tmp, out / (name + ".json"));
  log << "nightly-task " << task << ": exit " << o.exit_code << (o.written ? ", written" : "")
      << "\n"
      << o.errors;
  return 0;
}

}  // namespace chatterlab::app
