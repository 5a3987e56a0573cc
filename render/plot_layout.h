// Everything the gnuplot backend decides before writing a script: reduced data, axis
// ranges, legend corners and where each panel sits on the canvas. Pure functions, so the
// decisions are testable without gnuplot.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include "render/axis_tics.h"
#include "render/decimate.h"
#include "render/figure.h"

namespace chatterlab::render {

// The smallest interval holding some values (empty: lo > hi).
struct Extent {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  bool empty() const { return lo > hi; }
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
};

struct SeriesPlan {
  // What is written to the data file (maybe reduced). kDensity: nothing is written (the
  // points stay in the Series and go to the rasterizer); `data` holds the centres of the
  // cells of a kLegendGridCells-square grid over the panel that the cloud touches, which is
  // what legend placement counts as its samples.
  XY data;
  std::size_t drawable = 0;  // points that can be drawn (kDensity: of the Series itself)
  Extent density_x;          // kDensity: drawable points' extent in axis units (log10 on a
  Extent density_y;          // log axis), so the ranges need no second pass over millions
};

// A density cloud counts for legend placement as one sample per touched cell of this many
// cells a side, like a line sampled every 1 % of the plot.
inline constexpr std::size_t kLegendGridCells = 100;

struct PanelPlan {
  std::vector<SeriesPlan> series;  // one per Axes::series, same order
  Range x;                         // the axis ranges drawn, always set
  Range y;
  AxisTics x_tics;  // chosen for the room the panel has
  AxisTics y_tics;
  bool has_data = false;                          // some series has a drawable point
  LegendPosition legend = LegendPosition::kNone;  // resolved: never kAuto
  std::size_t key_columns = 1;                    // kAbove: entries per row
  std::size_t key_rows = 0;                       // kAbove: rows (space reserved above the plot)
  double top = 1.0;  // plot-area edges in screen fractions (0 bottom, 1 top)
  double bottom = 0.0;
};

struct FigurePlan {
  std::vector<PanelPlan> panels;
  bool has_density = false;    // some panel has a kDensity series: margins are fixed at
                               // screen positions (gnuplot_script.h, plot_box)
  int left_margin_chars = 10;  // the same for every panel, so stacked panels align
  int right_margin_chars = 3;
};

// Validates (throws RenderError) and plans the figure.
FigurePlan plan_figure(const Figure& figure);

// Where a legend box of key_width x key_height (fractions of the plot area) would cover the
// fewest drawn samples (points, and lines sampled every 1 % of the plot size).
struct CornerChoice {
  LegendPosition corner = LegendPosition::kTopRight;  // of TR, TL, BR, BL (that order on ties)
  double covered_fraction = 0.0;  // share of all samples under the box in that corner
};
CornerChoice least_covered_corner(const Axes& axes, const PanelPlan& panel, double key_width,
                                  double key_height);

// kAuto: the least covered corner, unless even that one hides more than this share of the
// samples; then the legend goes above the plot.
inline constexpr double kMaxLegendCoveredFraction = 0.01;

}  // namespace chatterlab::render
