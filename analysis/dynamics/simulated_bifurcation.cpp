#include "analysis/dynamics/simulated_bifurcation.h"

#include <cmath>

namespace chatterlab {
namespace dynamics {

Eigen::Index completed_revolutions(const milling::OncePerRevolution& s) {
  Eigen::Index n = 0;
  while (n < s.x_m.size() && n < s.y_m.size() && std::isfinite(s.x_m[n]) &&
         std::isfinite(s.y_m[n])) {
    ++n;
  }
  return n;
}

SimulatedRunBifurcation simulated_run_bifurcation(const milling::SimulationResult& sim,
                                                  BifurcationOptions options) {
  SimulatedRunBifurcation out;
  out.completed_revolutions = completed_revolutions(sim.samples);
  out.diverged = !sim.summary.ok();
  options.ends_unbounded = out.diverged;
  const Eigen::Index done = out.completed_revolutions;
  if (done > options.window_revolutions) {
    out.result =
        detect_bifurcation(sim.samples.depth_m.head(done), sim.samples.x_m.head(done), options);
  }
  return out;
}

}  // namespace dynamics
}  // namespace chatterlab
