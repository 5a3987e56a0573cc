// Comparison of identified values with a synthetic campaign's truth.yaml (EXPERIMENT_FORMAT.md).
#pragma once

#include <map>
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
// Identified per-tooth coefficients are compared tooth for tooth after relabelling by the
// offset: an offset found a whole tooth pitch s away from the truth's describes the same tool
// with tooth p called p - s (docs/identification.md, "Tooth labels").
TruthComparison compare_with_truth(const CampaignResults& r);

// Reference values of a cut test's estimates for the percent-error figures (000 figs 6.1-6.17),
// by key (m_kg, Kt1_N_m2, ...), with where each came from: test.yaml `reference` first, then
// truth.yaml (relabelled as above), then the test's own identified values.
struct ReferenceValue {
  double value = 0.0;
  std::string source;  // "test.yaml reference" | "truth.yaml" | "identified"
};
std::map<std::string, ReferenceValue> reference_values(const CampaignResults& r,
                                                       const TestOutcome& t);

}  // namespace chatterlab::app
