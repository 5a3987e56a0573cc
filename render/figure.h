// A small figure model: what to draw, not how. The gnuplot backend (gnuplot_backend.h)
// turns it into SVG, PNG or PDF. Knows nothing of milling: a caller fills labels and data.
//
//   Figure fig;                       // 16 cm wide: the text width of the A4 report
//   fig.share_x = true;               // stacked panels share one x axis
//   Axes& mag = fig.panels.emplace_back();
//   mag.y_label = "|H| [m/N]"; mag.log_y = true; mag.relative_height = 2;
//   mag.series.push_back({f_hz, magnitude, "measured"});
//   Axes& coh = fig.panels.emplace_back();
//   coh.x_label = "frequency [Hz]"; coh.y_label = "coherence [-]"; coh.y_range = Range{0, 1};
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace chatterlab::render {

enum class SeriesStyle {
  kLine,        // solid line; NaN in y (or x) breaks it: a gap, not an error
  kPoints,      // markers only (small filled circles)
  kDashedLine,  // dashed line, e.g. a fit or a model over measured data
  kLinePoints,  // line with markers at every sample
};

struct Series {
  Series() = default;
  // Series{x, y, "label"}, Series{x, y, "fit", SeriesStyle::kDashedLine}: a constructor
  // rather than aggregate initialisation, which -Wmissing-field-initializers rejects.
  Series(std::vector<double> x_values, std::vector<double> y_values, std::string legend = {},
         SeriesStyle line_style = SeriesStyle::kLine, std::string hex_colour = {})
      : x(std::move(x_values)),
        y(std::move(y_values)),
        label(std::move(legend)),
        style(line_style),
        color(std::move(hex_colour)) {}

  std::vector<double> x;
  std::vector<double> y;  // same length as x; NaN and +-inf are not drawn
  std::string label;      // legend text, drawn literally (no markup); empty: not in legend
  SeriesStyle style = SeriesStyle::kLine;
  std::string color;  // "#RRGGBB"; empty: the panel's next colour of the Okabe-Ito palette
};

struct Range {
  double min = 0.0;
  double max = 1.0;  // must be > min; both > 0 on a log axis
};

enum class LegendPosition {
  kAuto,  // the inside corner hiding the fewest data samples, else kAbove (docs/rendering.md)
  kTopRight,
  kTopLeft,
  kBottomRight,
  kBottomLeft,
  kAbove,         // above the plot in as many columns as fit; kAuto's choice when every
                  // inside corner would hide data (a dense signal filling the plot)
  kOutsideRight,  // right of the plot; all panels of the figure shrink alike to stay aligned
  kNone,
};

// One panel: a pair of axes with its series.
struct Axes {
  std::string title;    // above the panel; empty: none
  std::string x_label;  // with the unit, e.g. "frequency [Hz]"; with Figure::share_x only
                        // the bottom panel's x label and tic labels are drawn
  std::string y_label;  // with the unit, e.g. "deflection [um]"
  bool log_x = false;   // values <= 0 on a log axis are not drawn
  bool log_y = false;
  std::optional<Range> x_range;  // fixed range; unset: the data's x extent
  std::optional<Range> y_range;  // fixed range; unset: the data's extent padded by 5 %
                                 // (log axes: extended to whole decades)
  LegendPosition legend = LegendPosition::kAuto;
  double relative_height = 1.0;  // share of the figure's plot height, > 0
  std::vector<Series> series;    // a panel without any finite point shows "no data"
};

struct Figure {
  std::vector<Axes> panels;  // stacked top to bottom, at least one
  double width_in = 6.3;     // 16 cm: the A4 text width of report.css, so that fonts
                             // print at font_pt when the figure fills the text width
  double height_in = 3.6;
  double font_pt = 9.0;         // tic labels and legend; labels and titles are the same or +1 pt
  bool share_x = false;         // panels share the x axis: same x range, no x tic labels and
                                // no x label on any but the bottom panel, small gaps
  std::size_t max_bins = 2000;  // a line series with more than 4 * max_bins points and
                                // sorted x is reduced to first/min/max/last per x bin,
                                // which keeps its drawn envelope (0: never reduce)
};

// Checks sizes, ranges, colours and heights. Throws RenderError naming the field, its value
// and the rule, e.g. "figure.panels[1].series[0]: x has 10 values, y has 9: must be equal".
void validate(const Figure& figure);

}  // namespace chatterlab::render
