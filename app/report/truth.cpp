#include "app/report/truth.h"

#include <cmath>

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
  try {
    return YAML::LoadFile(c.truth_file.string());
  } catch (const YAML::Exception&) {
    return {};
  }
}

TruthComparison compare_with_truth(const CampaignResults& r) {
  TruthComparison c;
  if (!r.campaign.has_truth) return c;
  YAML::Node root;
  try {
    root = YAML::LoadFile(r.campaign.truth_file.string());
  } catch (const YAML::Exception& e) {
    c.warnings.push_back(std::string("truth.yaml: not valid YAML (") + e.what() + ")");
    return c;
  }
  c.present = true;
  const YAML::Node tests = root["tests"];
  if (!tests || !tests.IsMap()) return c;
  for (const auto& kv : tests) {
    const auto key = kv.first.as<std::string>();
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
