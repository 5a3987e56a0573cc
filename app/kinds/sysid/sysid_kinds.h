// Kinds `frf` and `sweep-frf` (EXPERIMENT_FORMAT section 5, source document 001, docs/sysid.md):
// a discrete state-space model of a spindle drive realized by ERA from a measured FRF (`frf`),
// or from the torque-to-current FRF built out of speed-loop sine sweeps (`sweep-frf`). Both
// provide the model to the spindle-current tests that name them.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "analysis/sysid/era.h"
#include "app/pipeline/kind.h"
#include "render/figure.h"

namespace chatterlab::app {

namespace value {
// std::shared_ptr<const DriveModel> of the frf or sweep-frf test `id`.
inline std::string drive_model(const std::string& id) { return "drive-model:" + id; }
}  // namespace value

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
  nlohmann::json results(const TestOutcome& out) const override;
  std::string note(const TestOutcome& out) const override;
  void figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const override;
  nlohmann::json report_section(const CampaignResults& r,
                                const std::vector<const TestOutcome*>& ok_tests,
                                const FigureSet& figures) const override;
  void compare_truth(const TruthInput& in, const TestOutcome& out,
                     TruthComparison& c) const override;
};

// ---- shared by frf and sweep-frf (era_model.cpp) -----------------------------------------
// Runs ERA on (f, G) and fills `out` (status, warnings, result) for test `t`.
EraModelResult run_era_model(const TestSpec& t, const Eigen::VectorXd& f_hz,
                             const Eigen::VectorXcd& G, const std::string& input_unit,
                             const std::string& output_unit, int era_max_order);
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
