#include "app/truth.h"

#include <yaml-cpp/yaml.h>

#include <cmath>

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

}  // namespace

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
    // Cut test: the offset angle, on the representative nearest the truth (modulo 360, or
    // modulo the tooth pitch when the model's alike teeth cannot tell the half turns apart).
    for (const auto& t : r.tests) {
      if (t.spec->id != key || !t.cut || !t.cut->offset_status.ok) continue;
      const double truth_deg = get(v, "offset_angle_deg");
      const int teeth = r.campaign.tool ? r.campaign.tool->teeth : 1;
      const double period = t.cut->offset.search.ambiguous ? 360.0 / teeth : 360.0;
      const double est = t.cut->offset.search.offset_angle_deg;
      add(c, "offset_angle_deg", key, truth_deg,
          est + period * std::round((truth_deg - est) / period));
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
