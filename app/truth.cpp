#include "app/truth.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <iterator>
#include <map>

namespace chatterlab::app {
namespace {

constexpr double kRadToDeg = 57.29577951308232;

void add(TruthComparison& c, const std::string& q, const std::string& src, double truth,
         double est) {
  if (!std::isfinite(truth) || !std::isfinite(est)) return;
  TruthRow row{q, src, truth, est, truth != 0 ? 100.0 * (est - truth) / std::abs(truth) : 0.0};
  c.rows.push_back(row);
}

double get(const YAML::Node& n, const char* key) {
  try {
    return n[key] ? n[key].as<double>() : std::nan("");
  } catch (const YAML::Exception&) {
    return std::nan("");
  }
}

// theta_dyn is defined modulo pi: compare on the nearest representative.
double wrap_to_pi_of(double est_deg, double truth_deg) {
  return est_deg + 180.0 * std::round((truth_deg - est_deg) / 180.0);
}

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
    for (const char* k : {"m_kg", "c_kg_s", "k_N_m"}) v[k] = get(m, k);
  }
  if (const YAML::Node c = root["coefficients"]) {
    for (int p = 1; p <= teeth; ++p) {
      const int q = (p - 1 + shift) % teeth + 1;
      v["Kt" + std::to_string(p) + "_N_m2"] = get(c, ("Kt" + std::to_string(q) + "_N_m2").c_str());
      v["Kr" + std::to_string(p) + "_N_m2"] = get(c, ("Kr" + std::to_string(q) + "_N_m2").c_str());
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

std::map<std::string, double> identified_values(const CutEstimation& e) {
  std::map<std::string, double> v;
  for (const auto& [k, value] : keyed_values(e.modal, e.coefficients)) v[k] = value;
  for (const auto& [k, value] : scale_free_values(e)) v[k] = value;
  return v;
}

// The truth's offset of test `id`, NaN when truth.yaml has none.
double truth_offset(const YAML::Node& root, const std::string& id) {
  const YAML::Node tests = root["tests"];
  if (!tests || !tests.IsMap() || !tests[id]) return std::nan("");
  return get(tests[id], "offset_angle_deg");
}

YAML::Node load_truth(const CampaignSpec& c) {
  if (!c.has_truth) return {};
  try {
    return YAML::LoadFile(c.truth_file.string());
  } catch (const YAML::Exception&) {
    return {};
  }
}

}  // namespace

std::map<std::string, ReferenceValue> reference_values(const CampaignResults& r,
                                                       const TestOutcome& t) {
  std::map<std::string, ReferenceValue> out;
  if (!t.cut || !t.cut->estimation.summary.ok) return out;
  const CutEstimation& e = t.cut->estimation;
  for (const auto& [k, v] : identified_values(e)) out[k] = {v, "identified"};
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
    const YAML::Node v = kv.second;
    // Tap test: modes matched to the fitted mode nearest in frequency.
    for (const auto& t : r.tests) {
      if (t.spec->id != key || !t.tap || !t.tap->fit_ok || !v["modes"]) continue;
      int i = 0;
      for (const auto& m : v["modes"]) {
        ++i;
        const double fn = get(m, "fn_hz");
        const frf::Mode* best = nullptr;
        for (const auto& fm : t.tap->modes) {
          if (!best || std::abs(fm.fn_hz - fn) < std::abs(best->fn_hz - fn)) best = &fm;
        }
        if (!best || std::abs(best->fn_hz - fn) > 0.1 * fn) continue;  // mode not found
        const std::string p = "mode" + std::to_string(i) + ".";
        add(c, p + "fn_hz", key, fn, best->fn_hz);
        add(c, p + "zeta", key, get(m, "zeta"), best->zeta);
        add(c, p + "m_kg", key, get(m, "m_kg"), best->m_kg);
        add(c, p + "c_kg_s", key, get(m, "c_kg_s"), best->c_kg_s);
        add(c, p + "k_N_m", key, get(m, "k_N_m"), best->k_N_m);
      }
    }
    // Cut test: the offset angles, on the representative nearest the truth modulo the tooth
    // pitch (the hammer/dyno model's alike teeth cannot tell the pitches apart; the identified
    // one can, but only up to the tooth labels, which the coefficients follow), and the
    // identified values relabelled to the truth's teeth.
    for (const auto& t : r.tests) {
      if (t.spec->id != key || !t.cut || !t.cut->offset_status.ok) continue;
      const double truth_deg = get(v, "offset_angle_deg");
      const int teeth = r.campaign.tool ? r.campaign.tool->teeth : 1;
      const double period = 360.0 / teeth;
      const auto nearest = [&](double est) {
        return est + period * std::round((truth_deg - est) / period);
      };
      add(c, "offset_hammer_dyno_deg", key, truth_deg,
          nearest(t.cut->offset.search.offset_angle_deg));
      const CutEstimation& e = t.cut->estimation;
      if (!e.summary.ok) continue;
      const double est = e.offset.search.offset_angle_deg;
      add(c, "offset_angle_deg", key, truth_deg, nearest(est));
      const int shift = tooth_shift(est, truth_deg, teeth);
      const auto truth_in_cut = truth_values(root, teeth, shift);
      for (const auto& [k, value] : identified_values(e)) {
        const auto it = truth_in_cut.find(k);
        if (it != truth_in_cut.end()) add(c, "identified." + k, key, it->second, value);
      }
    }
    // Dyno group ("dyno/" prefix of its tests).
    if (r.dyno_group && r.dyno_group->summary.ok && !r.dyno_group->test_ids.empty() &&
        r.dyno_group->test_ids.front().rfind(key, 0) == 0) {
      const auto& k = r.dyno_group->fit.coefficients;
      add(c, "Ktc_N_m2", key, get(v, "Ktc_N_m2"), k.Ktc_N_per_m2);
      add(c, "Kte_N_m", key, get(v, "Kte_N_m"), k.Kte_N_per_m);
      add(c, "Krc_N_m2", key, get(v, "Krc_N_m2"), k.Krc_N_per_m2);
      add(c, "Kre_N_m", key, get(v, "Kre_N_m"), k.Kre_N_per_m);
      const double th = get(v, "theta_dyn_deg");
      for (const auto& t : r.tests) {
        if (t.dyno && t.spec->id.rfind(key, 0) == 0 && std::isfinite(th)) {
          add(c, "theta_dyn_deg", t.spec->id, th,
              wrap_to_pi_of(t.dyno->result.theta_dyn_rad * kRadToDeg, th));
        }
      }
    }
  }
  return c;
}

}  // namespace chatterlab::app
