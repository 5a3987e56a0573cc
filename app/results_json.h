// results.json, version 1 (EXPERIMENT_FORMAT.md section 2): every number the report shows.
#pragma once

#include <nlohmann/json.hpp>

#include "app/pipeline.h"
#include "app/truth.h"

namespace chatterlab::app {

nlohmann::json results_json(const CampaignResults& r, const TruthComparison& truth);

// Finite numbers as numbers, NaN and infinities as null (JSON has no NaN).
nlohmann::json number_or_null(double v);

}  // namespace chatterlab::app
