#include "render/axis_tics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace chatterlab::render {
namespace {

// Labels of the linear tics k * step inside range, as gnuplot's "%h" shows them.
std::size_t linear_label_chars(const Range& range, double step) {
  std::size_t widest = 1;
  for (double t = std::ceil(range.min / step) * step; t <= range.max + 1e-9 * step; t += step) {
    const double shown = std::fabs(t) < 1e-9 * step ? 0.0 : t;
    widest = std::max(widest, tic_label(shown).size());
  }
  return widest;
}

std::size_t tic_count(const Range& range, double step) {
  return static_cast<std::size_t>(std::floor(range.max / step + 1e-9) -
                                  std::ceil(range.min / step - 1e-9) + 1);
}

// The next 1-2-5 step above `step`.
double next_step(double step) {
  const double power = std::pow(10.0, std::floor(std::log10(step) + 1e-9));
  const double m = step / power;
  return (m < 1.5 ? 2.0 : m < 3.5 ? 5.0 : 10.0) * power;
}

}  // namespace

double linear_tic_step(double span) {
  const double power = std::pow(10.0, std::floor(std::log10(span)));
  const double xnorm = span / power;
  const double positions = 20.0 / xnorm;  // gnuplot's guide of 20 tics
  double tics = 0.0;
  if (positions > 40) {
    tics = 0.05;
  } else if (positions > 20) {
    tics = 0.1;
  } else if (positions > 10) {
    tics = 0.2;
  } else if (positions > 4) {
    tics = 0.5;
  } else if (positions > 2) {
    tics = 1;
  } else if (positions > 0.5) {
    tics = 2;
  } else {
    tics = std::ceil(xnorm);
  }
  return tics * power;
}

std::string tic_label(double value) {
  std::array<char, 32> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%g", value);
  return buffer.data();
}

AxisTics choose_tics(const Range& range, bool log, std::size_t max_tics) {
  max_tics = std::max<std::size_t>(max_tics, 2);
  AxisTics tics;
  if (!log) {
    tics.step = linear_tic_step(range.max - range.min);
    while (tic_count(range, tics.step) > max_tics) tics.step = next_step(tics.step);
    tics.label_chars = linear_label_chars(range, tics.step);
    return tics;
  }
  const double lo = std::log10(range.min);
  const double hi = std::log10(range.max);
  if (hi - lo >= 2.0) {
    tics.decades = true;
    tics.power_format = range.min < 1e-3 || range.max > 1e5 || hi - lo > 5.0;
    const double first = std::ceil(lo - 1e-9);
    const double count = std::floor(hi + 1e-9) - first + 1;
    double skip = 1;
    while (count / skip > static_cast<double>(max_tics)) ++skip;
    tics.step = std::pow(10.0, skip);
    tics.start = std::pow(10.0, first);
    std::size_t widest = 1;
    for (double e = first; e <= hi + 1e-9; e += skip) {
      widest = std::max(widest, tic_label(std::pow(10.0, e)).size());
    }
    tics.label_chars = tics.power_format ? 4 : widest;  // "10" and a small exponent
    return tics;
  }
  // Fewer than two decades: 1-2-5 values, thinned until they fit.
  constexpr std::array<std::array<double, 3>, 3> kSets{
      {{1.0, 2.0, 5.0}, {1.0, 5.0, 0.0}, {1.0, 0.0, 0.0}}};
  for (const auto& mantissas : kSets) {
    tics.values.clear();
    tics.labels.clear();
    for (double e = std::floor(lo); e <= std::ceil(hi); e += 1.0) {
      for (double m : mantissas) {
        if (m == 0.0) continue;
        // Rounded through the label so that 2e-3 is exactly the value its label shows.
        const double v = std::stod(tic_label(m * std::pow(10.0, e)));
        if (v >= range.min * (1 - 1e-12) && v <= range.max * (1 + 1e-12)) {
          tics.values.push_back(v);
          tics.labels.push_back(tic_label(v));
        }
      }
    }
    if (tics.values.size() <= max_tics) break;
  }
  if (tics.values.size() < 2) {  // inside one decade, e.g. [3, 8]: linear steps, listed
    const AxisTics linear = choose_tics(range, false, max_tics);
    tics.values.clear();
    tics.labels.clear();
    for (double t = std::ceil(range.min / linear.step) * linear.step;
         t <= range.max + 1e-9 * linear.step; t += linear.step) {
      tics.values.push_back(t);
      tics.labels.push_back(tic_label(t));
    }
  }
  for (const auto& l : tics.labels) tics.label_chars = std::max(tics.label_chars, l.size());
  return tics;
}

}  // namespace chatterlab::render
