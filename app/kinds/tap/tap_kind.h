// Kind `tap`: impact-hammer tap tests (docs/tap-tests.md). Provides the hammer-test mode of its
// axis (the fitted mode of largest peak receptance) to the cut tests.
#pragma once

#include "app/kinds/tap/tap_step.h"
#include "app/pipeline/kind.h"
#include "render/figure.h"

namespace chatterlab::app {

namespace value {
// frf::Mode: the mode of largest peak receptance of the first tap test (by id) of each axis.
inline const std::string kHammerModeX = "hammer-mode/x";
inline const std::string kHammerModeY = "hammer-mode/y";
// std::vector<frf::Mode>: every fitted mode of the first tap test of each axis (the stability
// lobes take several modes per axis).
inline const std::string kHammerModesX = "hammer-modes/x";
inline const std::string kHammerModesY = "hammer-modes/y";
}  // namespace value

class TapKind : public TestKind {
 public:
  explicit TapKind(TapStepOptions options = {}) : options_(std::move(options)) {}

  std::string name() const override { return "tap"; }
  std::vector<std::string> keys() const override;
  std::shared_ptr<const KindSpec> parse(const YAML::Node& root, YamlReader& r) const override;
  std::vector<std::string> required_channels(const TestSpec& t) const override;
  std::vector<std::string> check_record(const TestSpec& t, double duration_s) const override;
  std::vector<std::string> check_files(const TestSpec& t) const override;
  std::vector<std::string> check_campaign(const CampaignSpec& c, const TestSpec& t) const override;
  std::vector<std::filesystem::path> input_files(const TestSpec& t) const override;
  std::vector<std::string> provides(const TestSpec& t) const override;
  std::string describe_value(const std::string& name) const override;
  void run(const TestSpec& t, const CampaignValues& in, const RunContext& ctx,
           TestOutcome& out) const override;
  void publish(const TestOutcome& out, CampaignValues& values) const override;
  bool cacheable() const override { return true; }
  std::string save(const TestOutcome& out) const override;
  void restore(const TestSpec& t, const std::string& bytes, TestOutcome& out) const override;
  nlohmann::json results(const TestOutcome& out) const override;
  // <test>/frf.csv and frf.uff: the measured and fitted FRF (docs/format/results-json.md, "Files").
  void write_files(const TestOutcome& out, const std::filesystem::path& report_dir) const override;
  nlohmann::json settings(const CampaignSpec&) const override;
  std::string note(const TestOutcome& out) const override;
  void figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r,
                                const std::vector<const TestOutcome*>& ok_tests,
                                const FigureSet& figures) const override;
  void compare_truth(const TruthInput& in, const TestOutcome& out,
                     TruthComparison& c) const override;
  std::string synth_section() const override { return "tap"; }
  std::shared_ptr<const KindSpec> parse_synth(const YAML::Node& section, const SynthContext& ctx,
                                              YamlReader& r) const override;
  int write_synth(const KindSpec& section, SynthContext& ctx) const override;

 private:
  TapStepOptions options_;
};

// The files a tap test writes beside results.json, relative to the report folder ("tap/x/frf.csv").
std::string tap_frf_csv_path(const std::string& test_id);

// <test>/frf.uff: H1, H2 (not for an FRF read from a file), the fit (function type 4, m/N) and
// the coherence (type 6) as ASCII UFF58, node 1, direction +1 (x) or +2 (y).
std::string tap_frf_uff_path(const std::string& test_id);
void write_tap_frf_uff(const TapOutcome& tap, const std::string& test_id, const std::string& axis,
                       const std::filesystem::path& file);

// Writes the FRF of a tap test as CSV (f_hz, re, im = H1, coherence, h2_re, h2_im, fit_re,
// fit_im, with a commented header stating units and provenance); read back by frf_text.
void write_tap_frf_csv(const TapOutcome& tap, const std::string& test_id,
                       const std::filesystem::path& file);

// The FRF figure of a tap test: |H1|, |H2| and the fit, phase, coherence (exposed for tests).
render::Figure tap_frf_figure(const TapOutcome& tap);

}  // namespace chatterlab::app
