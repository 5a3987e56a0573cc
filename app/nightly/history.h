// Reading a nightly site's history (app/nightly/site_db.h) back: the runs on record and the
// results.json of each campaign as it stood after a run, for `chatterlab compare --site`.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "app/nightly/site_db.h"

namespace chatterlab::app {

// A run of the history by its id ("12") or counted back from the last finished one ("last",
// "last-1"). @throws InputError naming the site and the run when there is no such run
std::int64_t resolve_run(SiteDb& db, const std::string& run);

// The results.json of every campaign that run `run` covered, as an object keyed by campaign
// name: for each, its row of that run decides. A recomputed campaign's results are the run's;
// a cached campaign's are those of the latest earlier run that computed them; a campaign that
// could not be read or stopped before its report was in place (`unreadable`, an internal error
// outside the tests) is absent. With `campaign`: that campaign's results alone.
// @throws InputError when the campaign is not in the run or has no results in it (its status
// and message named)
nlohmann::json run_results(SiteDb& db, std::int64_t run, const std::string& campaign = "");

}  // namespace chatterlab::app
