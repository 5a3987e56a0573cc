#include "render/decimate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_set>

namespace chatterlab::render {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double axis_value(double v, bool log) { return log ? std::log10(v) : v; }

// The samples of one bin: indices of first, lowest, highest and last.
struct Bin {
  std::size_t first = 0, low = 0, high = 0, last = 0;
  bool empty = true;
};

}  // namespace

XY reduce_line(const std::vector<double>& x, const std::vector<double>& y, std::size_t bins,
               bool log_x, bool log_y) {
  const std::size_t n = std::min(x.size(), y.size());
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  double previous = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    if (!drawable(x[i], y[i], log_x, log_y)) continue;
    if (x[i] < previous) return XY{x, y};  // not sorted: no envelope by x bins
    previous = x[i];
    lo = std::min(lo, axis_value(x[i], log_x));
    hi = std::max(hi, axis_value(x[i], log_x));
  }
  if (bins == 0 || !(hi > lo)) return XY{x, y};

  XY out;
  out.x.reserve(4 * bins + 16);
  out.y.reserve(4 * bins + 16);
  Bin bin;
  std::size_t bin_index = 0;
  const auto flush = [&] {
    if (bin.empty) return;
    std::array<std::size_t, 4> keep{bin.first, bin.low, bin.high, bin.last};
    std::sort(keep.begin(), keep.end());
    const auto end = std::unique(keep.begin(), keep.end());
    for (auto it = keep.begin(); it != end; ++it) {
      out.x.push_back(x[*it]);
      out.y.push_back(y[*it]);
    }
    bin = Bin{};
  };
  const double scale = static_cast<double>(bins) / (hi - lo);
  for (std::size_t i = 0; i < n; ++i) {
    if (!drawable(x[i], y[i], log_x, log_y)) {
      flush();
      if (!out.y.empty() && !std::isnan(out.y.back())) {
        out.x.push_back(x[i]);  // keep the gap: one invalid sample between two runs
        out.y.push_back(kNaN);
      }
      continue;
    }
    const double t = (axis_value(x[i], log_x) - lo) * scale;
    const auto b = std::min(bins - 1, static_cast<std::size_t>(std::max(0.0, t)));
    if (!bin.empty && b != bin_index) flush();
    bin_index = b;
    if (bin.empty) {
      bin.first = bin.low = bin.high = i;
      bin.empty = false;
    }
    if (y[i] < y[bin.low]) bin.low = i;
    if (y[i] > y[bin.high]) bin.high = i;
    bin.last = i;
  }
  flush();
  return out;
}

XY reduce_points(const std::vector<double>& x, const std::vector<double>& y, std::size_t cells,
                 bool log_x, bool log_y) {
  const std::size_t n = std::min(x.size(), y.size());
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
  double y_lo = x_lo, y_hi = -x_lo;
  for (std::size_t i = 0; i < n; ++i) {
    if (!drawable(x[i], y[i], log_x, log_y)) continue;
    x_lo = std::min(x_lo, axis_value(x[i], log_x));
    x_hi = std::max(x_hi, axis_value(x[i], log_x));
    y_lo = std::min(y_lo, axis_value(y[i], log_y));
    y_hi = std::max(y_hi, axis_value(y[i], log_y));
  }
  XY out;
  if (cells == 0 || x_lo > x_hi) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!drawable(x[i], y[i], log_x, log_y)) continue;
      out.x.push_back(x[i]);
      out.y.push_back(y[i]);
    }
    return out;
  }
  const double cx = x_hi > x_lo ? static_cast<double>(cells) / (x_hi - x_lo) : 0.0;
  const double cy = y_hi > y_lo ? static_cast<double>(cells) / (y_hi - y_lo) : 0.0;
  const auto last_cell = static_cast<double>(cells - 1);
  std::unordered_set<std::uint64_t> seen;
  for (std::size_t i = 0; i < n; ++i) {
    if (!drawable(x[i], y[i], log_x, log_y)) continue;
    const auto ix =
        static_cast<std::uint64_t>(std::min(last_cell, (axis_value(x[i], log_x) - x_lo) * cx));
    const auto iy =
        static_cast<std::uint64_t>(std::min(last_cell, (axis_value(y[i], log_y) - y_lo) * cy));
    if (!seen.insert(ix * static_cast<std::uint64_t>(cells) + iy).second) continue;
    out.x.push_back(x[i]);
    out.y.push_back(y[i]);
  }
  return out;
}

}  // namespace chatterlab::render
