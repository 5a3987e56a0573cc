// Kinds `dyno-frf` and `force-record` (EXPERIMENT_FORMAT section 4, source document 004,
// docs/forcerec.md): a table dynamometer's model per axis from hammer tests on it, and cut
// records whose force the dynamometer's resonances distorted, reconstructed by three methods.
#pragma once

#include <Eigen/Core>
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/forcerec/akf.h"
#include "analysis/forcerec/deconvolution.h"
#include "analysis/forcerec/force_metrics.h"
#include "analysis/forcerec/model.h"
#include "analysis/forcerec/smo.h"
#include "analysis/forcerec/transfer_fit.h"
#include "analysis/sifs/sensor_model.h"
#include "app/kinds/common/hammer_hits.h"
#include "app/pipeline/kind.h"
#include "render/figure.h"

namespace chatterlab::app {

namespace value {
// std::shared_ptr<const DynoModel> of the dyno-frf test `id`.
inline std::string dyno_model(const std::string& id) { return "dyno-model:" + id; }
// The same value under the axis ('x', 'y', 'z'): every dyno-frf test of the axis provides it, so
// a force record finds the campaign's models of an axis without naming them.
inline std::string dyno_axis(char axis) { return std::string("dyno-axis:") + axis; }
}  // namespace value

// What a dyno-frf test gives the force records: the fitted model of one axis.
struct DynoModel {
  std::string id;
  char axis = 'x';  // 'x' | 'y' | 'z'
  forcerec::TransferModel model;
  forcerec::ContinuousModel realization;  // scaled modal form (transfer_fit.h)
  double fit_pct = 0.0;
};

// ---- dyno-frf ------------------------------------------------------------------------------
struct DynoFrfSpec : KindSpec {
  char axis = 'x';
  HammerHits hits;
  // Fit band; band_given false: the default [50, min(4000, 0.4 sample_rate_hz)] Hz.
  bool band_given = false;
  double band_lo_hz = 0.0, band_hi_hz = 0.0;
  int order = 6;
};
struct DynoFrfResult : KindResult {
  sifs::TapFrf frf;  // H1 (dynamometer N per hammer N) over the hit windows, with coherence
  forcerec::TransferFit fit;
  double band_lo_hz = 0.0, band_hi_hz = 0.0;  // as asked (the fit's are the points inside)
  std::shared_ptr<const DynoModel> model;
};

class DynoFrfKind : public TestKind {
 public:
  std::string name() const override { return "dyno-frf"; }
  std::vector<std::string> keys() const override;
  std::shared_ptr<const KindSpec> parse(const YAML::Node& root, YamlReader& r) const override;
  std::vector<std::string> required_channels(const TestSpec&) const override;
  std::vector<std::string> check_record(const TestSpec& t, double duration_s) const override;
  std::vector<std::string> provides(const TestSpec& t) const override;
  std::string describe_value(const std::string& name) const override;
  void run(const TestSpec& t, const CampaignValues& in, const RunContext& ctx,
           TestOutcome& out) const override;
  void publish(const TestOutcome& out, CampaignValues& values) const override;
  bool cacheable() const override { return true; }
  std::string save(const TestOutcome& out) const override;
  void restore(const TestSpec& t, const std::string& bytes, TestOutcome& out) const override;
  nlohmann::json results(const TestOutcome& out) const override;
  std::string note(const TestOutcome& out) const override;
  void figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r,
                                const std::vector<const TestOutcome*>& ok_tests,
                                const FigureSet& figures) const override;
  void compare_truth(const TruthInput& in, const TestOutcome& out,
                     TruthComparison& c) const override;
  // The synth section `forcerec` (forcerec_synth.cpp): hammer tests of 004 Table 3.1's axes.
  std::string synth_section() const override { return "forcerec"; }
  std::shared_ptr<const KindSpec> parse_synth(const YAML::Node& section, const SynthContext& ctx,
                                              YamlReader& r) const override;
  int write_synth(const KindSpec& section, SynthContext& ctx) const override;
};

// The measured FRF over the model in the fit band (magnitude, phase) and the coherence.
render::Figure dyno_frf_figure(const DynoFrfResult& r);

// ---- force-record --------------------------------------------------------------------------
struct ForceRecordSpec : KindSpec {
  std::string operation;  // report only
  double spindle_rpm = 0.0;
  std::optional<std::pair<double, double>> air_window_s;
  std::map<char, double> noise_var_N2;  // required per axis when air_window_s is absent
  std::optional<std::pair<double, double>> cut_window_s;
  std::map<char, std::string> frf_tests;  // axis -> dyno-frf test id
  // reference.force: the known force (interval means), raw floats, no calibration.
  bool has_reference = false;
  DataSpec reference;
  // akf_S_N2: knee (nullopt) or a number.
  std::optional<double> akf_S_N2;
  forcerec::SmoOptions smo;
  forcerec::AlphaRule rd_rule = forcerec::AlphaRule::kDiscrepancy;
  double rd_alpha = 0.0;  // with kFixed
};

// One method on one axis with one model.
struct ForceMethodResult {
  std::string id;  // akf | smo | rd
  bool ok = false;
  std::string message;  // why it failed
  std::vector<std::string> warnings;
  double runtime_s = 0.0;
  Eigen::VectorXd force_N;   // emptied for other models (only their figures are kept)
  Eigen::Index samples = 0;  // of the reconstructed force
  bool has_harmonics = false;
  forcerec::Harmonics harmonics;
  std::optional<forcerec::ReferenceError> error;  // with a reference
  // The tuning: akf S (N^2), rd alpha; smo rho and delta are the options.
  double tuning = 0.0;
  double delta_N = 0.0, a22s_1_s = 0.0;  // smo
  forcerec::AkfResult akf;               // force moved out (E(S) curve kept)
  forcerec::SmoResult smo;               // force moved out
  forcerec::DeconvolutionResult rd;      // force moved out (L-curve kept)
};

// An axis with a model other than the one it is reconstructed with (004 sec. 4.5: a model that
// drifted): each method's force error against the reference.
struct ForceOtherModel {
  std::string frf_test;
  std::array<ForceMethodResult, 3> methods;
};

struct ForceAxisResult {
  char axis = 'x';
  bool done = false;
  std::string skip_reason;
  std::string frf_test;
  std::shared_ptr<const DynoModel> model;
  double noise_var_N2 = 0.0;
  bool noise_from_air = false;
  Eigen::VectorXd measured_N;
  Eigen::VectorXd reference_N;  // empty without a reference
  forcerec::Harmonics measured_harmonics;
  std::optional<forcerec::Harmonics> reference_harmonics;  // with a reference
  std::optional<double> measured_nrmse_pct;
  std::array<ForceMethodResult, 3> methods;  // akf, smo, rd
  std::vector<ForceOtherModel> other_models;
};

struct ForceRecordResult : KindResult {
  Eigen::Index samples = 0;
  double sample_rate_hz = 0.0;
  double tooth_freq_hz = 0.0;
  int harmonic_count = 0;
  int teeth = 0;
  double cut_begin_s = 0.0, cut_end_s = 0.0;
  forcerec::IndexWindow harmonic_window;
  forcerec::IndexWindow evaluation_window;
  std::vector<ForceAxisResult> axes;  // x, y (z when recorded)
};

// The force file of a force-record test, relative to results.json: forces/<id, / as __>.f32.
std::string force_file_path(const std::string& test_id);

class ForceRecordKind : public TestKind {
 public:
  std::string name() const override { return "force-record"; }
  std::vector<std::string> keys() const override;
  std::vector<std::string> reference_blocks() const override { return {"force"}; }
  std::shared_ptr<const KindSpec> parse(const YAML::Node& root, YamlReader& r) const override;
  std::vector<std::string> check_campaign(const CampaignSpec& c, const TestSpec& t) const override;
  std::vector<std::filesystem::path> input_files(const TestSpec& t) const override;
  std::vector<std::string> required_channels(const TestSpec&) const override;
  std::vector<std::string> check_record(const TestSpec& t, double duration_s) const override;
  std::vector<Need> needs(const TestSpec& t) const override;
  void run(const TestSpec& t, const CampaignValues& in, const RunContext& ctx,
           TestOutcome& out) const override;
  bool cacheable() const override { return true; }
  std::string save(const TestOutcome& out) const override;
  void restore(const TestSpec& t, const std::string& bytes, TestOutcome& out) const override;
  nlohmann::json results(const TestOutcome& out) const override;
  void write_files(const TestOutcome& out, const std::filesystem::path& report_dir) const override;
  std::string note(const TestOutcome& out) const override;
  void figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r,
                                const std::vector<const TestOutcome*>& ok_tests,
                                const FigureSet& figures) const override;
  void compare_truth(const TruthInput& in, const TestOutcome& out,
                     TruthComparison& c) const override;
};

}  // namespace chatterlab::app
