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
