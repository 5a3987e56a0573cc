// The density rasterizer: millions of (x, y) points counted per pixel on the GPU of an OSMesa
// context (an OpenGL 4.3 compute shader adding each point to its pixels with atomic adds),
// then shaded as one colour whose opacity grows with the count. The gnuplot backend draws
// SeriesStyle::kDensity series with it; callers who want only the picture use
// rasterize_density and write_png. docs/rendering.md, "Density series".
//
//   DensityOptions o;
//   o.color = "#0072B2";
//   RgbaImage img = rasterize_density(angle_deg, x_um, Range{0, 360}, Range{-40, 40}, 1000, 600,
//   o); write_png(img, "cloud.png");
#pragma once

#include <string>
#include <vector>

#include "render/figure.h"
#include "render/rgba_image.h"

namespace chatterlab::render {

struct DensityOptions {
  bool log_x = false;  // columns equal in log10(x); x_range and drawn x must be > 0
  bool log_y = false;
  std::string color = "#0072B2";  // "#RRGGBB": the colour at full density
  DensityStyle style;             // counting (antialias) and shading
};

// Points per pixel. Pixel (column c, row r) covers x in [x0 + c dx, x0 + (c + 1) dx) and
// y in (y1 - (r + 1) dy, y1 - r dy] with dx = (x1 - x0) / width (in log10 on a log axis):
// row 0 at the top, as in images; the range's far ends belong to the last column and the top
// row. Points outside the ranges, NaN or inf, and <= 0 on a log axis are not counted. Edges
// are resolved in single precision: a point within ~1e-7 of the span of a pixel edge may land
// in either neighbour. With style.antialias a point's weight is shared bilinearly among the
// 4 pixels whose centres surround it (the share beyond the image's edge stays in the edge
// pixel), so counts are fractional; a point on a pixel's centre counts 1 there.
struct DensityGrid {
  int width = 0;
  int height = 0;
  std::vector<float> counts;  // width * height, row 0 at the top

  float at(int column, int row) const {
    return counts[static_cast<std::size_t>(row) * static_cast<std::size_t>(width) +
                  static_cast<std::size_t>(column)];
  }
  double total() const;     // points counted
  float max_count() const;  // 0 when empty
};

// Counts the points into width_px x height_px pixels (each in [1, 16384]) spanning x_range and
// y_range. x and y have equal sizes; float inputs halve the memory. Counts are exact up to
// 2^32 points per pixel (2^24 with antialias). Throws RenderError for bad arguments (naming the
// argument, its value and the rule) and when OSMesa cannot create its context. Thread-safe:
// each thread uses its own context, created on first use (~15 ms) and kept until the thread
// ends. Speed in docs/rendering.md (12 million points: ~0.2 s on 2 cores).
DensityGrid count_density(const std::vector<double>& x, const std::vector<double>& y,
                          const Range& x_range, const Range& y_range, int width_px, int height_px,
                          const DensityOptions& options = {});
DensityGrid count_density(const std::vector<float>& x, const std::vector<float>& y,
                          const Range& x_range, const Range& y_range, int width_px, int height_px,
                          const DensityOptions& options = {});

// Colour and opacity per pixel: empty pixels transparent; a pixel with count n >= 1 gets the
// colour with alpha = min_alpha + (max_alpha - min_alpha) * t, where t rises from 0 at n = 1 to
// 1 at n = full (the largest count unless style.full_count is set) as ln n / ln full (kLog),
// (sqrt n - 1) / (sqrt full - 1) (kSqrt), (n - 1) / (full - 1) (kLinear), or the share of
// non-empty pixels holding less than n over that share for full (kEqualized), clamped to 1.
// A fractional count n < 1 (antialias) gets n * min_alpha. Over white, perceived lightness
// follows alpha.
RgbaImage shade_density(const DensityGrid& grid, const std::string& hex_colour,
                        const DensityStyle& style = {});

// count_density then shade_density with options.color and options.style.
RgbaImage rasterize_density(const std::vector<double>& x, const std::vector<double>& y,
                            const Range& x_range, const Range& y_range, int width_px, int height_px,
                            const DensityOptions& options = {});
RgbaImage rasterize_density(const std::vector<float>& x, const std::vector<float>& y,
                            const Range& x_range, const Range& y_range, int width_px, int height_px,
                            const DensityOptions& options = {});

// The GL renderer the calling thread's rasterizer context runs on (creating it if needed).
std::string density_renderer();

}  // namespace chatterlab::render
