// The stability lobe spec of EXPERIMENT_FORMAT.md "Stability lobe specs" (`chatterlab lobes`),
// read into the analysis core's input (analysis/lobes/lobes.h). docs/format/lobes.md.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "analysis/lobes/lobes.h"

namespace chatterlab::app {

// Bounds of the spec (docs/format/lobes.md): every count read is bounded.
constexpr long kMaxLobeSpeeds = 20000;
constexpr long kMaxModesPerAxis = 8;
constexpr long kMaxLobeStepsPerTooth = 2000;
constexpr long kMaxLobeDepthMm = 1000;

struct LobesSpec {
  lobes::LobesInput input;  // speeds filled from spindle_rpm and speeds
  bool semi_discretization = true;
  bool zoa = true;
  // Semi-discretization intervals per tooth period; 0: the automatic rule of docs/lobes.md
  // (lobes_steps_per_tooth).
  int steps_per_tooth = 0;
  std::vector<std::string> warnings;  // unknown keys, naming the file and key
};

// Reads and validates a spec; throws InputError listing every problem with file and key.
LobesSpec load_lobes_spec(const std::filesystem::path& file);

}  // namespace chatterlab::app
