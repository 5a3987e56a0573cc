// Tic choices the gnuplot backend makes itself, so that it knows the labels' widths, small
// panels do not get crowded labels, and log axes always carry labelled tics.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "render/figure.h"

namespace chatterlab::render {

// The starting step between major tics on a linear axis spanning `span` (> 0): 1, 2 or 5
// times a power of ten giving about 5 to 10 tics, by the rule of gnuplot's
// quantize_normal_tics (src/axis.c) with a guide of 20. choose_tics widens it for room.
double linear_tic_step(double span);

struct AxisTics {
  // Linear axis: tics at the multiples of `step`. Log axis with `decades`: tics at
  // `start` * step^k (step 10, or 100, 1000 when decades must be skipped for room), minor
  // tics at 2..9 when step is 10.
  double step = 1.0;
  double start = 1.0;
  bool decades = false;
  // Log axis spanning < 2 decades, where a decade has at most one tic: an explicit list of
  // 1-2-5 values (thinned to 1-5 or 1 for room) with their labels.
  std::vector<double> values;
  std::vector<std::string> labels;
  // Decade labels as 10^{n} (enhanced text) when the axis leaves [1e-3, 1e5] or spans more
  // than 5 decades; plain numbers (0.01, 100, 1000) otherwise.
  bool power_format = false;
  std::size_t label_chars = 1;  // the widest label, in characters
};

// Tics for an axis over `range` with at most `max_tics` labelled tics (>= 2).
AxisTics choose_tics(const Range& range, bool log, std::size_t max_tics);

// "%g" form of a tic value: 0.002, 50, 1e+06.
std::string tic_label(double value);

}  // namespace chatterlab::render
