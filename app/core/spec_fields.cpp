#include "app/core/spec_fields.h"

#include <algorithm>
#include <cmath>

namespace chatterlab::app {

ModalParameters read_modal_parameters(const YAML::Node& n, YamlReader& r, const std::string& path) {
  r.check_keys(n, {"m_kg", "c_kg_s", "k_N_m"}, path);
  ModalParameters m;
  m.m_kg = r.required_double(n, "m_kg", path);
  m.c_kg_s = r.required_double(n, "c_kg_s", path);
  m.k_N_m = r.required_double(n, "k_N_m", path);
  if (!(m.m_kg > 0)) r.error(path + ".m_kg", "must be > 0");
  if (!(m.c_kg_s >= 0)) r.error(path + ".c_kg_s", "must be >= 0");
  if (!(m.k_N_m > 0)) r.error(path + ".k_N_m", "must be > 0");
  return m;
}

std::vector<double> read_per_tooth(const YAML::Node& map, const std::string& key, int teeth,
                                   long max_teeth, YamlReader& r) {
  const std::string path = "coefficients." + key;
  const YAML::Node n = map[key];
  std::vector<double> v;
  if (!n) {
    r.error(path, "is missing");
    return v;
  }
  try {
    if (n.IsScalar()) {
      v.assign(static_cast<std::size_t>(std::max(teeth, 1)), n.as<double>());
      if (!std::isfinite(v.front()))
        r.error(path, "must be a finite number, got '" + n.Scalar() + "'");
    } else if (n.IsSequence()) {
      if (n.size() > static_cast<std::size_t>(max_teeth)) {
        r.error(path, "has " + std::to_string(n.size()) + " values: at most " +
                          std::to_string(max_teeth) + " (one per tooth)");
        return {};
      }
      for (const auto& e : n) {
        v.push_back(e.as<double>());
        if (!std::isfinite(v.back())) r.error(path, "values must be finite numbers");
      }
      if (teeth > 0 && static_cast<int>(v.size()) != teeth) {
        r.error(path, "has " + std::to_string(v.size()) +
                          " values: give one number or one per tooth (" + std::to_string(teeth) +
                          ")");
      }
    } else {
      r.error(path, "must be a number or a list of numbers, one per tooth");
    }
  } catch (const YAML::Exception&) {
    r.error(path, "must be a number or a list of numbers, one per tooth");
  }
  for (double x : v) {
    if (!(x >= 0)) r.error(path, "values must be >= 0");
  }
  return v;
}

}  // namespace chatterlab::app
