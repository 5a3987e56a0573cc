// Kinds `dyno-frf` and `force-record` (EXPERIMENT_FORMAT section 4, source document 004,
// docs/forcerec.md): a table dynamometer's model per axis from hammer tests on it, and cut
// records whose force the dynamometer's resonances distorted, reconstructed by three methods.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "analysis/forcerec/model.h"
#include "analysis/forcerec/transfer_fit.h"
#include "analysis/sifs/sensor_model.h"
#include "app/kinds/common/hammer_hits.h"
#include "app/pipeline/kind.h"
#include "render/figure.h"

namespace chatterlab::app {

namespace value {
// std::shared_ptr<const DynoModel> of the dyno-frf test `id`.
inline std::string dyno_model(const std::string& id) { return "dyno-model:" + id; }
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

}  // namespace chatterlab::app
