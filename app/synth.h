// `chatterlab synth <spec.yaml> --out <campaign>`: writes a synthetic campaign in the format
// of EXPERIMENT_FORMAT.md from given true values, with noise, offsets and several hits, and
// a truth.yaml with the values used. The spec format is documented in docs/synth.md.
#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace chatterlab::app {

struct SynthSummary {
  int tests_written = 0;
  std::string campaign_name;
};

// truth.yaml while the parts of a campaign are written: top-level values (`modal`,
// `coefficients`) and one entry per test under `tests:`, each in the order added.
struct SynthTruth {
  YAML::Node top = YAML::Node(YAML::NodeType::Map);
  YAML::Node tests = YAML::Node(YAML::NodeType::Map);
};

// Numbers in synth's YAML files: 10 significant digits (printf %.10g).
constexpr int kSynthDigits = 10;
std::string synth_number(double v);
// A flow mapping {key: number, ...} in the given order, numbers as synth_number.
YAML::Node synth_numbers(const std::vector<std::pair<std::string, double>>& values);
// A YAML emitter set up for synth's files (numbers as synth_number).
void configure_synth_emitter(YAML::Emitter& e);
// Writes the emitter's document and a final newline to `path`, creating its folder.
// @throws InputError naming the path when it cannot be written
void write_synth_yaml(const std::filesystem::path& path, const YAML::Emitter& e);

// Throws InputError naming the spec file and key for a bad spec.
SynthSummary synthesize_campaign(const std::filesystem::path& spec_yaml,
                                 const std::filesystem::path& out_dir);

}  // namespace chatterlab::app
