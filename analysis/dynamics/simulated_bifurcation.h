// Bifurcation detection on a simulated run (000 sec. 5.2, fig. 5.1; bifurcation.h): the
// detector over the once-per-revolution samples of the revolutions the simulator completed.
// A run that diverged (the deflection left the physical range, simulation.h) leaves NaN samples
// after its failure; the finite revolutions before it grow without bound, so the detector takes
// the run's end as chatter (BifurcationOptions::ends_unbounded, set here from the simulation's
// summary). `chatterlab simulate` and the cut tests' simulation with identified values
// (000 table 5.1) both use this.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "analysis/dynamics/bifurcation.h"
#include "analysis/milling/simulation.h"

namespace chatterlab {
namespace dynamics {

// Leading once-per-revolution samples with finite x_n and y_n: the revolutions a run completed.
Eigen::Index completed_revolutions(const milling::OncePerRevolution& samples);

struct SimulatedRunBifurcation {
  Eigen::Index completed_revolutions = 0;  // completed_revolutions(sim.samples)
  bool diverged = false;                   // !sim.summary.ok()
  // Unset when completed_revolutions <= options.window_revolutions: too few revolutions for
  // the detector's window. Otherwise the detector's result (its summary may still fail).
  std::optional<BifurcationResult> result;
};

// @param options  the detector's options (measurement_noise_m as the caller knows it);
//                 ends_unbounded is replaced by !sim.summary.ok()
// @throws InputError as detect_bifurcation for invalid options
SimulatedRunBifurcation simulated_run_bifurcation(const milling::SimulationResult& sim,
                                                  BifurcationOptions options = {});

}  // namespace dynamics
}  // namespace chatterlab
