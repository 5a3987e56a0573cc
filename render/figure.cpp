#include "render/figure.h"

#include <cctype>
#include <cmath>
#include <sstream>

#include "render/render_error.h"

namespace chatterlab::render {
namespace {

// "<field> = <value>: <rule>" (CONVENTIONS.md), or "<field>: <what>" without a value.
[[noreturn]] void fail(const std::string& field, const std::string& what) {
  throw RenderError(field + what);
}

bool is_hex_colour(const std::string& c) {
  if (c.size() != 7 || c[0] != '#') return false;
  for (std::size_t i = 1; i < c.size(); ++i) {
    if (!std::isxdigit(static_cast<unsigned char>(c[i]))) return false;
  }
  return true;
}

void check_range(const std::string& field, const std::optional<Range>& r, bool log) {
  if (!r) return;
  if (!std::isfinite(r->min) || !std::isfinite(r->max) || !(r->max > r->min)) {
    fail(field, " = [" + message_number(r->min) + ", " + message_number(r->max) +
                    "]: must be finite with max > min");
  }
  if (log && !(r->min > 0.0)) {
    fail(field, " = [" + message_number(r->min) + ", " + message_number(r->max) +
                    "]: must be > 0 on a log axis");
  }
}

void check_density(const std::string& name, const Series& series) {
  const bool doubles = !series.x.empty() || !series.y.empty();
  const bool floats = !series.xf.empty() || !series.yf.empty();
  if (series.style != SeriesStyle::kDensity) {
    if (floats) fail(name, ": xf/yf (float points) are for SeriesStyle::kDensity only");
    return;
  }
  if (doubles && floats) fail(name, ": both x/y and xf/yf are set: set one pair");
  if (series.xf.size() != series.yf.size()) {
    fail(name, ": xf has " + std::to_string(series.xf.size()) + " values, yf has " +
                   std::to_string(series.yf.size()) + ": must be equal");
  }
  const DensityStyle& d = series.density_style;
  if (!(d.min_alpha > 0.0 && d.min_alpha <= 1.0)) {
    fail(name + ".density_style.min_alpha",
         " = " + message_number(d.min_alpha) + ": must be in (0, 1]");
  }
  if (!(d.max_alpha >= d.min_alpha && d.max_alpha <= 1.0)) {
    fail(name + ".density_style.max_alpha", " = " + message_number(d.max_alpha) +
                                                ": must be in [min_alpha, 1] = [" +
                                                message_number(d.min_alpha) + ", 1]");
  }
  if (!(d.full_count >= 0.0 && std::isfinite(d.full_count))) {
    fail(name + ".density_style.full_count",
         " = " + message_number(d.full_count) + ": must be >= 0 (0: auto)");
  }
}

}  // namespace

Series Series::density(std::vector<float> x_values, std::vector<float> y_values, std::string legend,
                       std::string hex_colour) {
  Series s({}, {}, std::move(legend), SeriesStyle::kDensity, std::move(hex_colour));
  s.xf = std::move(x_values);
  s.yf = std::move(y_values);
  return s;
}

void validate(const Figure& figure) {
  if (figure.panels.empty()) fail("figure.panels", " is empty: a figure needs at least one panel");
  if (!(figure.width_in > 0.5 && figure.width_in < 100.0)) {
    fail("figure.width_in",
         " = " + message_number(figure.width_in) + ": must be in (0.5, 100) inches");
  }
  if (!(figure.height_in > 0.5 && figure.height_in < 100.0)) {
    fail("figure.height_in",
         " = " + message_number(figure.height_in) + ": must be in (0.5, 100) inches");
  }
  if (!(figure.font_pt >= 4.0 && figure.font_pt <= 30.0)) {
    fail("figure.font_pt", " = " + message_number(figure.font_pt) + ": must be in [4, 30] points");
  }
  if (!(figure.raster_dpi >= 10.0 && figure.raster_dpi <= 2400.0)) {
    fail("figure.raster_dpi",
         " = " + message_number(figure.raster_dpi) + ": must be in [10, 2400]");
  }
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    const Axes& axes = figure.panels[p];
    const std::string panel = "figure.panels[" + std::to_string(p) + "]";
    if (!(axes.relative_height > 0.0 && std::isfinite(axes.relative_height))) {
      fail(panel + ".relative_height",
           " = " + message_number(axes.relative_height) + ": must be > 0");
    }
    check_range(panel + ".x_range", axes.x_range, axes.log_x);
    check_range(panel + ".y_range", axes.y_range, axes.log_y);
    for (std::size_t s = 0; s < axes.series.size(); ++s) {
      const Series& series = axes.series[s];
      const std::string name = panel + ".series[" + std::to_string(s) + "]";
      if (series.x.size() != series.y.size()) {
        fail(name, ": x has " + std::to_string(series.x.size()) + " values, y has " +
                       std::to_string(series.y.size()) + ": must be equal");
      }
      if (!series.color.empty() && !is_hex_colour(series.color)) {
        fail(name + ".color", " = '" + series.color + "': must be #RRGGBB or empty");
      }
      check_density(name, series);
    }
  }
}

}  // namespace chatterlab::render
