// A cut test against truth.yaml: the offset angles and the identified values, relabelled to
// the truth's teeth (docs/identification.md, "Tooth labels"), and the reference values of the
// percent-error figures.
#include <cmath>
#include <iterator>

#include "app/kinds/cut/cut_kind.h"
#include "app/report/truth.h"

namespace chatterlab::app {
namespace {

// Tooth shift s of an identified offset against the truth's: the offset differs by s whole
// pitches (mod n), so identified tooth p is the truth's tooth p + s.
int tooth_shift(double est_deg, double truth_deg, int teeth) {
  const double pitch = 360.0 / teeth;
  const long s = std::lround((est_deg - truth_deg) / pitch);
  return static_cast<int>(((s % teeth) + teeth) % teeth);
}

// truth.yaml's in-cut values keyed as results.json, tooth numbers shifted by `shift`.
std::map<std::string, double> truth_values(const YAML::Node& root, int teeth, int shift) {
  std::map<std::string, double> v;
  if (const YAML::Node m = root["modal"]) {
    for (const char* k : {"m_kg", "c_kg_s", "k_N_m"}) v[k] = truth_number(m, k);
  }
  if (const YAML::Node c = root["coefficients"]) {
    for (int p = 1; p <= teeth; ++p) {
      const int q = (p - 1 + shift) % teeth + 1;
      v["Kt" + std::to_string(p) + "_N_m2"] =
          truth_number(c, ("Kt" + std::to_string(q) + "_N_m2").c_str());
      v["Kr" + std::to_string(p) + "_N_m2"] =
          truth_number(c, ("Kr" + std::to_string(q) + "_N_m2").c_str());
    }
  }
  // The scale-free combinations (cut_estimation.h scale_free_values).
  if (v.count("m_kg") && v.count("k_N_m")) {
    const double m = v["m_kg"], k = v["k_N_m"];
    v["fn_hz"] = std::sqrt(k / m) / (2 * M_PI);
    if (v.count("c_kg_s")) v["zeta"] = v["c_kg_s"] / (2 * std::sqrt(k * m));
    for (int p = 1; p <= teeth; ++p) {
      for (const char* c : {"Kt", "Kr"}) {
        const std::string key = c + std::to_string(p) + "_N_m2";
        if (v.count(key)) v[c + std::to_string(p) + "_over_k_per_m"] = v[key] / k;
      }
    }
  }
  for (auto it = v.begin(); it != v.end();)
    it = std::isfinite(it->second) ? std::next(it) : v.erase(it);
  return v;
}

// The truth's offset of test `id`, NaN when truth.yaml has none.
double truth_offset(const YAML::Node& root, const std::string& id) {
  const YAML::Node tests = root["tests"];
  if (!tests || !tests.IsMap() || !tests[id]) return std::nan("");
  return truth_number(tests[id], "offset_angle_deg");
}

}  // namespace

std::map<std::string, ReferenceValue> reference_values(const CampaignResults& r,
                                                       const TestOutcome& t) {
  std::map<std::string, ReferenceValue> out;
  const CutOutcome* c = t.status.ok() ? t.result_as<CutOutcome>() : nullptr;
  if (!c || !c->estimation.summary.ok()) return out;
  const CutEstimation& e = c->estimation;
  for (const auto& [k, v] : sequence_values(e)) out[k] = {v, "identified"};
  const YAML::Node root = load_truth(r.campaign);
  const double off = root ? truth_offset(root, t.spec->id) : std::nan("");
  if (root && std::isfinite(off)) {
    const int teeth = static_cast<int>(e.coefficients.size());
    const int shift = tooth_shift(e.offset.search.offset_angle_deg, off, teeth);
    for (const auto& [k, v] : truth_values(root, teeth, shift)) out[k] = {v, "truth.yaml"};
  }
  for (const auto& [k, v] : t.spec->reference) out[k] = {v, "test.yaml reference"};
  return out;
}

void CutKind::compare_truth(const TruthInput& in, const TestOutcome& t, TruthComparison& c) const {
  const CutOutcome& cut = t.result_of<CutOutcome>();
  if (!cut.offset_status.ok()) return;
  const YAML::Node& root = *in.root;
  const YAML::Node& v = *in.entry;
  const std::string& key = t.spec->id;
  const CampaignResults& r = *in.results;
  // Cut test: the offset angles, on the representative nearest the truth modulo the tooth
  // pitch (the hammer/dyno model's alike teeth cannot tell the pitches apart; the identified
  // one can, but only up to the tooth labels, which the coefficients follow), and the
  // identified values relabelled to the truth's teeth.
  const double truth_deg = truth_number(v, "offset_angle_deg");
  const int teeth = r.campaign.tool ? r.campaign.tool->teeth : 1;
  const double period = 360.0 / teeth;
  const auto nearest = [&](double est) {
    return est + period * std::round((truth_deg - est) / period);
  };
  add_truth_row(c, "offset_hammer_dyno_deg", key, truth_deg,
                nearest(cut.offset.search.offset_angle_deg));
  const CutEstimation& e = cut.estimation;
  if (!e.summary.ok()) return;
  const double est = e.offset.search.offset_angle_deg;
  add_truth_row(c, "offset_angle_deg", key, truth_deg, nearest(est));
  const int shift = tooth_shift(est, truth_deg, teeth);
  const auto truth_in_cut = truth_values(root, teeth, shift);
  for (const auto& [k, value] : sequence_values(e)) {
    const auto it = truth_in_cut.find(k);
    if (it != truth_in_cut.end()) add_truth_row(c, "identified." + k, key, it->second, value);
  }
  // The joint estimate beside the sequence, on its own offset's tooth labels.
  if (!e.joint.summary.ok()) return;
  const double joint_deg = e.joint.offset_deg.value;
  add_truth_row(c, "joint.offset_deg", key, truth_deg, nearest(joint_deg));
  const auto truth_joint = truth_values(root, teeth, tooth_shift(joint_deg, truth_deg, teeth));
  for (const auto& [k, iv] : keyed_intervals(e.joint)) {
    const auto it = truth_joint.find(k);
    if (it != truth_joint.end()) add_truth_row(c, "joint." + k, key, it->second, iv->value);
  }
}

}  // namespace chatterlab::app
