// Kind `dyno-slot`: rotating-dynamometer slot cuts (000 sec. 3.2, docs/dyno-coefficients.md),
// and the group product over them: the line fit of mean force magnitude against feed that
// gives Ktc, Kte, Krc, Kre, provided to the cut tests as the campaign's cutting coefficients.
#pragma once

#include "analysis/cutting/dyno_options.h"
#include "analysis/cutting/dyno_slot.h"
#include "analysis/cutting/slot_fit.h"
#include "app/pipeline/kind.h"
#include "render/figure.h"

namespace chatterlab::app {

namespace value {
inline const std::string kDynoSlotRecord = "dyno-slot/record";  // DynoRecordOutcome, per test
// milling::CuttingCoefficients (Ktc, Kte, Krc, Kre) from the group's line fit.
inline const std::string kCuttingCoefficients = "cutting-coefficients";
}  // namespace value

// test.yaml keys of a dyno-slot test.
struct DynoSlotSpec : KindSpec {
  double spindle_rpm = 0.0;
  double feed_per_tooth_m = 0.0;
  double axial_depth_m = 0.0;
};

// One analysed record: what the test provides to the group (value::kDynoSlotRecord).
struct DynoRecordOutcome : KindResult {
  std::string id;
  double feed_per_tooth_m = 0, axial_depth_m = 0, spindle_rpm = 0;
  cutting::SlotRecordResult result;
};

struct DynoGroupResult : KindResult {
  std::vector<DynoRecordOutcome> records;  // the analysed records, by test id
  cutting::SlotCoefficients fit;
};

class DynoSlotKind : public TestKind {
 public:
  explicit DynoSlotKind(cutting::DynoOptions options = {}) : options_(options) {}

  std::string name() const override { return "dyno-slot"; }
  std::vector<std::string> keys() const override;
  std::shared_ptr<const KindSpec> parse(const YAML::Node& root, YamlReader& r) const override;
  std::vector<std::string> check_campaign(const CampaignSpec& c, const TestSpec& t) const override;
  std::vector<std::string> required_channels(const TestSpec&) const override {
    return {"Fx", "Fy", "zero"};
  }
  std::vector<std::string> provides(const TestSpec&) const override;
  std::string describe_value(const std::string& name) const override {
    return name == value::kDynoSlotRecord ? "a dyno-slot record" : "";
  }
  void run(const TestSpec& t, const CampaignValues& in, const RunContext& ctx,
           TestOutcome& out) const override;
  void publish(const TestOutcome& out, CampaignValues& values) const override;
  bool cacheable() const override { return true; }
  std::string save(const TestOutcome& out) const override;
  void restore(const TestSpec& t, const std::string& bytes, TestOutcome& out) const override;
  nlohmann::json results(const TestOutcome& out) const override;
  nlohmann::json settings(const CampaignSpec&) const override;
  std::string note(const TestOutcome& out) const override;
  std::string synth_section() const override { return "dyno"; }
  std::shared_ptr<const KindSpec> parse_synth(const YAML::Node& section, const SynthContext& ctx,
                                              YamlReader& r) const override;
  int write_synth(const KindSpec& section, SynthContext& ctx) const override;

 private:
  cutting::DynoOptions options_;
};

class DynoSlotGroup : public GroupProduct {
 public:
  explicit DynoSlotGroup(cutting::DynoOptions options = {}) : options_(options) {}

  std::string name() const override { return "dyno-slot"; }
  bool applies(const CampaignSpec& c) const override;
  std::vector<Need> needs(const CampaignSpec&) const override;
  std::vector<std::string> provides(const CampaignSpec&) const override;
  std::string describe_value(const std::string& name) const override {
    return name == value::kCuttingCoefficients ? "the dynamometer cutting coefficients" : "";
  }
  void run(const CampaignValues& in, const RunContext& ctx, GroupOutcome& out) const override;
  void publish(const GroupOutcome& out, CampaignValues& values) const override;
  bool cacheable() const override { return true; }
  std::string save(const GroupOutcome& out) const override;
  void restore(const std::string& bytes, GroupOutcome& out) const override;
  nlohmann::json results(const GroupOutcome& out) const override;
  nlohmann::json settings(const CampaignSpec&) const override;
  void figures(const CampaignResults&, const GroupOutcome& out, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r, const GroupOutcome& out,
                                const FigureSet& figures) const override;
  void compare_truth(const TruthInput& in, const std::string& key, const GroupOutcome& out,
                     TruthComparison& c) const override;

 private:
  cutting::DynoOptions options_;
};

// Mean force magnitudes against feed with the fitted lines (exposed for tests).
render::Figure dyno_force_figure(const DynoGroupResult& g);

}  // namespace chatterlab::app
