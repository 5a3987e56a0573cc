// Comparison of identified values with a synthetic campaign's truth.yaml (EXPERIMENT_FORMAT.md).
#pragma once

#include <string>
#include <vector>

#include "app/pipeline.h"

namespace chatterlab::app {

struct TruthRow {
  std::string quantity;  // results.json key, e.g. "Ktc_N_m2" or "mode1.fn_hz"
  std::string source;    // test id or group ("dyno/")
  double truth = 0;
  double estimate = 0;
  double error_pct = 0;  // 100 (estimate - truth) / |truth|
};

struct TruthComparison {
  bool present = false;
  std::vector<TruthRow> rows;
  std::vector<std::string> warnings;  // unreadable truth.yaml entries
};

// Reads campaign.truth_file when present; only values from steps that succeeded are compared.
TruthComparison compare_with_truth(const CampaignResults& r);

}  // namespace chatterlab::app
