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
// name: for each, the results of the latest run at or before `run` that recomputed it (a
// cached campaign's results are those of the run that computed them). With `campaign`: that
// campaign's results alone. @throws InputError when the campaign is not in the run
nlohmann::json run_results(SiteDb& db, std::int64_t run, const std::string& campaign = "");

}  // namespace chatterlab::app
