// `chatterlab lobes <spec.yaml> --out <dir>`: stability lobes of one tool, modal set, coefficient
// set and cut (EXPERIMENT_FORMAT.md "Stability lobe specs") by semi-discretization and the
// zero-order approximation, with a figure, a short HTML report, a PDF and results.json.
#pragma once

#include <filesystem>
#include <ostream>

#include "analysis/lobes/lobes.h"
#include "app/lobes/lobes_spec.h"

namespace chatterlab::app {

struct LobesRunOptions {
  bool pdf = true;
  bool report = true;  // false: results.json only
  int jobs = 0;        // threads over the speeds; 0: one per hardware thread
  // Where the spec's warnings (misspelt keys) are said; nullptr: on `log`.
  std::ostream* warnings = nullptr;
};

// The semi-discretization options of a spec: its steps_per_tooth, else the automatic rule.
lobes::SemiDiscretizationOptions semi_discretization_options(const lobes::LobesInput& in,
                                                             int steps_per_tooth, int threads);

// Returns the exit code: 0 when everything was written, 1 when the PDF failed. A spec error
// throws InputError before anything is written.
int run_lobes(const std::filesystem::path& spec_file, const std::filesystem::path& out,
              const LobesRunOptions& options, std::ostream& log);

}  // namespace chatterlab::app
