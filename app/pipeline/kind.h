// A test kind as a module (docs/architecture.md, "Adding a test kind"). A kind owns its
// test.yaml keys and parser, the channels its record needs, what it needs from the other tests
// of the campaign and what it provides to them, its step, its results.json block, its report
// section (templates/kinds/<name>.html), its figures and its truth comparison. A group product
// (the dyno-slot line fit over every dyno-slot test, later the stability lobes) is the same
// idea over a set of tests: it needs values the tests provide and provides values of its own.
//
// The pipeline (app/pipeline/pipeline.h) orders the campaign's tests and group products by
// what they need and provide, runs independent ones in parallel and skips, with the reason, a
// consumer whose required input failed.
#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/core/campaign.h"
#include "app/pipeline/campaign_values.h"
#include "app/pipeline/outcome.h"

namespace chatterlab::app {

class YamlReader;
class FigureJobs;
struct FigureSet;
struct CampaignResults;
struct TruthComparison;
struct SynthContext;

// A value a test or group needs, by its name in CampaignValues (campaign_values.h).
// required: without it the consumer is skipped ("needs the ... from ..., which was skipped:
// ..."); optional: the consumer runs and the step that needed it says why it did not run.
struct Need {
  std::string value;
  bool required = false;
};

// What a step may use while it runs.
struct RunContext {
  const CampaignSpec* campaign = nullptr;
  int jobs = 1;  // threads the step may use inside itself
};

// Where a kind's truth comparison reads from: truth.yaml's entry for the test (its `tests:` key
// equal to the test id) and the whole file (for campaign-wide blocks such as `modal`).
struct TruthInput {
  const YAML::Node* root = nullptr;
  const YAML::Node* entry = nullptr;
  const CampaignResults* results = nullptr;
};

class TestKind {
 public:
  virtual ~TestKind() = default;

  // The test.yaml `kind` value ("tap").
  virtual std::string name() const = 0;

  // test.yaml keys of this kind beyond the common ones (kind, sample_rate_hz, data, channels,
  // reference), for the unknown-key check.
  virtual std::vector<std::string> keys() const = 0;
  // Parses those keys; every problem goes to `r` (the test becomes unusable on an error).
  virtual std::shared_ptr<const KindSpec> parse(const YAML::Node& root, YamlReader& r) const = 0;
  // campaign.yaml blocks this kind owns (the cut kind's `estimation:`).
  virtual std::vector<std::string> campaign_blocks() const { return {}; }
  // Parses one of them; an absent block arrives as a null node (the defaults). Problems go to
  // `r`: they do not stop the campaign; the kind's steps that use the block fail with them and
  // `validate` reports them.
  virtual std::shared_ptr<const KindSpec> parse_campaign_block(const std::string& /*key*/,
                                                               const YAML::Node& /*block*/,
                                                               YamlReader& /*r*/) const {
    return nullptr;
  }
  // Keys under test.yaml `reference` that are blocks this kind parses itself (force-record's
  // `reference.force: {file, channels}`), not the common numbers of known values.
  virtual std::vector<std::string> reference_blocks() const { return {}; }
  // Campaign-wide requirements checked after loading (a cut needs campaign.yaml's tool):
  // returns the problems, each naming the file and key.
  virtual std::vector<std::string> check_campaign(const CampaignSpec&, const TestSpec&) const {
    return {};
  }
  // Files the test reads beside campaign.yaml, its test.yaml and its data file (an inspections
  // table a key names), hashed into results.json `inputs_sha256`: paths inside the campaign
  // (check_campaign() has checked them); a missing one is left out.
  virtual std::vector<std::filesystem::path> input_files(const TestSpec&) const { return {}; }
  // Channels the record must hold.
  virtual std::vector<std::string> required_channels(const TestSpec&) const = 0;
  // Checks of the record against the test.yaml once its length is known (a window inside it, a
  // reference record as long as it).
  virtual std::vector<std::string> check_record(const TestSpec&, double /*duration_s*/) const {
    return {};
  }
  // Reads the files input_files() names that do not depend on the record (a measured FRF, an
  // inspections table) with the step's own reader and returns its refusals: `validate` and
  // `report` run this alike before computing (pipeline check_signals), so that a file the step
  // would refuse makes the test unusable in both.
  virtual std::vector<std::string> check_files(const TestSpec&) const { return {}; }

  virtual std::vector<Need> needs(const TestSpec&) const { return {}; }
  virtual std::vector<std::string> provides(const TestSpec&) const { return {}; }
  // What a value this kind provides is, for messages ("the hammer-test mode of x"); empty for
  // names it does not provide.
  virtual std::string describe_value(const std::string&) const { return ""; }

  // The step. Bad input throws InputError (the test is skipped with the message); any other
  // exception is an internal error. Sets out.status and out.result; a failed step leaves
  // out.status failed with its message.
  virtual void run(const TestSpec&, const CampaignValues& in, const RunContext&,
                   TestOutcome& out) const = 0;
  // Puts what the test provides into `values` (called only when the step succeeded).
  virtual void publish(const TestOutcome&, CampaignValues&) const {}

  // results.json: keys merged into the test's entry (only for a test whose step succeeded).
  virtual nlohmann::json results(const TestOutcome&) const { return nlohmann::json::object(); }
  // Files of a test whose step succeeded, written beside results.json (a filter's trajectory,
  // a reconstructed force): under `report_dir / <test id>/`, each named in results() by its
  // path relative to report_dir (EXPERIMENT_FORMAT sections 4-7). Called by `report` before
  // results.json is written; an exception is reported as a warning naming the test.
  virtual void write_files(const TestOutcome&, const std::filesystem::path& /*report_dir*/) const {}
  // Keys at the top level of results.json (the cut kind's `identified`), from every test.
  virtual void campaign_results(const CampaignResults&, nlohmann::json&) const {}
  // The settings this kind's steps used, for results.json `settings` and the report.
  virtual nlohmann::json settings(const CampaignSpec&) const { return nlohmann::json::object(); }

  // A line for the report's table of tests.
  virtual std::string note(const TestOutcome&) const { return ""; }
  // Figures of one test whose step succeeded.
  virtual void figures(const CampaignResults&, const TestOutcome&, FigureJobs&) const {}
  // The report section: the context of templates/kinds/<name>.html for the tests of this kind
  // whose step succeeded (null: no section).
  virtual nlohmann::json report_section(const CampaignResults&,
                                        const std::vector<const TestOutcome*>& ok_tests,
                                        const FigureSet&) const {
    (void)ok_tests;
    return nullptr;
  }
  // Comparison with truth.yaml (a synthetic campaign's known values).
  virtual void compare_truth(const TruthInput&, const TestOutcome&, TruthComparison&) const {}

  // The per-test cache of nightly runs (docs/nightly.md#the-per-test-cache): a kind whose step
  // result can be written as bytes (app/core/archive.h) and read back is restored instead of
  // run when its cache key is unchanged. save() is called for a step that succeeded; restore()
  // sets out.result from what save() wrote (the pipeline restores the status, warnings and
  // runtime, then calls publish() as after a run). restore() throws InputError on damaged bytes
  // (the test is then run).
  virtual bool cacheable() const { return false; }
  virtual std::string save(const TestOutcome&) const { return {}; }
  virtual void restore(const TestSpec&, const std::string& /*bytes*/, TestOutcome&) const {}

  // `chatterlab synth` (app/synth/synth.h, docs/format/synth-spec.md): the top-level section of
  // a synth spec this kind writes tests from (`tap`); empty when the kind has no synth writer.
  virtual std::string synth_section() const { return ""; }
  // Parses that section; every problem goes to `r`, keyed `<section>.<key>`. `ctx` holds the
  // spec's seed and tool (its out and truth are not yet in use).
  virtual std::shared_ptr<const KindSpec> parse_synth(const YAML::Node& /*section*/,
                                                      const SynthContext& /*ctx*/,
                                                      YamlReader& /*r*/) const {
    return nullptr;
  }
  // Writes the section's tests under ctx.out and adds the values used to ctx.truth (the entry
  // of each test, keyed by its id, and campaign-wide values). Returns the number of tests
  // written. @throws InputError for a spec the parser could not judge alone
  virtual int write_synth(const KindSpec& /*section*/, SynthContext& /*ctx*/) const { return 0; }
};

class GroupProduct {
 public:
  virtual ~GroupProduct() = default;

  // Its key under results.json `groups` and its report template (templates/kinds/<name>.html).
  virtual std::string name() const = 0;
  // Whether the campaign has this product (the dyno-slot fit: any dyno-slot test).
  virtual bool applies(const CampaignSpec&) const = 0;
  virtual std::vector<Need> needs(const CampaignSpec&) const = 0;
  virtual std::vector<std::string> provides(const CampaignSpec&) const = 0;
  virtual std::string describe_value(const std::string&) const { return ""; }

  // Sets out.status, out.result and out.members. Same error rules as TestKind::run.
  virtual void run(const CampaignValues& in, const RunContext&, GroupOutcome& out) const = 0;
  virtual void publish(const GroupOutcome&, CampaignValues&) const {}

  // results.json `groups.<name>` (for any status: a failed product says why).
  virtual nlohmann::json results(const GroupOutcome&) const = 0;
  virtual nlohmann::json settings(const CampaignSpec&) const { return nlohmann::json::object(); }
  virtual void figures(const CampaignResults&, const GroupOutcome&, FigureJobs&) const {}
  virtual nlohmann::json report_section(const CampaignResults&, const GroupOutcome&,
                                        const FigureSet&) const {
    return nullptr;
  }
  // As TestKind's (the per-test cache); out.members is restored by the pipeline.
  virtual bool cacheable() const { return false; }
  virtual std::string save(const GroupOutcome&) const { return {}; }
  virtual void restore(const std::string& /*bytes*/, GroupOutcome&) const {}
  // truth.yaml `tests:` entry `key` (a group is matched by its members' common prefix).
  virtual void compare_truth(const TruthInput&, const std::string& /*key*/, const GroupOutcome&,
                             TruthComparison&) const {}
};

}  // namespace chatterlab::app
