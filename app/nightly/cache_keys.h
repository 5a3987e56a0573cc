// The cache key of every test of a campaign (docs/nightly.md#cache-keys): a SHA-256 over what
// the test's numbers depend on. Two runs give a test the same key exactly when
//  - its test.yaml, its data file and every other file its kind reads (input_files) have the
//    same bytes,
//  - campaign.yaml and truth.yaml have the same bytes (the settings a kind reads live in
//    campaign.yaml; truth.yaml decides the truth comparison),
//  - every value it needs comes from the same providers with the same keys (a new hammer test
//    changes the key of every cut that uses its mode; a group product's key is made the same
//    way from its own needs),
//  - and the program (version, commit) and the options that reach results.json are the same.
// A test whose key changed is recomputed, and so is every test that depends on it: their keys
// hold its key.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "app/core/campaign.h"
#include "app/pipeline/registry.h"

namespace chatterlab::app {

struct CampaignKeys {
  std::map<std::string, std::string> tests;   // test id ("." for a test at the root) -> key
  std::map<std::string, std::string> groups;  // "group:<name>" -> key, for products that apply
  // test id -> every test that uses its values, directly or through others (sorted)
  std::map<std::string, std::vector<std::string>> dependents;
};

// `program` identifies the program and the options that reach the results ("0.1.0 <commit>
// jobs=0"). Files that cannot be read count as missing (their absence is part of the key).
CampaignKeys campaign_keys(const CampaignSpec& campaign, const std::string& program,
                           const KindRegistry& kinds = builtin_kinds());

}  // namespace chatterlab::app
