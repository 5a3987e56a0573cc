// Fields the simulation and lobes specs share (docs/format/simulation.md, docs/format/lobes.md):
// a modal set {m_kg, c_kg_s, k_N_m} and a per-tooth coefficient list. Problems are recorded in
// the YamlReader with their key path; nothing is thrown.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "analysis/common/modal_parameters.h"
#include "app/core/yaml_reader.h"

namespace chatterlab::app {

// {m_kg, c_kg_s, k_N_m} at `path`: m > 0, c >= 0, k > 0, finite.
ModalParameters read_modal_parameters(const YAML::Node& n, YamlReader& r, const std::string& path);

// coefficients.<key>: a number (every tooth) or a list of one value per tooth (`teeth` of them
// when teeth > 0; at most max_teeth values), each finite and >= 0.
std::vector<double> read_per_tooth(const YAML::Node& map, const std::string& key, int teeth,
                                   long max_teeth, YamlReader& r);

}  // namespace chatterlab::app
