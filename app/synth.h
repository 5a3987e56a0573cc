// `chatterlab synth <spec.yaml> --out <campaign>`: writes a synthetic campaign in the format
// of EXPERIMENT_FORMAT.md from given true values, with noise, offsets and several hits, and
// a truth.yaml with the values used. The spec format is documented in docs/synth.md.
#pragma once

#include <filesystem>
#include <string>

namespace chatterlab::app {

struct SynthSummary {
  int tests_written = 0;
  std::string campaign_name;
};

// Throws InputError naming the spec file and key for a bad spec.
SynthSummary synthesize_campaign(const std::filesystem::path& spec_yaml,
                                 const std::filesystem::path& out_dir);

}  // namespace chatterlab::app
