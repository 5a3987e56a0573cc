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
  kDensity,     // every point counted into a density image drawn behind the panel's other
                // series (OSMesa rasterizer, render/density_raster.h): clouds of millions of
                // points, e.g. every revolution of a run overlaid. Legend: a small square
};

// How a density series turns its points into an image: counting per pixel, then opacity of
// its colour growing with the count (docs/rendering.md, "Density series").
enum class DensityScale {
  kLog,        // log(count): shows single stray points and the core of the cloud alike
  kSqrt,       // sqrt(count): between kLog and kLinear
  kLinear,     // count: only where most points are
  kEqualized,  // rank of the count among the image's non-empty pixels (histogram
               // equalisation): every opacity step holds as many pixels, so the structure of
               // any distribution shows; not comparable between figures
};

struct DensityStyle {
  DensityScale scale = DensityScale::kSqrt;
  // Opacity of a pixel holding one point and of a pixel at full_count or more, in (0, 1].
  // 0.2 keeps a lone point visible at print resolution without greying sparse regions.
  double min_alpha = 0.2;
  double max_alpha = 1.0;
  // Count drawn at max_alpha; 0: the image's largest count. Fix it to compare figures.
  double full_count = 0.0;
  // Each point shares its weight among the 4 pixels around it by its position (bilinear, in
  // 1/16 pixel steps) instead of counting whole in the pixel it falls in. Samples on a regular
  // grid (every revolution at the same angles) then do not stripe the image where a pixel
  // column holds one sample angle and the next holds two.
  bool antialias = true;
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

  // A density series holding its points as floats (half the memory of doubles: 12 million
  // points take 96 MB). float carries ~7 significant digits: subtract a large offset
  // (e.g. a start time) before converting.
  static Series density(std::vector<float> x_values, std::vector<float> y_values,
                        std::string legend = {}, std::string hex_colour = {});

  std::vector<double> x;
  std::vector<double> y;  // same length as x; NaN and +-inf are not drawn
  std::string label;      // legend text, drawn literally (no markup); empty: not in legend
  SeriesStyle style = SeriesStyle::kLine;
  std::string color;  // "#RRGGBB"; empty: the panel's next colour of the Okabe-Ito palette
  // kDensity only: the points as floats instead of x and y (one pair or the other is set).
  std::vector<float> xf;
  std::vector<float> yf;
  DensityStyle density_style;  // kDensity only
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
  double font_pt = 9.0;        // tic labels and legend; labels and titles are the same or +1 pt
  bool share_x = false;        // panels share the x axis: same x range, no x tic labels and
                               // no x label on any but the bottom panel, small gaps
  std::size_t max_bins = 500;  // a line series with more than 4 * max_bins points and
                               // sorted x is reduced to first/min/max/last per x bin,
                               // which keeps its drawn envelope (0: never reduce); 500
                               // bins over 6.3 in: ~1 px a bin on screen, ~2 px in print
                               // at 200 dpi, and small SVGs
  double raster_dpi = 200.0;   // density images in SVG and PDF outputs, in pixels per inch
                               // of the figure (PNG outputs, and SVG or PDF written with a
                               // PNG, use the PNG's dpi); 200: sharp on a 2x screen,
                               // ~0.1-1 MB embedded per image
};

// Checks sizes, ranges, colours and heights. Throws RenderError naming the field, its value
// and the rule, e.g. "figure.panels[1].series[0]: x has 10 values, y has 9: must be equal".
void validate(const Figure& figure);

}  // namespace chatterlab::render
