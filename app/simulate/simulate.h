// `chatterlab simulate <spec.yaml> --out <dir>`: one time-domain milling simulation
// (EXPERIMENT_FORMAT.md section 3) with its bifurcation depth, Poincare maps, figures, a short
// HTML report, a PDF and results.json.
#pragma once

#include <filesystem>
#include <ostream>

#include "analysis/milling/simulation_options.h"
#include "app/simulate/simulation_spec.h"

namespace chatterlab::app {

struct SimulateOptions {
  bool pdf = true;
  bool report = true;  // false: results.json only (no figures, HTML or PDF), for sweeps
  int jobs = 0;        // figure threads; 0: one per hardware thread
  // Where the spec's warnings (misspelt keys) are said before the run; nullptr: on `log`. The
  // command line passes stderr, so that --quiet keeps them (they are also in results.json).
  std::ostream* warnings = nullptr;
};

// The simulator's options for a spec (traditional model: contact switching, velocity-first
// symplectic Euler, docs/simulator.md).
milling::SimulationOptions simulation_options(const SimulationSpec& spec);

// Returns the exit code: 0 when the report was written and the run completed, 1 otherwise
// (a spec error, or a run that diverged: the report then says where).
int run_simulate(const std::filesystem::path& spec_file, const std::filesystem::path& out,
                 const SimulateOptions& options, std::ostream& log);

}  // namespace chatterlab::app
