// Runs every test of a campaign and every group product that applies, each through its kind
// (app/pipeline/kind.h). The campaign is a small dependency graph: a test or group that needs
// a value runs after every provider of that value. Nodes of one level run in parallel; each
// test is isolated: bad input skips it with the reason, a failed provider skips the consumers
// that require its value ("needs ... from ..., which was skipped: ..."), and nothing stops the
// rest of the campaign. A report never shows a number from a step that failed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/core/campaign.h"
#include "app/pipeline/campaign_values.h"
#include "app/pipeline/outcome.h"
#include "app/pipeline/registry.h"

namespace chatterlab::app {

// One test or group product that has just finished (PipelineOptions::on_finished).
struct NodeFinished {
  std::string name;  // test id ("." for the root) or "group:<name>"
  bool group = false;
  bool ok = false;
  Failure failure = Failure::kNone;
  std::string message;    // the skip or error reason when not ok
  double runtime_s = 0;   // this test's or group's own time
  double elapsed_s = 0;   // since run_campaign started
  std::size_t done = 0;   // tests and groups finished so far, this one included
  std::size_t total = 0;  // every test of the campaign and every group that applies
};

// The per-test cache of a nightly run (docs/nightly.md#the-per-test-cache), seen from the
// pipeline: the bytes kept for a test or group whose cache key has not changed, and the bytes
// of those computed now. Implemented by app/nightly.
class ResultCache {
 public:
  virtual ~ResultCache() = default;
  // The bytes kept for node `name` (a test id or "group:<name>") when its key is unchanged.
  virtual std::optional<std::string> find(const std::string& name) const = 0;
  // A node computed in this run that succeeded. Called from worker threads, concurrently.
  virtual void keep(const std::string& name, std::string bytes) = 0;
};

struct PipelineOptions {
  int jobs = 0;  // worker threads; 0: one per hardware thread
  // Called once per test or group as it finishes (progress lines), from the worker thread that
  // ran it; a test that does not run (unusable) counts as finished before the first one runs.
  // Calls never overlap (the pipeline serializes them), so the callback needs no lock of its
  // own; `done` counts up by one per call. An exception it throws is ignored.
  std::function<void(const NodeFinished&)> on_finished;
  // Tests and groups of cacheable kinds are restored from it when it holds them and kept in
  // it when they are computed (nullptr: every node runs).
  ResultCache* cache = nullptr;
};

struct InputFile {
  std::string relative_path;
  std::uintmax_t bytes = 0;
  std::string sha256;
};

struct CampaignResults {
  CampaignSpec campaign;
  const KindRegistry* kinds = nullptr;
  PipelineOptions options;
  std::vector<TestOutcome> tests;                // same order as campaign.tests
  std::vector<GroupOutcome> groups;              // products that apply, in registration order
  CampaignValues values;                         // what the tests and groups provided
  std::vector<std::vector<std::string>> levels;  // the run order: test ids / group:<name>
  std::vector<InputFile> inputs;                 // every yaml and signal file read
  double runtime_s = 0;

  const GroupOutcome* group(const std::string& name) const;
  // Tests that failed with an internal error (not bad input), and groups alike.
  int internal_errors() const;
};

// The run order of a campaign: levels of node names (test ids, "group:<name>"); a node's
// providers are all in earlier levels. Exposed for tests.
std::vector<std::vector<std::string>> schedule(const CampaignSpec& campaign,
                                               const KindRegistry& kinds);

// Opens the test's record and checks it holds the kind's channels and fits its windows; every
// problem becomes one of t.errors (the test is then unusable).
void check_signals(TestSpec& t, const KindRegistry& kinds = builtin_kinds());

// Loads nothing: takes a loaded campaign. Never throws for bad test content.
CampaignResults run_campaign(CampaignSpec campaign, const PipelineOptions& options,
                             const KindRegistry& kinds = builtin_kinds());

}  // namespace chatterlab::app
