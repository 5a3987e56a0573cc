#include "app/report/truth.h"

#include <cmath>

#include "app/core/yaml_load.h"

namespace chatterlab::app {

void add_truth_row(TruthComparison& c, const std::string& q, const std::string& src, double truth,
                   double est) {
  if (!std::isfinite(truth) || !std::isfinite(est)) return;
  TruthRow row{q, src, truth, est, truth != 0 ? 100.0 * (est - truth) / std::abs(truth) : 0.0};
  c.rows.push_back(row);
}

double truth_number(const YAML::Node& n, const char* key) {
  try {
    return n[key] ? n[key].as<double>() : std::nan("");
  } catch (const YAML::Exception&) {
    return std::nan("");
  }
}

YAML::Node load_truth(const CampaignSpec& c) {
  if (!c.has_truth) return {};
  // A refused truth.yaml (compare_with_truth warns with the reason) gives no known values.
  std::vector<std::string> errors;
  const YAML::Node n = load_yaml_file(c.truth_file, "truth.yaml", &errors);
  return n ? n : YAML::Node();
}

TruthComparison compare_with_truth(const CampaignResults& r) {
  TruthComparison c;
  if (!r.campaign.has_truth) return c;
  std::vector<std::string> errors;
  const YAML::Node root = load_yaml_file(r.campaign.truth_file, "truth.yaml", &errors);
  if (!root) {
    c.warnings.insert(c.warnings.end(), errors.begin(), errors.end());
    return c;
  }
  c.present = true;
  const YAML::Node tests = root["tests"];
  if (!tests || !tests.IsMap()) return c;
  for (const auto& kv : tests) {
    if (!is_name_key(kv.first)) continue;  // refused by load_yaml_file already
    const auto key = kv.first.Scalar();
    const YAML::Node entry = kv.second;
    const TruthInput in{&root, &entry, &r};
    for (const auto& t : r.tests) {
      if (t.spec->id != key || !t.status.ok()) continue;
      if (const TestKind* kind = r.kinds->find(t.spec->kind)) kind->compare_truth(in, t, c);
    }
    for (const auto& g : r.groups) {
      if (const GroupProduct* p = r.kinds->find_group(g.name)) p->compare_truth(in, key, g, c);
    }
  }
  return c;
}

}  // namespace chatterlab::app
