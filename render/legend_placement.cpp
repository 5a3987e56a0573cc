#include <algorithm>
#include <array>
#include <cmath>

#include "render/plot_layout.h"

namespace chatterlab::render {
namespace {

double to_axis(double v, bool log) { return log ? std::log10(v) : v; }

}  // namespace

CornerChoice least_covered_corner(const Axes& axes, const PanelPlan& panel, double key_width,
                                  double key_height) {
  const double x0 = to_axis(panel.x.min, axes.log_x), x1 = to_axis(panel.x.max, axes.log_x);
  const double y0 = to_axis(panel.y.min, axes.log_y), y1 = to_axis(panel.y.max, axes.log_y);
  // The box is estimated from average character widths; a margin of 4 % of the plot keeps
  // data from touching it when the estimate is short.
  constexpr double kMargin = 0.04;
  const double w = std::min(key_width + kMargin, 0.95);
  const double h = std::min(key_height + kMargin, 0.95);
  // Samples under each corner box: top right, top left, bottom right, bottom left.
  std::array<std::size_t, 4> covered{};
  std::size_t total = 0;
  const auto count = [&](double u, double v) {
    if (u < 0 || u > 1 || v < 0 || v > 1) return;
    ++total;
    const bool right = u >= 1 - w, left = u <= w, top = v >= 1 - h, bottom = v <= h;
    covered[0] += right && top;
    covered[1] += left && top;
    covered[2] += right && bottom;
    covered[3] += left && bottom;
  };
  constexpr double kStep = 0.01;  // line segments are sampled every 1 % of the plot size
  for (std::size_t k = 0; k < panel.series.size(); ++k) {
    const XY& d = panel.series[k].data;
    const bool line = axes.series[k].style != SeriesStyle::kPoints &&
                      axes.series[k].style != SeriesStyle::kDensity;
    double pu = std::nan(""), pv = std::nan("");
    for (std::size_t i = 0; i < d.x.size(); ++i) {
      if (!drawable(d.x[i], d.y[i], axes.log_x, axes.log_y)) {
        pu = pv = std::nan("");
        continue;
      }
      const double u = (to_axis(d.x[i], axes.log_x) - x0) / (x1 - x0);
      const double v = (to_axis(d.y[i], axes.log_y) - y0) / (y1 - y0);
      if (line && std::isfinite(pu)) {
        const double length = std::hypot(u - pu, v - pv);
        const int pieces = static_cast<int>(std::min(200.0, std::ceil(length / kStep)));
        for (int j = 1; j < pieces; ++j) {
          const double t = static_cast<double>(j) / pieces;
          count(pu + t * (u - pu), pv + t * (v - pv));
        }
      }
      count(u, v);
      pu = u;
      pv = v;
    }
  }
  constexpr std::array<LegendPosition, 4> kCorners{
      LegendPosition::kTopRight, LegendPosition::kTopLeft, LegendPosition::kBottomRight,
      LegendPosition::kBottomLeft};
  const auto best = std::min_element(covered.begin(), covered.end());
  CornerChoice choice;
  choice.corner = kCorners[static_cast<std::size_t>(best - covered.begin())];
  choice.covered_fraction =
      total == 0 ? 0.0 : static_cast<double>(*best) / static_cast<double>(total);
  return choice;
}

}  // namespace chatterlab::render
