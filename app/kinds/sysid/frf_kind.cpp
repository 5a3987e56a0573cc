// Kind `frf` (format section 5): an FRF file realized as a discrete state-space model by ERA
// (001 sec. 3.2). See sysid_kinds.h and docs/sysid.md.
#include "app/core/signals.h"
#include "app/core/yaml_reader.h"
#include "app/kinds/sysid/sysid_archive.h"
#include "app/kinds/sysid/sysid_kinds.h"
#include "app/pipeline/cached_result.h"
#include "app/report/figure_jobs.h"

namespace chatterlab::app {

using nlohmann::json;

std::vector<std::string> FrfKind::keys() const {
  return {"input_unit", "output_unit", "era_max_order"};
}

std::shared_ptr<const KindSpec> FrfKind::parse(const YAML::Node& root, YamlReader& r) const {
  auto s = std::make_shared<FrfSpec>();
  s->input_unit = r.required_string(root, "input_unit");
  s->output_unit = r.required_string(root, "output_unit");
  if (const auto n = r.optional_int(root, "era_max_order", "", 1, 1000)) {
    s->era_max_order = static_cast<int>(*n);
  }
  return s;
}

std::vector<std::string> FrfKind::required_channels(const TestSpec&) const {
  return {"freq_hz", "re", "im"};
}

std::vector<std::string> FrfKind::provides(const TestSpec& t) const {
  return {value::drive_model(t.id)};
}

std::string FrfKind::describe_value(const std::string& name) const {
  return value::describe_drive_model(name);
}

void FrfKind::run(const TestSpec& t, const CampaignValues&, const RunContext&,
                  TestOutcome& out) const {
  const auto& s = t.kind_spec<FrfSpec>();
  const std::string label = t.data_label();
  const SignalTable table = SignalTable::open(t.data, label);
  const Eigen::VectorXd f = table.channel("freq_hz", t.channel("freq_hz"));
  const Eigen::VectorXd re = table.channel("re", t.channel("re"));
  const Eigen::VectorXd im = table.channel("im", t.channel("im"));
  Eigen::VectorXcd G(f.size());
  G.real() = re;
  G.imag() = im;
  auto res = std::make_unique<FrfResult>();
  sysid::EraOptions o;
  o.max_order = s.era_max_order;
  res->model = run_era_model(t, f, G, s.input_unit, s.output_unit, o);
  const auto& e = res->model.era;
  out.warnings.insert(out.warnings.end(), e.summary.warnings.begin(), e.summary.warnings.end());
  if (!e.summary.ok()) {
    out.status.fail(label + ": " + e.summary.message);
    return;
  }
  out.result = std::move(res);
  out.status.succeed();
}

template <class Ar>
void fields(Ar& ar, FrfResult& r) {
  LAYOUT_GUARD(FrfResult, 600);
  ar(r.model);
}

std::string FrfKind::save(const TestOutcome& out) const { return save_result<FrfResult>(out); }

void FrfKind::restore(const TestSpec&, const std::string& bytes, TestOutcome& out) const {
  restore_result<FrfResult>(bytes, out);
}

void FrfKind::publish(const TestOutcome& out, CampaignValues& values) const {
  values.put(value::drive_model(out.spec->id), out.spec->id,
             out.result_of<FrfResult>().model.drive);
}

json FrfKind::results(const TestOutcome& out) const {
  return era_model_json(out.result_of<FrfResult>().model);
}

std::string FrfKind::note(const TestOutcome& out) const {
  return era_model_note(out.result_of<FrfResult>().model);
}

void FrfKind::figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const {
  const auto& m = out.result_of<FrfResult>().model;
  jobs.add(out.spec->id, "frf", figure_stem("frf", out.spec->id) + "frf", era_frf_figure(m));
  jobs.add(out.spec->id, "singular-values", figure_stem("frf", out.spec->id) + "sv",
           era_singular_value_figure(m));
}

json FrfKind::report_section(const CampaignResults&, const std::vector<const TestOutcome*>& ok,
                             const FigureSet& figures) const {
  if (ok.empty()) return nullptr;
  json tests = json::array();
  for (const TestOutcome* t : ok) {
    tests.push_back(era_model_section(*t, t->result_of<FrfResult>().model, figures));
  }
  return {{"toc", json::array({{{"anchor", "frf"}, {"title", "Drive models from FRFs (ERA)"}}})},
          {"frf_tests", tests}};
}

void FrfKind::compare_truth(const TruthInput& in, const TestOutcome& out,
                            TruthComparison& c) const {
  era_model_truth(in, out, out.result_of<FrfResult>().model, c);
}

}  // namespace chatterlab::app
