// Options of the estimation part of a cut test (app/cut_estimation.h), read from campaign.yaml
// `estimation:` (docs/formats.md).
#pragma once

#include "analysis/estimate/estimation_window.h"
#include "analysis/estimate/identification.h"
#include "analysis/estimate/repeatability.h"

namespace chatterlab::app {

// campaign.yaml `estimation:` (docs/formats.md). Defaults: 000 secs 6.1-6.2 where it gives a
// value, docs/identification.md otherwise. The window rule's options (window_s,
// settle_revolutions) and the identification sequence's (max_passes, offset_tolerance_deg,
// parameter_tolerance, modal, coeff) are the analysis options themselves.
struct EstimationOptions : estimate::EstimationWindowOptions, estimate::IdentificationOptions {
  double resample_step_s = 5e-7;          // 000 sec. 6.1, s, > 0
  estimate::RepeatabilityOptions repeat;  // runs (10), spread (0.5), seed
};

}  // namespace chatterlab::app
