// The nightly site's trend and estimator pages (docs/nightly.md#trends-and-estimator-comparison):
//   <site>/trends.html       per series of campaigns (those sharing a tool), each identified
//                            headline value against the run, one line per campaign, its 95 %
//                            interval as a band, and a table flagging a value that moved beyond
//                            its tolerance since the campaign's previous run ("moved") and a
//                            program version that changed ("program changed")
//   <site>/estimators.html   per series, every estimator variant on every cut: final
//                            estimates, spread over repeat runs, NIS consistency, runtime
//   <site>/figures/          their figures (SVG on screen, PNG and CSV beside)
// Every number shown is in the database's trend_values (the trends) or in the campaigns'
// results.json (the comparison): nothing is computed here but the flags.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/nightly/compare.h"

namespace chatterlab::app {

class SiteDb;

// One campaign of the run as the pages see it.
struct TrendCampaign {
  std::string name;        // folder name in the site: the campaign in trend_values
  std::string series;      // the series it belongs to (tool_series_name, else its name)
  nlohmann::json results;  // its results.json as of this run; null when it has none
};

// "2 teeth, r 6.35 mm": the name of the series of campaigns that use this tool.
std::string tool_series_name(int teeth, double radius_mm);

// "cuts/constant/ekf-modal-x/m_kg" -> {"cuts/constant", "ekf-modal-x", "m_kg"}: a trend key of
// an estimator final. A key without two '/' (an identified value) gives three empty strings.
struct EstimatorKey {
  std::string test, variant, estimate;
};
EstimatorKey split_estimator_key(const std::string& key);

struct TrendPages {
  std::size_t figures = 0;          // figures drawn
  std::vector<std::string> errors;  // figures that could not be drawn
};

// Writes trends.html, estimators.html and their figures (under figures/) into `stage`, from the
// trend_values of the finished runs and run `run_id`, for the campaigns of this run. `title`
// holds the page heads' keys (root, version, generated_utc, generated_iso). A value moved when
// compare_results with `tolerances` flags key "identified.<key>" (an estimator final:
// "tests.<test>.estimators.<variant>.estimates.<key>") between two runs of its campaign.
TrendPages write_trend_pages(const std::filesystem::path& stage, SiteDb& db, std::int64_t run_id,
                             const std::vector<TrendCampaign>& campaigns,
                             const CompareOptions& tolerances, const nlohmann::json& title,
                             int jobs);

}  // namespace chatterlab::app
