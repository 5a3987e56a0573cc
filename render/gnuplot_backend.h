// Figures to image files through gnuplot (gnuplot-nox 5.4: svg, pngcairo and pdfcairo
// terminals). The data goes to binary files and a script in a private temporary folder
// (a density series as a raster image of its plot area, counted by density_raster.h),
// gnuplot runs as `gnuplot -d script.gp` (no init files, no window), and the image is
// copied to its destination only when gnuplot succeeded. See docs/rendering.md.
#pragma once

#include <filesystem>
#include <string>

#include "render/figure.h"
#include "render/gnuplot_script.h"

namespace chatterlab::render {

// Each throws RenderError on invalid figures (naming the field), when gnuplot is missing
// or fails (quoting its stderr), and when the output cannot be written (naming the file).
void render_svg(const Figure& figure, const std::filesystem::path& out_svg);
void render_png(const Figure& figure, const std::filesystem::path& out_png, double dpi = 150.0);
void render_pdf(const Figure& figure, const std::filesystem::path& out_pdf);
void render_figure(const Figure& figure, ImageFormat format, const std::filesystem::path& out,
                   double png_dpi = 150.0);

// A report figure: <stem>.svg for the browser and <stem>.png at print_dpi for the PDF, from
// one gnuplot run. WeasyPrint 57 draws gnuplot's SVG wrongly (it stops on the point
// markers' currentColor, misplaces superscripts and widens opaque legend boxes), so the
// HTML shows the SVG on screen and the PNG in print (docs/rendering.md, "Figures in the
// PDF"). 200 dpi keeps 9 pt text crisp on paper at ~100-200 kB per figure.
struct ReportFigure {
  std::filesystem::path svg;
  std::filesystem::path png;
};
ReportFigure render_report_figure(const Figure& figure, const std::filesystem::path& stem,
                                  double print_dpi = 200.0);

// Runs gnuplot on a script file; throws RenderError naming the script and quoting gnuplot's
// stderr when it exits non-zero. `gnuplot` is the program, found in PATH.
void run_gnuplot(const std::filesystem::path& script, const std::string& gnuplot = "gnuplot");

}  // namespace chatterlab::render
