// The gnuplot script for a planned figure: one `set multiplot` page with a panel per Axes,
// each reading its series from binary data files written by the backend.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "render/figure.h"
#include "render/plot_layout.h"

namespace chatterlab::render {

enum class ImageFormat { kSvg, kPng, kPdf };

// The `set terminal` line for a figure of width_in x height_in inches whose text is
// font_pt points and whose `lw 1` line is 1 point wide when shown at that size. Each
// terminal counts differently (svg: 96 user units per inch; cairo: 96 dpi fonts, pdfcairo
// `lw 1` = 0.5 pt), calibrated against pdftotext and stroke widths.
std::string terminal_command(const Figure& figure, ImageFormat format, double png_dpi);

// The path of data file k of panel p inside `data_dir`: p<p>_s<k>.bin, interleaved
// native-endian doubles x0 y0 x1 y1 ...
std::filesystem::path series_data_path(const std::filesystem::path& data_dir, std::size_t p,
                                       std::size_t k);

struct ImageOutput {
  ImageFormat format = ImageFormat::kSvg;
  std::filesystem::path path;
  double png_dpi = 150.0;  // kPng only
};

// The plot area of a panel on one output and the raster that covers it. Figures with a
// density series fix all four margins at screen positions (the left and right ones from the
// plan's character counts at the terminal's own character width, so the layout matches the
// same figure without density), and the raster is placed on the x2/y2 axes spanning
// [0, width_px] x [0, height_px]: it fills the plot area whatever the x/y axes are (log too).
// On a PNG the edges fall on pixel boundaries and the raster maps one to one onto the
// image's pixels; on SVG and PDF the raster has Figure::raster_dpi and is scaled to fit.
struct PlotBox {
  double left = 0.0;  // screen fractions, 0 at the left and bottom edges of the canvas
  double right = 1.0;
  double bottom = 0.0;
  double top = 1.0;
  int width_px = 1;  // raster size
  int height_px = 1;
};
PlotBox plot_box(const Figure& figure, const FigurePlan& plan, std::size_t panel,
                 const ImageOutput& output);

// Which output's raster output i draws: its own, except that an SVG or PDF written in the
// same run as a PNG shares the first PNG's (gnuplot scales it to the plot area, whose aspect
// differs by the terminals' character widths, ~1 %), so render_report_figure counts once.
std::size_t raster_source(const std::vector<ImageOutput>& outputs, std::size_t i);

// The density image of series k of panel p for output number `output` inside data_dir:
// o<output>_p<p>_s<k>.rgba, raw 8-bit RGBA rows from the top (RgbaImage::rgba). Raw, not PNG:
// gnuplot reads PNG through libgd, whose 7-bit alpha turns transparent into 1/255 opaque.
std::filesystem::path density_image_path(const std::filesystem::path& data_dir, std::size_t output,
                                         std::size_t p, std::size_t k);

// The colour a series is drawn in: its own, else palette_colour(index in its panel).
std::string series_colour(const Series& series, std::size_t index);

// The whole script, drawing the figure once per output. Text from the caller (titles,
// labels, legend entries) is quoted for gnuplot and drawn literally (`noenhanced`): quotes,
// underscores, ^, @ and $ are safe.
std::string gnuplot_script(const Figure& figure, const FigurePlan& plan,
                           const std::vector<ImageOutput>& outputs,
                           const std::filesystem::path& data_dir);

// A gnuplot single-quoted string literal: ' doubled, newlines and other control characters
// replaced by spaces.
std::string gnuplot_quote(const std::string& text);

// The Okabe-Ito colour-blind-safe palette (Okabe & Ito 2008, "Color Universal Design"),
// reordered so that the first colours are the most distinct on white; yellow comes last.
const char* palette_colour(std::size_t index);

}  // namespace chatterlab::render
