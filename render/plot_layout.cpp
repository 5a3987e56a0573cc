#include "render/plot_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "render/render_error.h"

namespace chatterlab::render {
namespace {

// Height of one text line in units of the font size (gnuplot's own spacing is ~1.2).
constexpr double kLineEm = 1.25;
// Average advance of a DejaVu Sans character in units of the font size.
constexpr double kCharEm = 0.6;
// Autoscaled y axes are padded by this fraction of their span on each side (log: of decades).
constexpr double kPadFraction = 0.05;
// Legend rows are this many text lines apart (gnuplot `set key spacing`).
constexpr double kKeySpacing = 1.15;

double to_axis(double v, bool log) { return log ? std::log10(v) : v; }
double from_axis(double v, bool log) { return log ? std::pow(10.0, v) : v; }

// Text sizes in inches for the figure's font.
struct Metrics {
  double line_in;
  double char_in;
  explicit Metrics(const Figure& f)
      : line_in(f.font_pt * kLineEm / 72.0), char_in(f.font_pt * kCharEm / 72.0) {}
};

// A range around an extent in axis coordinates (log10 on log axes), padded by `pad`.
Range range_from(const Extent& e, bool log, double pad) {
  if (e.empty()) return log ? Range{1.0, 10.0} : Range{0.0, 1.0};
  double lo = e.lo, hi = e.hi;
  if (!(hi > lo)) {  // a single value: a window around it
    const double half = log ? 0.5 : (lo == 0.0 ? 1.0 : 0.1 * std::fabs(lo));
    lo -= half;
    hi += half;
  } else {
    const double d = hi - lo;
    lo -= pad * d;
    hi += pad * d;
  }
  return Range{from_axis(lo, log), from_axis(hi, log)};
}

// Calls f(x, y) for every point of a series, whichever payload (double or float) it holds.
template <class F>
void for_each_point(const Series& s, F&& f) {
  if (!s.xf.empty()) {
    for (std::size_t i = 0; i < s.xf.size(); ++i) {
      f(static_cast<double>(s.xf[i]), static_cast<double>(s.yf[i]));
    }
  } else {
    for (std::size_t i = 0; i < s.x.size(); ++i) f(s.x[i], s.y[i]);
  }
}

// A density series: its drawable count and extents in one pass; no data to write.
SeriesPlan plan_density(const Series& s, const Axes& axes) {
  SeriesPlan plan;
  for_each_point(s, [&](double x, double y) {
    if (!drawable(x, y, axes.log_x, axes.log_y)) return;
    ++plan.drawable;
    plan.density_x.add(to_axis(x, axes.log_x));
    plan.density_y.add(to_axis(y, axes.log_y));
  });
  return plan;
}

// The centres of the legend-grid cells over the panel that a density series touches.
XY touched_cells(const Series& s, const Axes& axes, const PanelPlan& panel) {
  const double x0 = to_axis(panel.x.min, axes.log_x), x1 = to_axis(panel.x.max, axes.log_x);
  const double y0 = to_axis(panel.y.min, axes.log_y), y1 = to_axis(panel.y.max, axes.log_y);
  constexpr std::size_t n = kLegendGridCells;
  const double cells = static_cast<double>(n);
  std::vector<unsigned char> touched(n * n, 0);
  for_each_point(s, [&](double x, double y) {
    if (!drawable(x, y, axes.log_x, axes.log_y)) return;
    const double u = (to_axis(x, axes.log_x) - x0) / (x1 - x0);
    const double v = (to_axis(y, axes.log_y) - y0) / (y1 - y0);
    if (!(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0)) return;
    const auto i = std::min(n - 1, static_cast<std::size_t>(u * cells));
    const auto j = std::min(n - 1, static_cast<std::size_t>(v * cells));
    touched[j * n + i] = 1;
  });
  XY centres;
  for (std::size_t j = 0; j < n; ++j) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!touched[j * n + i]) continue;
      centres.x.push_back(
          from_axis(x0 + (static_cast<double>(i) + 0.5) / cells * (x1 - x0), axes.log_x));
      centres.y.push_back(
          from_axis(y0 + (static_cast<double>(j) + 0.5) / cells * (y1 - y0), axes.log_y));
    }
  }
  return centres;
}

SeriesPlan plan_series(const Series& s, const Axes& axes, std::size_t max_bins) {
  if (s.style == SeriesStyle::kDensity) return plan_density(s, axes);
  SeriesPlan plan;
  if (max_bins > 0 && s.x.size() > 4 * max_bins) {
    plan.data = s.style == SeriesStyle::kPoints
                    ? reduce_points(s.x, s.y, max_bins, axes.log_x, axes.log_y)
                    : reduce_line(s.x, s.y, max_bins, axes.log_x, axes.log_y);
  } else {
    plan.data = XY{s.x, s.y};
  }
  for (std::size_t i = 0; i < plan.data.x.size(); ++i) {
    if (drawable(plan.data.x[i], plan.data.y[i], axes.log_x, axes.log_y)) ++plan.drawable;
  }
  return plan;
}

// Drawable x (or y, for points inside the panel's x range) in axis coordinates.
Extent data_extent(const Axes& axes, const PanelPlan& panel, bool of_y) {
  Extent e;
  for (std::size_t k = 0; k < panel.series.size(); ++k) {
    const SeriesPlan& s = panel.series[k];
    if (axes.series[k].style == SeriesStyle::kDensity) {
      if (s.drawable == 0) continue;
      if (!of_y) {
        e.add(s.density_x.lo);
        e.add(s.density_x.hi);
      } else if (s.density_x.lo >= to_axis(panel.x.min, axes.log_x) &&
                 s.density_x.hi <= to_axis(panel.x.max, axes.log_x)) {
        e.add(s.density_y.lo);
        e.add(s.density_y.hi);
      } else {  // a fixed x range cuts the cloud: y of the points inside it
        for_each_point(axes.series[k], [&](double x, double y) {
          if (drawable(x, y, axes.log_x, axes.log_y) && x >= panel.x.min && x <= panel.x.max) {
            e.add(to_axis(y, axes.log_y));
          }
        });
      }
      continue;
    }
    for (std::size_t i = 0; i < s.data.x.size(); ++i) {
      const double x = s.data.x[i], y = s.data.y[i];
      if (!drawable(x, y, axes.log_x, axes.log_y)) continue;
      if (!of_y) {
        e.add(to_axis(x, axes.log_x));
      } else if (x >= panel.x.min && x <= panel.x.max) {
        e.add(to_axis(y, axes.log_y));
      }
    }
  }
  return e;
}

std::size_t legend_entries(const Axes& axes) {
  return static_cast<std::size_t>(std::count_if(axes.series.begin(), axes.series.end(),
                                                [](const Series& s) { return !s.label.empty(); }));
}

// The longest legend text in characters (UTF-8 continuation bytes take no room; a series
// without points gets " (no data)").
std::size_t longest_label(const Axes& axes, const PanelPlan& panel) {
  std::size_t n = 0;
  for (std::size_t k = 0; k < axes.series.size(); ++k) {
    const std::string& label = axes.series[k].label;
    const auto chars = static_cast<std::size_t>(
        std::count_if(label.begin(), label.end(), [](char c) { return (c & 0xC0) != 0x80; }));
    n = std::max(n, chars + (panel.series[k].drawable == 0 ? 10 : 0));
  }
  return n;
}

void plan_ranges(const Figure& figure, FigurePlan& plan) {
  // x: fixed, else the union of every panel's data when shared, else the panel's own data.
  Extent shared_x;  // in data units, so that a log and a linear panel can share
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    const Axes& axes = figure.panels[p];
    const Extent e = data_extent(axes, plan.panels[p], false);
    if (!e.empty()) {
      shared_x.add(from_axis(e.lo, axes.log_x));
      shared_x.add(from_axis(e.hi, axes.log_x));
    }
  }
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    const Axes& axes = figure.panels[p];
    PanelPlan& panel = plan.panels[p];
    if (axes.x_range) {
      panel.x = *axes.x_range;
    } else if (figure.share_x && !shared_x.empty() && (!axes.log_x || shared_x.lo > 0)) {
      Extent e;
      e.add(to_axis(shared_x.lo, axes.log_x));
      e.add(to_axis(shared_x.hi, axes.log_x));
      panel.x = range_from(e, axes.log_x, 0.0);
    } else {
      panel.x = range_from(data_extent(axes, panel, false), axes.log_x, 0.0);
    }
    panel.y = axes.y_range ? *axes.y_range
                           : range_from(data_extent(axes, panel, true), axes.log_y, kPadFraction);
    for (std::size_t k = 0; k < axes.series.size(); ++k) {
      if (axes.series[k].style == SeriesStyle::kDensity && panel.series[k].drawable > 0) {
        panel.series[k].data = touched_cells(axes.series[k], axes, panel);
      }
    }
  }
}

// Panels top to bottom: fixed space for titles, legends above, tic labels and x labels;
// the rest shared by relative height.
void place_panels(const Figure& figure, const Metrics& m, FigurePlan& plan) {
  const std::size_t n = figure.panels.size();
  const double title_in = 1.7 * m.line_in;
  const double xtics_in = 1.5 * m.line_in;
  const double xlabel_in = 1.4 * m.line_in;
  std::vector<double> above(n, 0.0), below(n, 0.0);
  double fixed = 0.0, weights = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    const Axes& axes = figure.panels[p];
    const PanelPlan& panel = plan.panels[p];
    const bool labels_x = p + 1 == n || !figure.share_x;
    above[p] = (p == 0           ? 0.6
                : figure.share_x ? 0.7
                                 : 0.9) *
                   m.line_in +
               (axes.title.empty() ? 0.0 : title_in);
    if (panel.legend == LegendPosition::kAbove) {
      above[p] += (static_cast<double>(panel.key_rows) * kKeySpacing + 0.9) * m.line_in;
    }
    below[p] = labels_x ? xtics_in + (axes.x_label.empty() ? 0.0 : xlabel_in) : 0.0;
    fixed += above[p] + below[p];
    weights += axes.relative_height;
  }
  fixed += 0.35 * m.line_in;  // under the bottom panel's x label
  const double available = figure.height_in - fixed;
  if (available < 0.6 * static_cast<double>(n)) {
    throw RenderError("figure.height_in = " + std::to_string(figure.height_in) +
                      ": too small for " + std::to_string(n) +
                      " panel(s) with their labels (needs about " +
                      std::to_string(fixed + 0.6 * static_cast<double>(n)) + " in)");
  }
  double cursor = figure.height_in;  // inches from the bottom
  for (std::size_t p = 0; p < n; ++p) {
    cursor -= above[p];
    plan.panels[p].top = cursor / figure.height_in;
    cursor -= available * figure.panels[p].relative_height / weights;
    plan.panels[p].bottom = cursor / figure.height_in;
    cursor -= below[p];
  }
}

// y tics: a labelled tic per two text lines of panel height. The left margin is the same
// for all panels so that stacked panels align: widest tic label, gaps, the y label.
void plan_y_axes(const Figure& figure, const Metrics& m, FigurePlan& plan) {
  std::size_t left = 0;
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    const Axes& axes = figure.panels[p];
    PanelPlan& panel = plan.panels[p];
    const double height_in = (panel.top - panel.bottom) * figure.height_in;
    const auto max_tics = static_cast<std::size_t>(height_in / (1.8 * m.line_in)) + 1;
    panel.y_tics = choose_tics(panel.y, axes.log_y, max_tics);
    left = std::max(left, panel.y_tics.label_chars + 2 + (axes.y_label.empty() ? 0 : 3));
  }
  plan.left_margin_chars = static_cast<int>(left);
}

void plan_right_margin(const Figure& figure, FigurePlan& plan) {
  std::size_t right = 3;  // half of the last x tic label
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    if (plan.panels[p].legend == LegendPosition::kOutsideRight) {
      right = std::max(right, longest_label(figure.panels[p], plan.panels[p]) + 8);
    }
  }
  plan.right_margin_chars = static_cast<int>(right);
}

double plot_width_in(const Figure& figure, const Metrics& m, const FigurePlan& plan) {
  return figure.width_in -
         static_cast<double>(plan.left_margin_chars + plan.right_margin_chars) * m.char_in;
}

// kAuto: the least covered inside corner for a key of the estimated size, else above.
// Returns whether some legend went above (the vertical layout must make room).
bool place_legends(const Figure& figure, const Metrics& m, FigurePlan& plan) {
  bool any_above = false;
  const double width_in = plot_width_in(figure, m, plan);
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    const Axes& axes = figure.panels[p];
    PanelPlan& panel = plan.panels[p];
    const std::size_t entries = legend_entries(axes);
    const double entry_width_in = static_cast<double>(longest_label(axes, panel) + 7) * m.char_in;
    panel.legend = entries == 0 ? LegendPosition::kNone : axes.legend;
    if (panel.legend == LegendPosition::kAuto) {
      const double height_in = (panel.top - panel.bottom) * figure.height_in;
      const double key_h =
          (static_cast<double>(entries) * kKeySpacing + 0.8) * m.line_in / height_in;
      const CornerChoice choice =
          least_covered_corner(axes, panel, entry_width_in / width_in, key_h);
      panel.legend = choice.covered_fraction <= kMaxLegendCoveredFraction ? choice.corner
                                                                          : LegendPosition::kAbove;
    }
    if (panel.legend == LegendPosition::kAbove) {
      panel.key_columns =
          std::clamp<std::size_t>(static_cast<std::size_t>(width_in / entry_width_in), 1, entries);
      panel.key_rows = (entries + panel.key_columns - 1) / panel.key_columns;
      any_above = true;
    }
  }
  return any_above;
}

// x tics: each label needs its width and three characters of space.
void plan_x_axes(const Figure& figure, const Metrics& m, FigurePlan& plan) {
  const double width_in = plot_width_in(figure, m, plan);
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    PanelPlan& panel = plan.panels[p];
    std::size_t max_tics = 12;
    for (;;) {  // the label width depends on the step: shrink until both agree
      panel.x_tics = choose_tics(panel.x, figure.panels[p].log_x, max_tics);
      const auto fit = static_cast<std::size_t>(
          width_in / (static_cast<double>(panel.x_tics.label_chars + 3) * m.char_in));
      if (fit >= max_tics || max_tics <= 2) break;
      max_tics = std::max<std::size_t>(2, fit);
    }
  }
}

}  // namespace

FigurePlan plan_figure(const Figure& figure) {
  validate(figure);
  const Metrics m(figure);
  FigurePlan plan;
  plan.panels.resize(figure.panels.size());
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    PanelPlan& panel = plan.panels[p];
    for (const auto& s : figure.panels[p].series) {
      panel.series.push_back(plan_series(s, figure.panels[p], figure.max_bins));
      panel.has_data = panel.has_data || panel.series.back().drawable > 0;
      plan.has_density = plan.has_density || s.style == SeriesStyle::kDensity;
    }
    // Explicit positions first, so the first layout already has the right margins.
    const bool fixed = figure.panels[p].legend != LegendPosition::kAuto;
    panel.legend = fixed ? figure.panels[p].legend : LegendPosition::kNone;
  }
  plan_ranges(figure, plan);
  place_panels(figure, m, plan);
  plan_y_axes(figure, m, plan);
  plan_right_margin(figure, plan);
  if (place_legends(figure, m, plan)) {  // legends above take height: lay out again
    place_panels(figure, m, plan);
    plan_y_axes(figure, m, plan);
  }
  plan_right_margin(figure, plan);
  if (plot_width_in(figure, m, plan) < 1.0) {
    throw RenderError("figure.width_in = " + std::to_string(figure.width_in) +
                      ": too narrow for the tic labels, y label and legend (leaves " +
                      std::to_string(plot_width_in(figure, m, plan)) + " in to plot)");
  }
  plan_x_axes(figure, m, plan);
  return plan;
}

}  // namespace chatterlab::render
