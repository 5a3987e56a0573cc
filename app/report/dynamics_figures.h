// Figures of nonlinear dynamics shared by `simulate` and the cut tests of a campaign report:
// bifurcation diagrams (000 fig. 5.1) and Poincare maps (000 figs 5.1, 5.5-5.8).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/dynamics/poincare.h"
#include "render/figure.h"

namespace chatterlab::app {

// Once-per-revolution samples (one panel per named signal, in m) against depth (m), or
// against the revolution number when the depth is constant; a dashed line at the bifurcation
// depth when given.
render::Figure bifurcation_figure(
    const Eigen::Ref<const Eigen::VectorXd>& depth_m,
    const std::vector<std::pair<std::string, Eigen::VectorXd>>& samples_m,
    const std::optional<double>& bifurcation_depth_m, bool constant_depth);

// One panel per map: x_n against x_(n-1) (um).
render::Figure poincare_figure(const std::vector<dynamics::PoincareMap>& maps);

}  // namespace chatterlab::app
