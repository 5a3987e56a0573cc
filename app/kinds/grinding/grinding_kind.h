// Kind `grinding` (EXPERIMENT_FORMAT section 7, source document 002): one series of parts ground
// one after another with one wheel. The fast record (cycle, u_mm_s, power, Dw_mm) and the
// end-of-cycle inspections feed the four multirate EKFs of analysis/grinding/multirate_ekf.h;
// results.json carries each one's per-cycle estimates and a trajectory file beside results.json
// (docs/grinding.md, docs/format/test-kinds.md). A grinding test needs no other test and
// provides nothing.
#pragma once

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/grinding/grinding_model.h"
#include "analysis/grinding/multirate_ekf.h"
#include "app/pipeline/kind.h"
#include "render/figure.h"

namespace chatterlab::app {

// test.yaml keys of a grinding test beyond the common ones.
struct GrindingSpec : KindSpec {
  // inspections.file as written (relative to the test folder); empty: no inspection at all.
  std::string inspections_file;
  grinding::GrindingParameters model;
  std::optional<double> roundness_sd_um;  // noise.roundness_sd_um (no estimator uses it)
  // noise and filter (sample_period_s is set from sample_rate_hz when the test runs).
  grinding::GrindingFilterSettings filter;
  std::vector<grinding::Dressing> dressings;
};

// The observability rank of one estimator over operating points of its own trajectory.
struct GrindingObservabilityResult {
  bool ok = false;
  std::string message;  // why it could not be computed
  int min_rank = 0, max_rank = 0, states = 0, points = 0;
  int full_rank_points = 0;  // points at which the rank is the number of states
};

struct GrindingEstimatorResult {
  grinding::GrindingRun run;
  double runtime_s = 0;
  double nees_per_dof = std::numeric_limits<double>::quiet_NaN();  // only with truth
  GrindingObservabilityResult observability;
};

struct GrindingResult : KindResult {
  int cycles = 0;
  std::vector<int> n;  // n_i per cycle
  std::vector<grinding::Inspection> inspections;
  std::vector<GrindingEstimatorResult> estimators;  // kGrindingEstimators order
  // truth.yaml tests.<id>.per_cycle, when present and of the series' length: Vw_mm2, v_mm_s,
  // ds_mm, R0_um per cycle, and R_a (um).
  bool has_truth = false;
  Eigen::MatrixX4d truth;
  std::vector<double> truth_Ra_um;
};

class GrindingKind : public TestKind {
 public:
  std::string name() const override { return "grinding"; }
  std::vector<std::string> keys() const override;
  std::shared_ptr<const KindSpec> parse(const YAML::Node& root, YamlReader& r) const override;
  std::vector<std::string> check_campaign(const CampaignSpec& c, const TestSpec& t) const override;
  std::vector<std::filesystem::path> input_files(const TestSpec& t) const override;
  std::vector<std::string> check_files(const TestSpec& t) const override;
  std::vector<std::string> required_channels(const TestSpec&) const override {
    return {"cycle", "u_mm_s", "power", "Dw_mm"};
  }
  void run(const TestSpec& t, const CampaignValues& in, const RunContext& ctx,
           TestOutcome& out) const override;
  bool cacheable() const override { return true; }
  std::string save(const TestOutcome& out) const override;
  void restore(const TestSpec& t, const std::string& bytes, TestOutcome& out) const override;
  nlohmann::json results(const TestOutcome& out) const override;
  void write_files(const TestOutcome& out, const std::filesystem::path& report_dir) const override;
  nlohmann::json settings(const CampaignSpec& c) const override;
  std::string note(const TestOutcome& out) const override;
  void figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r,
                                const std::vector<const TestOutcome*>& ok_tests,
                                const FigureSet& figures) const override;
  void compare_truth(const TruthInput& in, const TestOutcome& out,
                     TruthComparison& c) const override;
  std::string synth_section() const override { return "grinding"; }
  std::shared_ptr<const KindSpec> parse_synth(const YAML::Node& section, const SynthContext& ctx,
                                              YamlReader& r) const override;
  int write_synth(const KindSpec& section, SynthContext& ctx) const override;
};

// RMS over the cycles with an inspected d_s of the a priori d_s at the cycle end minus that
// d_s, in um, and the number of such cycles (NaN, 0 without any): results.json
// `ds_prior_rms_error_vs_inspection_um` and the report's column.
std::pair<double, int> prior_vs_inspection(const grinding::GrindingRun& run,
                                           const std::vector<grinding::Inspection>& ins);

// The inspections CSV of format section 7 (header cycle[,available_cycle],ds_mm,Ra_um,
// roundness_um; empty or nan: not measured; no available_cycle column: on time). `label` names
// the file in messages; a column beyond these (an operator's name) is read past with a note
// in `warnings`. @throws InputError
std::vector<grinding::Inspection> read_inspections(const std::filesystem::path& file,
                                                   const std::string& label,
                                                   std::vector<std::string>& warnings);

// The trajectory file of one estimator: `cycle,j`, the states and their 3sigma with the
// per_cycle names, one row per filter instant (format section 7). @throws InputError
void write_grinding_trajectory(const std::filesystem::path& file, const grinding::GrindingRun& run);

// results.json's relative path of an estimator's trajectory: "<test id>/<estimator>.csv".
std::string grinding_trajectory_path(const std::string& test_id, const std::string& estimator);

// Figures of a grinding test (exposed for tests): wheel diameter with 3-sigma bands,
// inspections and truth; R0 and R_a predicted against measured (xr ids).
render::Figure grinding_ds_figure(const GrindingResult& g);
render::Figure grinding_r0_figure(const GrindingResult& g);

}  // namespace chatterlab::app
