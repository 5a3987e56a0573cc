// Kinds `frf` and `sweep-frf` (EXPERIMENT_FORMAT section 5, source document 001, docs/sysid.md):
// a discrete state-space model of a spindle drive realized by ERA from a measured FRF (`frf`),
// or from the torque-to-current FRF built out of speed-loop sine sweeps (`sweep-frf`). Both
// provide the model to the spindle-current tests that name them.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/sysid/era.h"
#include "analysis/sysid/torque_observer.h"
#include "app/pipeline/kind.h"
#include "render/figure.h"

namespace chatterlab::app {

namespace value {
// std::shared_ptr<const DriveModel> of the frf or sweep-frf test `id`.
inline std::string drive_model(const std::string& id) { return "drive-model:" + id; }
// "the ERA model of <id>" for a drive_model name, else empty (TestKind::describe_value).
std::string describe_drive_model(const std::string& name);
}  // namespace value

// A test id as one file name: every '/' replaced by '_' (torque/<id>.csv, truth files).
std::string underscored(std::string id);

// What a model test gives its consumers.
struct DriveModel {
  std::string id;
  sysid::DiscreteStateSpace model;  // the stable part
  std::string input_unit, output_unit;
};

// The ERA step of both kinds and what it reports.
struct EraModelResult {
  sysid::EraResult era;
  std::string input_unit, output_unit;
  std::shared_ptr<const DriveModel> drive;
};

// ---- frf -----------------------------------------------------------------------------------
struct FrfSpec : KindSpec {
  std::string input_unit, output_unit;
  int era_max_order = 40;
};
struct FrfResult : KindResult {
  EraModelResult model;
};

class FrfKind : public TestKind {
 public:
  std::string name() const override { return "frf"; }
  std::vector<std::string> keys() const override;
  std::shared_ptr<const KindSpec> parse(const YAML::Node& root, YamlReader& r) const override;
  std::vector<std::string> required_channels(const TestSpec&) const override;
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
  // The synth section `era` (era_synth.cpp): frf tests of random systems with noise.
  std::string synth_section() const override { return "era"; }
  std::shared_ptr<const KindSpec> parse_synth(const YAML::Node& section, const SynthContext& ctx,
                                              YamlReader& r) const override;
  int write_synth(const KindSpec& section, SynthContext& ctx) const override;
};

// ---- sweep-frf -----------------------------------------------------------------------------
struct SweepFrfSpec : KindSpec {
  double spindle_rpm = 0.0;
  double band_lo_hz = 0.0, band_hi_hz = 0.0;
  double torque_constant_Nm_per_A = 0.0;
  int segment_samples = 4096;
  int era_max_order = 40;
};
// The loop FRFs of 001 eqs 3.4-3.6 and 3.9 on the Welch grid, every one an H1-type ratio of
// cross-spectra against the speed command (sweep_frf_kind.cpp).
struct SweepFrfs {
  Eigen::VectorXd f_hz;
  Eigen::VectorXcd G_o, G_loop, G_s, G_dtau;
  // Coherence of speed, current and current_act with the speed command.
  Eigen::VectorXd coh_speed, coh_current, coh_current_act;
  int segments = 0;
  Eigen::Index band_begin = 0, band_end = 0;  // [begin, end) of the bins inside sweep_band_hz
};
struct SweepFrfResult : KindResult {
  SweepFrfs frfs;
  EraModelResult model;
  double min_coherence_in_band = 0.0;  // of the three channels
};

// The FRFs of a sweep record: Welch cross-spectra S_rx = E[conj(R) X] of speed_ref r against
// e = r - speed, speed, current and current_act; G_o = S_r,speed / S_r,e, G_loop =
// S_r,speed / S_r,current, G_s = S_r,speed / S_r,current_act and G_dtau = S_r,speed S_r,current
// / (Kt S_r,current_act S_rr) (= G_s (G_o / G_loop) / (Kt (1 + G_o)), 001 eqs 3.7-3.9).
// @throws InputError (segment, lengths, non-finite samples)
SweepFrfs sweep_frfs(const Eigen::VectorXd& speed_ref, const Eigen::VectorXd& speed,
                     const Eigen::VectorXd& current, const Eigen::VectorXd& current_act,
                     double fs_hz, int segment, double Kt, double band_lo_hz, double band_hi_hz);

class SweepFrfKind : public TestKind {
 public:
  std::string name() const override { return "sweep-frf"; }
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
  // The synth section `spindle` (sysid_synth.cpp): the sweep and the spindle-current cuts.
  std::string synth_section() const override { return "spindle"; }
  std::shared_ptr<const KindSpec> parse_synth(const YAML::Node& section, const SynthContext& ctx,
                                              YamlReader& r) const override;
  int write_synth(const KindSpec& section, SynthContext& ctx) const override;
};

// The three loop FRFs (magnitude) and the coherences of a sweep.
render::Figure sweep_loop_figure(const SweepFrfResult& r);

// ---- spindle-current -----------------------------------------------------------------------
struct SpindleCurrentSpec : KindSpec {
  double current_resolution_A = 0.0;
  std::string model;  // a frf or sweep-frf test id
  double spindle_rpm = 0.0;
  bool up_milling = true;
  double radial_immersion_m = 0.0, axial_depth_m = 0.0, feed_per_tooth_m = 0.0;
  double Ktc_N_m2 = 0.0, Kte_N_m = 0.0;
  double air_lo_s = 0.0, air_hi_s = 0.0, cut_lo_s = 0.0, cut_hi_s = 0.0;
  std::string dyno_file;  // as written; empty: no dynamometer
  double dyno_rate_hz = 0.0;
  // Beyond the contract: manual overrides of the automatic tuning (001 sec. 4.3).
  std::optional<double> Q_Nm2, R_A2;
};
struct SpindleCurrentResult : KindResult {
  std::string model_id;
  double fs_hz = 0.0;
  double friction_current_A = 0.0;
  sysid::TorqueObserver observer;
  double bandwidth_hz = 0.0;
  bool Q_from_cut = true, R_from_resolution = true;
  double helix_deg = 0.0;
  Eigen::VectorXd torque_Nm;     // whole record, at fs
  Eigen::VectorXd reference_Nm;  // resampled to fs, air mean removed; empty without one
  Eigen::Index cut_begin = 0, cut_end = 0;
  double torque_mean_Nm = 0.0, tooth_pass_amplitude_Nm = 0.0, tooth_pass_hz = 0.0;
  double rmse_Nm = 0.0, nrmse_pct = 0.0;
  double observer_runtime_s = 0.0;
};

class SpindleCurrentKind : public TestKind {
 public:
  std::string name() const override { return "spindle-current"; }
  std::vector<std::string> keys() const override;
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
  // torque/<test id, / as _>.csv: t, torque (format section 5).
  void write_files(const TestOutcome& out, const std::filesystem::path& report_dir) const override;
  std::string note(const TestOutcome& out) const override;
  void figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r,
                                const std::vector<const TestOutcome*>& ok_tests,
                                const FigureSet& figures) const override;
  void compare_truth(const TruthInput& in, const TestOutcome& out,
                     TruthComparison& c) const override;
};

// results.json's relative path of a test's torque: "torque/<id with / as _>.csv".
std::string spindle_torque_path(const std::string& test_id);
// Figures: the estimate over the reference (time, over a few tooth periods of the cut window,
// and amplitude spectrum), and the estimator's magnitude response.
render::Figure spindle_torque_figure(const SpindleCurrentResult& r);
render::Figure spindle_observer_response_figure(const SpindleCurrentResult& r);

// ---- shared by frf and sweep-frf (era_model.cpp) -----------------------------------------
// Runs ERA on (f, G) and fills `out` (status, warnings, result) for test `t`.
EraModelResult run_era_model(const TestSpec& t, const Eigen::VectorXd& f_hz,
                             const Eigen::VectorXcd& G, const std::string& input_unit,
                             const std::string& output_unit, const sysid::EraOptions& options);
// results.json `model` block (format section 5).
nlohmann::json era_model_json(const EraModelResult& m);
// One line for the table of tests: "order 12 (ERA 14, 2 unstable removed), fit 98.7 %".
std::string era_model_note(const EraModelResult& m);
// Report rows of one test (the template's fields of templates/kinds/frf.html).
nlohmann::json era_model_section(const TestOutcome& t, const EraModelResult& m,
                                 const FigureSet& figures);
// Truth rows: modes by nearest natural frequency, the DC gain, the order.
void era_model_truth(const TruthInput& in, const TestOutcome& out, const EraModelResult& m,
                     TruthComparison& c);
// Figures: the FRF against the model (magnitude, phase) and the singular values with the
// threshold.
render::Figure era_frf_figure(const EraModelResult& m);
render::Figure era_singular_value_figure(const EraModelResult& m);

}  // namespace chatterlab::app
