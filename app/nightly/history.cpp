#include "app/nightly/history.h"

#include <algorithm>
#include <cctype>

#include "analysis/common/summary.h"

namespace chatterlab::app {

std::int64_t resolve_run(SiteDb& db, const std::string& run) {
  const std::string where = db.file().parent_path().string();
  const auto whole = [](const std::string& s) {
    return !s.empty() && s.size() < 18 && std::all_of(s.begin(), s.end(), [](char c) {
      return std::isdigit(static_cast<unsigned char>(c)) != 0;
    });
  };
  if (whole(run)) {
    const std::int64_t id = std::stoll(run);
    SiteDb::Statement s(db, "SELECT id FROM runs WHERE id = ?");
    s.bind(1, id);
    if (s.step()) return id;
    throw InputError("the site " + where + " has no run " + run);
  }
  long back = -1;
  if (run == "last") {
    back = 0;
  } else if (run.rfind("last-", 0) == 0 && whole(run.substr(5))) {
    back = std::stol(run.substr(5));
  }
  if (back < 0) {
    throw InputError("'" + run + "': a run is its number, 'last' or 'last-N'");
  }
  SiteDb::Statement s(db,
                      "SELECT id FROM runs WHERE status = 'done' ORDER BY id DESC LIMIT 1 "
                      "OFFSET ?");
  s.bind(1, static_cast<std::int64_t>(back));
  if (s.step()) return s.integer(0);
  throw InputError("the site " + where + " has no run " + run + " (fewer finished runs)");
}

nlohmann::json run_results(SiteDb& db, std::int64_t run, const std::string& campaign) {
  nlohmann::json out = nlohmann::json::object();
  std::string failed_message;  // the chosen campaign's, when it has no results in the run
  // Each campaign's own row of the run: its status, and its results when it was recomputed.
  SiteDb::Statement rows(db,
                         "SELECT name, status, message, campaign_key, results FROM campaign_runs "
                         "WHERE "
                         "run_id = ? ORDER BY name");
  rows.bind(1, run);
  // A cached campaign's results: those of the latest run before that computed them.
  SiteDb::Statement earlier(db,
                            "SELECT results FROM campaign_runs WHERE name = ? AND run_id <= ? "
                            "AND results IS NOT NULL ORDER BY run_id DESC LIMIT 1");
  while (rows.step()) {
    const std::string name = rows.text(0);
    if (!campaign.empty() && name != campaign) continue;
    const std::string status = rows.text(1);
    // A campaign reused from an earlier run keeps its key; one that failed in this run has none.
    const bool reused = !rows.text(3).empty();
    if (!rows.is_null(4)) {
      out[name] = nlohmann::json::parse(rows.blob(4));
      continue;
    }
    // Not read, or stopped before a report was in place: nothing of it stands in this run
    // (its numbers show as removed), not an earlier run's numbers.
    if (status == "unreadable" || !reused) {
      failed_message = status + (rows.text(2).empty() ? "" : ": " + rows.text(2));
      continue;
    }
    earlier.reset();
    earlier.bind(1, name).bind(2, run);
    if (earlier.step()) out[name] = nlohmann::json::parse(earlier.blob(0));
  }
  if (campaign.empty()) return out;
  if (!out.contains(campaign)) {
    throw InputError("run " + std::to_string(run) + " of the site " +
                     db.file().parent_path().string() + " has no results of campaign '" + campaign +
                     "'" + (failed_message.empty() ? "" : " (" + failed_message + ")"));
  }
  return out[campaign];
}

}  // namespace chatterlab::app
