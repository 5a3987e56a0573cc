// H1/H2 FRF estimates and coherence from the accepted hits of a tap test.
#pragma once

#include <Eigen/Core>

#include "analysis/common/summary.h"
#include "analysis/frf/hits.h"
#include "analysis/frf/response_kind.h"

namespace chatterlab {
namespace frf {

struct FrfOptions {
  // Force window margin, in units of the pulse's duration above the threshold (see
  // force_window): 1 keeps the pulse's foot and tapers well before the noise dominates.
  double force_window_margin = 1.0;
  // Exponential window: automatic (auto_exponential_tau_s), or exp_window_tau_s as given
  // (0 = none) when exp_window_auto is false.
  bool exp_window_auto = true;
  double exp_window_tau_s = 0.0;
  // Automatic rule: residual response amplitude at the record end, as a fraction of the
  // early amplitude. 1 % (-40 dB) keeps truncation leakage below typical 1 % noise.
  double exp_window_end_fraction = 0.01;
  // Length of the early and late segments the automatic rule compares, fraction of L.
  double decay_segment_fraction = 0.05;
};

// Receptance FRF (m/N) on bins k = 1 .. L/2 (DC excluded), f = k fs / L:
//   S_ff = sum |F|^2, S_xx = sum |X|^2, S_fx = sum conj(F) X, S_xf = conj(S_fx) over hits,
//   H1 = S_fx / S_ff, H2 = S_xx / S_xf, coherence = |S_fx|^2 / (S_ff S_xx),
// with F, X the DFTs of the windowed, baseline-free force and response of each record.
// Response -> receptance: acceleration / (-w^2), velocity / (j w), displacement as is;
// with an exponential window, at s = 1/tau + j w instead of j w (acceleration / s^2,
// velocity / s), so that H is exactly the receptance with every pole moved by -1/tau.
struct Frf {
  StepSummary summary;
  Eigen::VectorXd f_hz;
  Eigen::VectorXcd h1;
  Eigen::VectorXcd h2;
  Eigen::VectorXd coherence;  // 1 by construction with a single hit
  int hits_used = 0;
  double df_hz = 0.0;
  double exp_window_tau_s = 0.0;  // exponential window applied to both channels; 0 = none
};

// @param force_n, response  the channels detect_hits saw
// @param hits               its result; only accepted hits are used
// @return Frf whose summary fails when hits has no accepted hit
// @throws InputError on lengths that do not match hits, or invalid options
Frf compute_frf(const Eigen::Ref<const Eigen::VectorXd>& force_n,
                const Eigen::Ref<const Eigen::VectorXd>& response, const HitSet& hits,
                ResponseKind kind, const FrfOptions& options = {});

}  // namespace frf
}  // namespace chatterlab
