// `chatterlab synth <spec.yaml> --out <campaign>`: writes a synthetic campaign in the campaign
// format (docs/format/campaign.md) from given true values, with noise, offsets and several hits,
// and a truth.yaml with the values used. The spec format is docs/format/synth-spec.md.
//
// The spec's top level (format, name, description, seed, tool, workpiece, machine) is read here
// and becomes campaign.yaml; every other top-level section belongs to the test kind that names
// it (TestKind::synth_section(): `tap`, `dyno`, `cut`), which parses it and writes its tests.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "app/core/yaml_reader.h"

namespace chatterlab::app {

struct SynthSummary {
  int tests_written = 0;
  std::string campaign_name;
  // Keys of the spec nobody reads (a misspelt key gets a suggestion), naming the file and key.
  std::vector<std::string> warnings;
};

// truth.yaml while the parts of a campaign are written: campaign-wide values (`modal`,
// `coefficients`) and one entry per test or group under `tests:`, each in the order added. A
// kind that sets a campaign-wide value another kind set before replaces it in place (the cut
// tests' modal parameters, the values their identification targets, replace the first x mode
// of the tap tests).
struct SynthTruth {
  YAML::Node top = YAML::Node(YAML::NodeType::Map);
  YAML::Node tests = YAML::Node(YAML::NodeType::Map);
};

// campaign.yaml's `tool` as the spec gives it.
struct SynthTool {
  int teeth = 0;
  double radius_mm = 0.0;  // as written (campaign.yaml repeats it)
  double radius_m() const { return radius_mm * 1e-3; }
  std::optional<double> helix_deg;
};

// What a kind's synth writer reads beside its own section, and where it writes.
struct SynthContext {
  std::string spec_label;         // the spec file's name, for messages
  std::uint64_t seed = 1;         // the spec's `seed`
  bool tool_given = false;        // the spec has a `tool` key (valid or not)
  std::optional<SynthTool> tool;  // the tool, when given and valid
  std::filesystem::path out;      // the campaign folder
  SynthTruth truth;

  // The seed of random stream `index` of kind `tag` (derive_seed(seed, tag, index),
  // analysis/common/seed.h): every stream of a campaign independent of the others.
  std::uint64_t stream_seed(std::string_view tag, std::uint64_t index) const;
};

// Numbers in synth's YAML files: 10 significant digits (printf %.10g).
constexpr int kSynthDigits = 10;
std::string synth_number(double v);
// A flow mapping {key: number, ...} in the given order, numbers as synth_number.
YAML::Node synth_numbers(const std::vector<std::pair<std::string, double>>& values);
// The optional key `folder` of a synth section (the parent folder of its tests): a relative
// path without `..` or a backslash, not ending in '/'; `fallback` when absent. Errors through r,
// keyed `<section>.folder`.
std::string read_synth_folder(const YAML::Node& section, const std::string& name,
                              const std::string& fallback, YamlReader& r);
// A flow sequence [number, ...], numbers as synth_number.
YAML::Node synth_number_list(const std::vector<double>& values);
// A YAML emitter set up for synth's files (numbers as synth_number).
void configure_synth_emitter(YAML::Emitter& e);
// Writes the emitter's document and a final newline to `path`, creating its folder.
// @throws InputError naming the path when it cannot be written
void write_synth_yaml(const std::filesystem::path& path, const YAML::Emitter& e);

// Throws InputError naming the spec file and key for a bad spec, before anything is written.
// `before_writing`, when set, runs once the spec has been read and before the first file is
// written (the command line writes into a new temporary folder beside --out and swaps it into
// place afterwards: app/cli/output_folder.h).
SynthSummary synthesize_campaign(const std::filesystem::path& spec_yaml,
                                 const std::filesystem::path& out_dir,
                                 const std::function<void()>& before_writing = {});

}  // namespace chatterlab::app
