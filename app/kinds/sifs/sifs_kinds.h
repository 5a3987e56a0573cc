// Kinds `sifs-static`, `sifs-tap`, `sifs-cut` (EXPERIMENT_FORMAT section 6, source document 003,
// docs/sifs.md): the spindle-integrated force sensor ring calibrated statically (group
// `sifs-static`: the 3x3 calibration matrix over every static test), the tip-to-sensor dynamics
// of each lateral axis from hammer taps, and milling records compensated by the
// expanded-disturbance Kalman filter tuned from those taps (group `sifs-cut`: the tap-test
// RMSE(speed, q) map and the Q_opt table against the cutting optima).
//
// Order: sifs-static tests -> group sifs-static (provides the calibration) -> sifs-tap tests
// (need it) -> sifs-cut tests (need it and their axes' taps) -> group sifs-cut.
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/sifs/calibration.h"
#include "analysis/sifs/compensator.h"
#include "analysis/sifs/sensor_model.h"
#include "analysis/signal/harmonic_fit.h"
#include "app/kinds/common/hammer_hits.h"
#include "app/pipeline/kind.h"
#include "render/figure.h"

namespace chatterlab::app {

namespace value {
// sifs::StaticReduction of one static test (the group reads every one).
inline const std::string kSifsStaticRecord = "sifs-static/record";
// SifsCalibration: the group's calibration matrix.
inline const std::string kSifsCalibration = "sifs-calibration";
// std::shared_ptr<const SifsTapData> of the sifs-tap test `id`.
inline std::string sifs_tap(const std::string& id) { return "sifs-tap:" + id; }
// std::shared_ptr<const SifsCutSummary> of each sifs-cut test (the group's Q table).
inline const std::string kSifsCutSummary = "sifs-cut/summary";
}  // namespace value

// The calibration the consumers use: one matrix, or one per tool length when the static tests
// were run with several tools (test.yaml `tool_length_mm`; 003 eq. 3-4 makes the lateral
// calibration depend on the length). With two lengths or more, each entry's straight line
// C_ij(L) = slope_ij L + intercept_ij (003 eq. 3-4 generalised to every entry).
struct SifsCalibration {
  Eigen::Matrix3d C = Eigen::Matrix3d::Identity();            // the only one, or the first length's
  std::vector<std::pair<double, Eigen::Matrix3d>> by_length;  // ascending length; empty: one C
  Eigen::Matrix3d slope_per_mm = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d intercept = Eigen::Matrix3d::Zero();
  std::optional<double> single_length_mm;  // the one length the static tests name, if any
  // The matrix for a test of tool length L (mm, absent: none given): the single C; the
  // calibration of that length; else the law at L (*note says so). Throws InputError naming
  // `tool_length_mm` when several lengths were calibrated and the test gives none.
  Eigen::Matrix3d at(const std::optional<double>& length_mm, std::string* note) const;
};

// ---- sifs-static ---------------------------------------------------------------------------
struct SifsStaticSpec : KindSpec {
  sifs::Axis axis = sifs::Axis::kX;
  std::vector<sifs::LoadWindow> loads;
  std::optional<double> tool_length_mm;  // extension key: tool + holder length L of 003 eq. 3-4
};
struct SifsStaticResult : KindResult {
  sifs::StaticReduction reduction;
};
struct SifsStaticGroupResult : KindResult {
  std::vector<std::string> ids;
  std::vector<sifs::StaticReduction> tests;
  sifs::CalibrationFit fit;  // the only fit, or the first tool length's
  // Several tool lengths: one fit per length (ascending) and the law of each entry.
  std::vector<std::pair<double, sifs::CalibrationFit>> by_length;
  SifsCalibration calibration;
};

// ---- sifs-tap ------------------------------------------------------------------------------
struct SifsTapSpec : KindSpec {
  sifs::Axis axis = sifs::Axis::kX;
  HammerHits hits;
  double band_lo_hz = 0.0, band_hi_hz = 0.0;
  int modes = 3;
  std::optional<double> tool_length_mm;  // extension key: picks the calibration (see above)
};
// What a tap test gives the cuts: the fitted plant and its record (hammer and calibrated
// response along the axis, at the tap's rate) for the tuning sweep.
struct SifsTapData {
  std::string id;
  sifs::Axis axis = sifs::Axis::kX;
  std::vector<sifs::SensorMode> modes;
  double fs_hz = 0.0;
  Eigen::VectorXd hammer_n, response_n;
  std::vector<sifs::TapWindow> windows;
  std::vector<Eigen::Index> impact;  // per window, absolute sample
  double r_tap_n = 0.0;
};
struct SifsTapResult : KindResult {
  std::shared_ptr<const SifsTapData> data;
  sifs::TapFrf frf;
  sifs::SensorModel model;
  sifs::ScaledModal realization;
  double obsv_rcond = 0.0;  // plant (e^{AT}, C) at T = 1 / sample_rate_hz
  sifs::FrfConfidence confidence;
  double bandwidth_before_hz = 0.0;  // ||G| - 1| >= 0.1, 1 Hz grid up to fs / 2
  Eigen::VectorXd antiresonances_hz;
};

// ---- sifs-cut ------------------------------------------------------------------------------
struct SifsCutSpec : KindSpec {
  double spindle_rpm = 0.0;
  double air_lo_s = 0.0, air_hi_s = 0.0;
  double cut_lo_s = 0.0, cut_hi_s = 0.0;
  std::string tap_x, tap_y;  // sifs-tap test ids
  bool has_dynamometer = false;
  std::array<std::string, 3> dyn_channels{"dx", "dy", "dz"};
  double dyn_angle_deg = 0.0;
  std::optional<std::pair<double, double>> band_hz;
  std::optional<double> filter_rate_hz;
  int unbalance_harmonics = 2;
  sifs::GainMode gain = sifs::GainMode::kTimeVarying;  // extension key `gain`
  std::optional<double> tool_length_mm;  // extension key: picks the calibration (see above)
};
struct SifsAxisResult {
  StepSummary summary;
  signal::HarmonicFit unbalance;  // over the air window at the record rate (c0 = offset)
  double r_cut_n = 0.0, r_tap_n = 0.0;
  sifs::SweepCurve tap_curve;  // the tap sweep at this speed (q_opt)
  double q = 0.0;
  int q_exponent = 0;
  std::vector<int> harmonics;
  Eigen::VectorXcd c_measured, c_compensated, c_reference;  // reference: empty without one
  double rmse_compensated_n = 0.0, rmse_measured_n = 0.0;   // NaN without a reference
  sifs::SweepCurve cut_curve;  // the same sweep on the cut against the reference (validation)
  double bandwidth_before_hz = 0.0, bandwidth_after_hz = 0.0;
  double cond_F = 0.0, obsv_rcond = 0.0;
  // Time-varying gain: when it converged (s from the record start); NaN for the steady-state
  // gain or a gain that had not converged by the end of the record.
  double gain_converged_s = 0.0;
  std::vector<std::string> warnings;                       // of the axis's steps
  Eigen::VectorXd measured_n, compensated_n, reference_n;  // at the filter rate, whole record
};
struct SifsCutSummary {
  std::string id;
  double spindle_rpm = 0.0;
  std::array<int, 2> tap_exponent{0, 0}, cut_exponent{0, 0};  // 0: not available
};
struct SifsCutResult : KindResult {
  double spindle_rpm = 0.0, tooth_passing_hz = 0.0, spindle_hz = 0.0;
  double fs_hz = 0.0, filter_rate_hz = 0.0;
  int teeth = 0;
  bool has_reference = false;
  std::array<SifsAxisResult, 2> axes;       // x, y
  Eigen::Index cut_begin = 0, cut_end = 0;  // cut window at the filter rate
};
struct SifsCutGroupResult : KindResult {
  std::vector<SifsCutSummary> cuts;  // by test id
  std::array<std::string, 2> tap_ids;
  std::array<sifs::TapMap, 2> maps;  // per axis; empty rpm when the axis has no tap
  double filter_rate_hz = 0.0;
  int teeth = 0;
};

class SifsStaticKind : public TestKind {
 public:
  std::string name() const override { return "sifs-static"; }
  std::vector<std::string> keys() const override;
  std::shared_ptr<const KindSpec> parse(const YAML::Node& root, YamlReader& r) const override;
  std::vector<std::string> required_channels(const TestSpec&) const override;
  std::vector<std::string> check_record(const TestSpec& t, double duration_s) const override;
  std::vector<std::string> provides(const TestSpec&) const override;
  std::string describe_value(const std::string& name) const override;
  void run(const TestSpec& t, const CampaignValues& in, const RunContext& ctx,
           TestOutcome& out) const override;
  void publish(const TestOutcome& out, CampaignValues& values) const override;
  bool cacheable() const override { return true; }
  std::string save(const TestOutcome& out) const override;
  void restore(const TestSpec& t, const std::string& bytes, TestOutcome& out) const override;
  nlohmann::json results(const TestOutcome& out) const override;
  std::string note(const TestOutcome& out) const override;
};

class SifsStaticGroup : public GroupProduct {
 public:
  std::string name() const override { return "sifs-static"; }
  bool applies(const CampaignSpec& c) const override;
  std::vector<Need> needs(const CampaignSpec&) const override;
  std::vector<std::string> provides(const CampaignSpec&) const override;
  std::string describe_value(const std::string& name) const override;
  void run(const CampaignValues& in, const RunContext& ctx, GroupOutcome& out) const override;
  void publish(const GroupOutcome& out, CampaignValues& values) const override;
  bool cacheable() const override { return true; }
  std::string save(const GroupOutcome& out) const override;
  void restore(const std::string& bytes, GroupOutcome& out) const override;
  nlohmann::json results(const GroupOutcome& out) const override;
  void figures(const CampaignResults&, const GroupOutcome& out, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r, const GroupOutcome& out,
                                const FigureSet& figures) const override;
  void compare_truth(const TruthInput& in, const std::string& key, const GroupOutcome& out,
                     TruthComparison& c) const override;
};

class SifsTapKind : public TestKind {
 public:
  std::string name() const override { return "sifs-tap"; }
  std::vector<std::string> keys() const override;
  std::shared_ptr<const KindSpec> parse(const YAML::Node& root, YamlReader& r) const override;
  std::vector<std::string> required_channels(const TestSpec&) const override;
  std::vector<std::string> check_record(const TestSpec& t, double duration_s) const override;
  std::vector<Need> needs(const TestSpec&) const override;
  std::vector<std::string> provides(const TestSpec& t) const override;
  std::string describe_value(const std::string& name) const override;
  void run(const TestSpec& t, const CampaignValues& in, const RunContext& ctx,
           TestOutcome& out) const override;
  void publish(const TestOutcome& out, CampaignValues& values) const override;
  bool cacheable() const override { return true; }
  std::string save(const TestOutcome& out) const override;
  void restore(const TestSpec& t, const std::string& bytes, TestOutcome& out) const override;
  nlohmann::json results(const TestOutcome& out) const override;
  // <test>/frf.csv and frf.uff: H1, coherence and the fitted sensor model (sifs_tap_kind.cpp).
  void write_files(const TestOutcome& out, const std::filesystem::path& report_dir) const override;
  nlohmann::json settings(const CampaignSpec&) const override;
  std::string note(const TestOutcome& out) const override;
  void figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r,
                                const std::vector<const TestOutcome*>& ok_tests,
                                const FigureSet& figures) const override;
  void compare_truth(const TruthInput& in, const TestOutcome& out,
                     TruthComparison& c) const override;
};

class SifsCutKind : public TestKind {
 public:
  std::string name() const override { return "sifs-cut"; }
  std::vector<std::string> keys() const override;
  std::shared_ptr<const KindSpec> parse(const YAML::Node& root, YamlReader& r) const override;
  std::vector<std::string> check_campaign(const CampaignSpec& c, const TestSpec& t) const override;
  std::vector<std::string> required_channels(const TestSpec& t) const override;
  std::vector<std::string> check_record(const TestSpec& t, double duration_s) const override;
  std::vector<Need> needs(const TestSpec& t) const override;
  std::vector<std::string> provides(const TestSpec&) const override;
  std::string describe_value(const std::string& name) const override;
  void run(const TestSpec& t, const CampaignValues& in, const RunContext& ctx,
           TestOutcome& out) const override;
  void publish(const TestOutcome& out, CampaignValues& values) const override;
  bool cacheable() const override { return true; }
  std::string save(const TestOutcome& out) const override;
  void restore(const TestSpec& t, const std::string& bytes, TestOutcome& out) const override;
  nlohmann::json results(const TestOutcome& out) const override;
  void write_files(const TestOutcome& out, const std::filesystem::path& report_dir) const override;
  nlohmann::json settings(const CampaignSpec&) const override;
  std::string note(const TestOutcome& out) const override;
  void figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r,
                                const std::vector<const TestOutcome*>& ok_tests,
                                const FigureSet& figures) const override;
  void compare_truth(const TruthInput& in, const TestOutcome& out,
                     TruthComparison& c) const override;
  std::string synth_section() const override { return "sifs"; }
  std::shared_ptr<const KindSpec> parse_synth(const YAML::Node& section, const SynthContext& ctx,
                                              YamlReader& r) const override;
  int write_synth(const KindSpec& section, SynthContext& ctx) const override;
};

class SifsCutGroup : public GroupProduct {
 public:
  std::string name() const override { return "sifs-cut"; }
  bool applies(const CampaignSpec& c) const override;
  std::vector<Need> needs(const CampaignSpec& c) const override;
  std::vector<std::string> provides(const CampaignSpec&) const override { return {}; }
  void run(const CampaignValues& in, const RunContext& ctx, GroupOutcome& out) const override;
  nlohmann::json results(const GroupOutcome& out) const override;
  bool cacheable() const override { return true; }
  std::string save(const GroupOutcome& out) const override;
  void restore(const std::string& bytes, GroupOutcome& out) const override;
  nlohmann::json settings(const CampaignSpec&) const override;
  void figures(const CampaignResults&, const GroupOutcome& out, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r, const GroupOutcome& out,
                                const FigureSet& figures) const override;
};

// The speed grid of the tap-test map: 1000 to 24000 rpm in 500 rpm steps (47 speeds; 003 does
// not state its grid, notes/003.md section 4), plus every cut's speed.
std::vector<double> sifs_map_grid(const std::vector<double>& cut_rpm);

// results.json's relative path of a cut's compensated force: "<test id>/compensated.csv".
std::string sifs_compensated_path(const std::string& test_id);

// Figures (exposed for tests).
render::Figure sifs_tap_figure(const SifsTapResult& t);
render::Figure sifs_cut_spectrum_figure(const SifsCutResult& c, int axis);
render::Figure sifs_cut_rmse_figure(const SifsCutResult& c);
render::Figure sifs_map_figure(const SifsCutGroupResult& g);

}  // namespace chatterlab::app
