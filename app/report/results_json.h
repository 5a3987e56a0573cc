// results.json, version 1 (docs/formats.md, "results.json"): every number the report shows.
// The envelope (format, campaign, generator, provenance, settings, tests, groups, truth
// comparison) is written here; each test's and group's own keys come from its kind.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "app/pipeline/pipeline.h"
#include "app/report/figure_jobs.h"
#include "app/report/truth.h"

namespace chatterlab::app {

// `figures`: what the report drew; each analysed test and group names its files in `figures`.
nlohmann::json results_json(const CampaignResults& r, const TruthComparison& truth,
                            const FigureSet& figures);

// The files of `owner`'s figures (test id, or "group:<name>") that were written, keyed by figure
// key: {"<key>": {"svg": "figures/<stem>.svg", "png": "figures/<stem>.png",
// "csv": "figures/<stem>.csv"}}, svg and png only when the figure was drawn, csv only when its
// data was written; {} when it has none (docs/format/results-json.md, "figures").
nlohmann::json figure_files_json(const FigureSet& figures, const std::string& owner);

// Finite numbers as numbers, NaN and infinities as null (JSON has no NaN).
nlohmann::json number_or_null(double v);
// The entries of v as a JSON array of numbers.
nlohmann::json number_array(const Eigen::Ref<const Eigen::VectorXd>& v);

// A test's status word: "ok", "skipped" (bad or missing input) or "error" (internal error).
const char* status_word(const StepSummary& status, Failure failure);

// Every setting the campaign's steps used, by kind and group name (results.json `settings`).
nlohmann::json settings_json(const CampaignResults& r);

// Tool version, git commit (when known) and the versions of the libraries that computed
// numbers (results.json `provenance`).
nlohmann::json provenance_json(const CampaignResults& r);

}  // namespace chatterlab::app
