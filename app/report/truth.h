// Comparison of a campaign's results with a synthetic campaign's truth.yaml (docs/formats.md,
// "truth.yaml"). Each kind compares its own tests (TestKind::compare_truth) and each group
// product its own values; this file reads truth.yaml and walks its `tests:` entries.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "app/pipeline/pipeline.h"

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
// Entries of truth.yaml `tests:` are taken in file order; an entry whose key is a test id goes
// to that test's kind, and every group product sees every entry (it matches its members).
TruthComparison compare_with_truth(const CampaignResults& r);

// Adds a row when both numbers are finite.
void add_truth_row(TruthComparison& c, const std::string& quantity, const std::string& source,
                   double truth, double estimate);
// n[key] as a number; NaN when absent or not a number.
double truth_number(const YAML::Node& n, const char* key);
// truth.yaml as a node; a null node when the campaign has none or it does not parse.
YAML::Node load_truth(const CampaignSpec& c);

}  // namespace chatterlab::app
