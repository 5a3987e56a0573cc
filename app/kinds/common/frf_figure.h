// The figure of a measured FRF against a fitted model: magnitude (log) with an optional band
// around the measurement, phase, coherence (sifs-tap, dyno-frf).
#pragma once

#include <string>
#include <vector>

#include "render/figure.h"

namespace chatterlab::app {

struct FrfFigureData {
  std::vector<double> f_hz;
  std::vector<double> measured_mag, model_mag;
  std::vector<double> measured_phase_deg, model_phase_deg;
  std::vector<double> coherence;
  std::vector<double> band_lo, band_hi;  // empty: no band drawn
};

struct FrfFigureLabels {
  std::string magnitude_axis;  // "|G| [N/N]"
  std::string measured;        // "H1 (taps)"
  std::string model;           // "fit, eq. 4-27"
  std::string band;            // "H1 +- 2 sigma (eq. 6-3)"; unused without a band
};

render::Figure frf_model_figure(const FrfFigureData& d, const FrfFigureLabels& labels);

}  // namespace chatterlab::app
