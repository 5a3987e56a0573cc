#include "app/kinds/tap/tap_step.h"

#include <array>

#include "analysis/frf/frf.h"
#include "analysis/frf/hits.h"
#include "analysis/frf/modal_fit.h"
#include "app/core/signals.h"

namespace chatterlab::app {
frf::ResponseKind response_kind_of(const std::string& s) {
  if (s == "velocity") return frf::ResponseKind::kVelocity;
  if (s == "displacement") return frf::ResponseKind::kDisplacement;
  return frf::ResponseKind::kAcceleration;
}

TapOutcome run_tap_test(const TestSpec& t, const TapStepOptions& options) {
  TapOutcome out;
  const TapSpec& tap = t.kind_spec<TapSpec>();
  const std::string label = (t.id.empty() ? "" : t.id + "/") + t.data.relative_file;
  const SignalTable table = SignalTable::open(t.data, label);
  const Eigen::VectorXd force = table.channel("force", t.channel("force"));
  const Eigen::VectorXd response = table.channel("response", t.channel("response"));

  frf::HitSet hits;
  if (tap.hits_auto) {
    hits = frf::detect_hits(force, response, t.sample_rate_hz, options.hits);
  } else {
    std::vector<std::array<double, 2>> windows;
    for (const auto& [a, b] : tap.hit_windows_s) windows.push_back({a, b});
    hits = frf::hits_from_windows(force, response, t.sample_rate_hz, windows, options.hits);
  }
  for (const auto& h : hits.hits) {
    out.hits.push_back({h.time_s, h.peak_force_n, h.accepted, h.rejection});
  }
  // hits.summary.warnings only restate the rejections, which out.hits carries.
  if (!hits.summary.ok()) {
    out.summary.fail(label + ": " + hits.summary.message);
    return out;
  }

  const frf::Frf f =
      frf::compute_frf(force, response, hits, response_kind_of(tap.response), options.frf);
  out.warnings.insert(out.warnings.end(), f.summary.warnings.begin(), f.summary.warnings.end());
  if (!f.summary.ok()) {
    out.summary.fail(label + ": " + f.summary.message);
    return out;
  }
  out.hits_used = f.hits_used;
  out.f_hz = f.f_hz;
  out.h1 = f.h1;
  out.h2 = f.h2;
  out.coherence = f.coherence;
  out.df_hz = f.df_hz;
  if (f.exp_window_tau_s > 0) out.exp_window_tau_s = f.exp_window_tau_s;
  out.summary.succeed();

  frf::ModalFitOptions fo = options.fit;
  if (tap.band_hz) fo.band_hz = std::array<double, 2>{tap.band_hz->first, tap.band_hz->second};
  if (tap.modes > 0) fo.n_modes = tap.modes;
  const frf::ModalFit fit = frf::fit_modes(f, fo);
  out.warnings.insert(out.warnings.end(), fit.summary.warnings.begin(), fit.summary.warnings.end());
  out.fit_message = fit.summary.message;
  if (fit.summary.ok()) {
    out.fit_ok = true;
    out.modes = fit.modes;
    out.quality = fit.quality;
    out.fit_nrmse_pct = fit.fit_nrmse_pct;
    out.fitted = fit.fitted;
    out.band_lo_hz = fit.band_lo_hz;
    out.band_hi_hz = fit.band_hi_hz;
  }
  return out;
}

}  // namespace chatterlab::app
