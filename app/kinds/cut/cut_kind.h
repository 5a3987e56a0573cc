// Kind `cut`: milling runs with deflection sensors and a tachometer (000 secs 3.1, 5.1, ch. 4
// and 6; docs/cut-processing.md, docs/identification.md). Needs the hammer-test modes and the
// dynamometer coefficients (optional: without them the offset and identification steps say
// why they did not run); its identified values become the campaign's `identified` block.
#pragma once

#include <map>

#include "app/kinds/cut/cut_spec.h"
#include "app/kinds/cut/cut_step.h"
#include "app/kinds/cut/cut_summary.h"
#include "app/kinds/dyno_slot/dyno_slot_kind.h"
#include "app/kinds/tap/tap_kind.h"
#include "app/pipeline/kind.h"
#include "app/pipeline/pipeline.h"
#include "render/figure.h"

namespace chatterlab::app {

class CutKind : public TestKind {
 public:
  std::string name() const override { return "cut"; }
  std::vector<std::string> keys() const override;
  std::shared_ptr<const KindSpec> parse(const YAML::Node& root, YamlReader& r) const override;
  std::vector<std::string> campaign_blocks() const override { return {"estimation"}; }
  std::shared_ptr<const KindSpec> parse_campaign_block(const std::string& key,
                                                       const YAML::Node& block,
                                                       YamlReader& r) const override;
  std::vector<std::string> check_campaign(const CampaignSpec& c, const TestSpec& t) const override;
  std::vector<std::string> required_channels(const TestSpec&) const override {
    return {"x", "y", "tach"};
  }
  std::vector<std::string> check_record(const TestSpec& t, double duration_s) const override;
  std::vector<Need> needs(const TestSpec&) const override;
  std::vector<std::string> provides(const TestSpec&) const override { return {value::kCutSummary}; }
  std::string describe_value(const std::string& name) const override;
  void run(const TestSpec& t, const CampaignValues& in, const RunContext& ctx,
           TestOutcome& out) const override;
  void publish(const TestOutcome& t, CampaignValues& values) const override;
  bool cacheable() const override { return true; }
  std::string save(const TestOutcome& out) const override;
  void restore(const TestSpec& t, const std::string& bytes, TestOutcome& out) const override;
  nlohmann::json results(const TestOutcome& t) const override;
  // <test>/identified.csv: the test's identified values (cut_results.cpp).
  void write_files(const TestOutcome& t, const std::filesystem::path& report_dir) const override;
  void campaign_results(const CampaignResults& r, nlohmann::json& root) const override;
  nlohmann::json settings(const CampaignSpec& c) const override;
  std::string note(const TestOutcome& t) const override;
  void figures(const CampaignResults& r, const TestOutcome& t, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r,
                                const std::vector<const TestOutcome*>& ok_tests,
                                const FigureSet& figures) const override;
  void compare_truth(const TruthInput& in, const TestOutcome& t, TruthComparison& c) const override;
  std::string synth_section() const override { return "cut"; }
  std::shared_ptr<const KindSpec> parse_synth(const YAML::Node& section, const SynthContext& ctx,
                                              YamlReader& r) const override;
  int write_synth(const KindSpec& section, SynthContext& ctx) const override;
};

// The estimation options of the campaign (campaign.yaml `estimation:`, defaults when absent).
const EstimationOptions& estimation_options(const CampaignSpec& c);

// What a cut test takes from the campaign (000 sec. 5.1): the hammer-test modes and the
// dynamometer coefficients, with the reasons when they are missing.
CutStepInputs cut_inputs(const CampaignSpec& c, const CampaignValues& values);

// The cut test whose identification gives the campaign's `identified` block
// (docs/identification.md): the first constant-depth cut test (by id) whose identification
// succeeded, else the first ramped one; null when none succeeded.
const TestOutcome* identification_source(const CampaignResults& r);

// "<test>/identified.csv", relative to the report folder; the unit of a results key by its
// suffix ("k_N_m" -> "N/m", "-" for none).
std::string identified_csv_path(const std::string& test_id);
std::string unit_of_key(const std::string& key);

// Reference values of a cut test's estimates for the percent-error figures (000 figs 6.1-6.17),
// by key (m_kg, Kt1_N_m2, ...), with where each came from: test.yaml `reference` first, then
// truth.yaml (relabelled by the offset, docs/identification.md "Tooth labels"), then the test's
// own identified values.
struct ReferenceValue {
  double value = 0.0;
  std::string source;  // "test.yaml reference" | "truth.yaml" | "identified"
};
std::map<std::string, ReferenceValue> reference_values(const CampaignResults& r,
                                                       const TestOutcome& t);

// Figure models (exposed for tests).
render::Figure cut_processing_figure(const CutOutcome& c);
render::Figure cut_offset_figure(const sync::OffsetAngleResult& o);
// Percent error of a variant's estimates against time, one panel per estimate key: the run
// and its seeded repeatability runs (000 figs 6.1-6.17, 6.19-6.20). A key without a reference
// is shown as the difference from the run's own final value.
render::Figure estimator_error_figure(const VariantOutcome& v,
                                      const std::map<std::string, ReferenceValue>& reference);
// Chip thickness of every tooth at the start of the filter window (000 fig. 6.18).
render::Figure chip_thickness_figure(const CutEstimation& e);

}  // namespace chatterlab::app
