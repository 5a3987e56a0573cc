#include "app/kinds/common/frf_figure.h"

namespace chatterlab::app {

render::Figure frf_model_figure(const FrfFigureData& d, const FrfFigureLabels& labels) {
  render::Figure fig;
  fig.height_in = 5.0;
  fig.share_x = true;
  render::Axes& m = fig.panels.emplace_back();
  m.y_label = labels.magnitude_axis;
  m.log_y = true;
  m.relative_height = 2;
  m.series = {{d.f_hz, d.measured_mag, labels.measured, render::SeriesStyle::kLine, "#0072B2"},
              {d.f_hz, d.model_mag, labels.model, render::SeriesStyle::kDashedLine, "#D55E00"}};
  if (!d.band_lo.empty()) {
    m.series.push_back(
        {d.f_hz, d.band_lo, labels.band, render::SeriesStyle::kDashedLine, "#56B4E9"});
    m.series.push_back({d.f_hz, d.band_hi, "", render::SeriesStyle::kDashedLine, "#56B4E9"});
  }
  render::Axes& p = fig.panels.emplace_back();
  p.y_label = "phase [deg]";
  p.series = {{d.f_hz, d.measured_phase_deg, "", render::SeriesStyle::kLine, "#0072B2"},
              {d.f_hz, d.model_phase_deg, "", render::SeriesStyle::kDashedLine, "#D55E00"}};
  render::Axes& c = fig.panels.emplace_back();
  c.x_label = "frequency [Hz]";
  c.y_label = "coherence";
  c.y_range = render::Range{0, 1.05};
  c.series = {{d.f_hz, d.coherence, "", render::SeriesStyle::kLine, "#009E73"}};
  return fig;
}

}  // namespace chatterlab::app
