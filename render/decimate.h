// Reducing a long series to what can be seen at print resolution, so that a figure with
// ~1e6 points stays a small SVG that browsers and WeasyPrint draw quickly.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

namespace chatterlab::render {

struct XY {
  std::vector<double> x;
  std::vector<double> y;
};

// Min/max envelope reduction of a line whose finite x values are sorted ascending: the
// x extent is cut into `bins` equal bins (equal in log10 x when log_x) and each bin keeps
// its first, lowest, highest and last sample, in their original order. A run of invalid
// samples (NaN or inf in x or y, or <= 0 on a log axis) becomes one NaN, so gaps stay gaps.
// The drawn line covers the same pixels as the full line whenever a bin is narrower than
// a pixel. Unsorted x or bins == 0: returns the input unchanged.
XY reduce_line(const std::vector<double>& x, const std::vector<double>& y, std::size_t bins,
               bool log_x = false, bool log_y = false);

// Scatter reduction: of all points falling in the same cell of a cells x cells grid over
// the data extent (log10 on log axes), only the first is kept; invalid points are dropped.
// With a grid much finer than a marker, the plot looks the same.
XY reduce_points(const std::vector<double>& x, const std::vector<double>& y, std::size_t cells,
                 bool log_x = false, bool log_y = false);

// True when (x, y) can be drawn on the axes: both finite, and > 0 where the axis is log.
inline bool drawable(double x, double y, bool log_x, bool log_y) {
  return std::isfinite(x) && std::isfinite(y) && (!log_x || x > 0.0) && (!log_y || y > 0.0);
}

}  // namespace chatterlab::render
