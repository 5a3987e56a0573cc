#include "render/gnuplot_script.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "render/axis_tics.h"

namespace chatterlab::render {
namespace {

// Numbers in the script: 15 significant digits, enough for any range or tic a user sets.
std::string num(double v) {
  std::array<char, 40> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%.15g", v);
  return buffer.data();
}

constexpr const char* kFont = "DejaVu Sans";
constexpr double kSeriesLineWidthPt = 1.25;
constexpr double kBorderLineWidthPt = 0.6;
constexpr double kGridLineWidthPt = 0.4;
// gnuplot's character width (`set lmargin 10` is 10 of them), in units of the font size,
// measured with GPVAL_TERM_XMIN: svg 0.70, pngcairo and pdfcairo 0.64 (DejaVu Sans).
constexpr double kSvgCharEm = 0.70;
constexpr double kCairoCharEm = 0.64;

// Session-wide style, repeated after each panel's `reset`.
void write_style(std::ostringstream& s, const Figure& figure) {
  s << "set encoding utf8\n"
    << "set border 15 lw " << num(kBorderLineWidthPt) << " lc rgb '#404040'\n"
    << "set tics in scale 0.6, 0.35 nomirror textcolor rgb '#202020'\n"
    << "set mxtics default\nset mytics default\n"
    << "set style line 100 lc rgb '#d0d0d0' lw " << num(kGridLineWidthPt) << " dt 1\n"
    << "set style line 101 lc rgb '#ececec' lw " << num(kGridLineWidthPt) << " dt 1\n"
    << "set format x '%h'\nset format y '%h'\n"
    << "set key noautotitle\n"
    << "set title font '," << num(figure.font_pt + 1) << "' textcolor rgb '#202020'\n"
    << "set xlabel textcolor rgb '#202020'\nset ylabel textcolor rgb '#202020'\n";
}

// Range, tics, tic format and grid for one axis ("x" or "y").
void write_axis(std::ostringstream& s, const std::string& axis, const Range& range, bool log,
                const AxisTics& tics, bool hide_labels) {
  s << "set " << axis << "range [" << num(range.min) << ":" << num(range.max) << "]\n";
  bool minor = false;
  if (!log) {
    s << "set " << axis << "tics " << num(tics.step) << "\n";
  } else if (tics.decades) {
    s << "set logscale " << axis << " 10\n"
      << "set " << axis << "tics " << num(tics.start) << ", " << num(tics.step) << "\n"
      << "set format " << axis << " '" << (tics.power_format ? "10^{%L}" : "%g") << "'\n";
    minor = tics.step == 10.0;
    if (minor) s << "set m" << axis << "tics 10\n";
  } else {
    s << "set logscale " << axis << " 10\nset " << axis << "tics (";
    for (std::size_t i = 0; i < tics.values.size(); ++i) {
      // Explicit labels ignore `set format`: a hidden axis gets empty ones.
      s << (i ? ", " : "") << gnuplot_quote(hide_labels ? std::string() : tics.labels[i]) << " "
        << num(tics.values[i]);
    }
    s << ")\n";
  }
  if (hide_labels) s << "set format " << axis << " ''\n";
  s << "set grid " << axis << "tics" << (minor ? " m" + axis + "tics" : "") << "\n";
}

std::string key_command(const Figure& figure, const PanelPlan& panel) {
  const std::string common =
      " opaque box lc rgb '#c8c8c8' lw 0.4 samplen 2.5 spacing 1.15 width 0.5 height 0.4";
  switch (panel.legend) {
    case LegendPosition::kTopRight:
      return "set key inside top right Right noreverse" + common;
    case LegendPosition::kTopLeft:
      return "set key inside top left Left reverse" + common;
    case LegendPosition::kBottomRight:
      return "set key inside bottom right Right noreverse" + common;
    case LegendPosition::kBottomLeft:
      return "set key inside bottom left Left reverse" + common;
    case LegendPosition::kAbove:
      // Anchored to the plot, not the canvas: gnuplot's own `above` ignores fixed margins.
      // A quarter line above the plot; gnuplot 5.4 has no `set key offset`.
      return "set key at graph 0.5, screen " +
             num(panel.top + 0.25 * figure.font_pt * 1.25 / 72.0 / figure.height_in) +
             " center bottom horizontal Left reverse maxcols " + std::to_string(panel.key_columns) +
             " maxrows " + std::to_string(panel.key_rows) + " samplen 2.5 spacing 1.15 width 1";
    case LegendPosition::kOutsideRight:
      return "set key outside right top Left reverse samplen 2.5 spacing 1.15";
    case LegendPosition::kAuto:  // resolved by plan_figure
    case LegendPosition::kNone:
      break;
  }
  return "unset key";
}

// A dashed line of 4 pt dashes and 2.5 pt gaps. The terminals count dash units differently
// (measured at lw 1.25: svg 0.63 pt, pngcairo and pdfcairo ~0.37 pt per unit).
std::string dash_pattern(ImageFormat format) {
  return format == ImageFormat::kSvg ? "(6,4)" : "(11,7)";
}

std::string with_clause(const Series& series, const std::string& colour, ImageFormat format) {
  std::ostringstream w;
  const std::string lc = " lc rgb '" + colour + "'";
  switch (series.style) {
    case SeriesStyle::kLine:
      w << "with lines lw " << num(kSeriesLineWidthPt) << lc << " dt solid";
      break;
    case SeriesStyle::kDashedLine:
      w << "with lines lw " << num(kSeriesLineWidthPt) << lc << " dt " << dash_pattern(format);
      break;
    case SeriesStyle::kPoints:
      w << "with points pt 7 ps 0.5" << lc;
      break;
    case SeriesStyle::kLinePoints:
      w << "with linespoints lw " << num(kSeriesLineWidthPt) << lc << " dt solid pt 7 ps 0.5";
      break;
    case SeriesStyle::kDensity:  // the legend's marker; the cloud itself is an image
      w << "with points pt 5 ps 0.6" << lc;
      break;
  }
  return w.str();
}

}  // namespace

const char* palette_colour(std::size_t index) {
  constexpr std::array<const char*, 8> kOkabeIto{"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                 "#E69F00", "#56B4E9", "#000000", "#F0E442"};
  return kOkabeIto[index % kOkabeIto.size()];
}

std::string gnuplot_quote(const std::string& text) {
  std::string q = "'";
  for (char c : text) {
    if (c == '\'') {
      q += "''";
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      q += ' ';
    } else {
      q += c;
    }
  }
  return q + "'";
}

std::string terminal_command(const Figure& figure, ImageFormat format, double png_dpi) {
  const std::string font = std::string("font '") + kFont + "," + num(figure.font_pt) + "'";
  std::ostringstream s;
  switch (format) {
    case ImageFormat::kSvg:
      // 96 user units per inch (the CSS px), so the SVG's intrinsic size is the figure's.
      s << "set terminal svg size " << num(std::round(figure.width_in * 96)) << ","
        << num(std::round(figure.height_in * 96)) << " fixed enhanced font '" << kFont << ","
        << num(figure.font_pt * 96.0 / 72.0) << "' linewidth " << num(96.0 / 72.0)
        << " rounded background rgb 'white'";
      break;
    case ImageFormat::kPng:
      // pngcairo sizes fonts at 96 dpi and draws `lw 1` one pixel wide.
      s << "set terminal pngcairo size " << num(std::round(figure.width_in * png_dpi)) << ","
        << num(std::round(figure.height_in * png_dpi)) << " enhanced " << font << " fontscale "
        << num(png_dpi / 96.0) << " linewidth " << num(png_dpi / 72.0)
        << " rounded background rgb 'white'";
      break;
    case ImageFormat::kPdf:
      // pdfcairo sizes fonts at 96 dpi too (its default fontscale 0.5 hides it) and
      // draws `lw 1` 0.5 pt wide.
      s << "set terminal pdfcairo size " << num(figure.width_in) << "in," << num(figure.height_in)
        << "in enhanced " << font << " fontscale 0.75 linewidth 2 rounded"
        << " background rgb 'white'";
      break;
  }
  return s.str();
}

std::string series_colour(const Series& series, std::size_t index) {
  return series.color.empty() ? palette_colour(index) : series.color;
}

PlotBox plot_box(const Figure& figure, const FigurePlan& plan, std::size_t panel,
                 const ImageOutput& output) {
  const double em = output.format == ImageFormat::kSvg ? kSvgCharEm : kCairoCharEm;
  const double char_in = em * figure.font_pt / 72.0;
  const double left_in = plan.left_margin_chars * char_in;
  const double right_in = plan.right_margin_chars * char_in;
  const PanelPlan& p = plan.panels[panel];
  PlotBox box;
  if (output.format == ImageFormat::kPng) {
    // Whole pixels of the canvas terminal_command sets; rows counted from the top. gnuplot
    // puts `at screen f` at f * canvas pixels (checked by the density figure tests).
    const double w = std::round(figure.width_in * output.png_dpi);
    const double h = std::round(figure.height_in * output.png_dpi);
    const double l = std::round(left_in * output.png_dpi);
    const double r = w - std::round(right_in * output.png_dpi);
    const double t = std::round((1.0 - p.top) * h);
    const double b = std::round((1.0 - p.bottom) * h);
    box = {
        l / w, r / w, 1.0 - b / h, 1.0 - t / h, static_cast<int>(r - l), static_cast<int>(b - t)};
  } else {
    box.left = left_in / figure.width_in;
    box.right = 1.0 - right_in / figure.width_in;
    box.bottom = p.bottom;
    box.top = p.top;
    box.width_px =
        static_cast<int>(std::lround((box.right - box.left) * figure.width_in * figure.raster_dpi));
    box.height_px = static_cast<int>(
        std::lround((box.top - box.bottom) * figure.height_in * figure.raster_dpi));
  }
  // gnuplot needs an image of at least 2 x 2 pixels.
  box.width_px = std::max(box.width_px, 2);
  box.height_px = std::max(box.height_px, 2);
  return box;
}

std::size_t raster_source(const std::vector<ImageOutput>& outputs, std::size_t i) {
  if (outputs[i].format == ImageFormat::kPng) return i;
  for (std::size_t j = 0; j < outputs.size(); ++j) {
    if (outputs[j].format == ImageFormat::kPng) return j;
  }
  return i;
}

std::filesystem::path density_image_path(const std::filesystem::path& data_dir, std::size_t output,
                                         std::size_t p, std::size_t k) {
  return data_dir / ("o" + std::to_string(output) + "_p" + std::to_string(p) + "_s" +
                     std::to_string(k) + ".rgba");
}

std::filesystem::path series_data_path(const std::filesystem::path& data_dir, std::size_t p,
                                       std::size_t k) {
  return data_dir / ("p" + std::to_string(p) + "_s" + std::to_string(k) + ".bin");
}

namespace {

// The panels of one image, between `set multiplot` and `unset multiplot`.
void write_panels(std::ostringstream& s, const Figure& figure, const FigurePlan& plan,
                  const std::vector<ImageOutput>& outputs, std::size_t output_index,
                  const std::filesystem::path& data_dir) {
  const ImageOutput& output = outputs[output_index];
  const ImageFormat format = output.format;
  const std::size_t raster = raster_source(outputs, output_index);
  const std::size_t n = figure.panels.size();
  for (std::size_t p = 0; p < n; ++p) {
    const Axes& axes = figure.panels[p];
    const PanelPlan& panel = plan.panels[p];
    const bool hide_x = figure.share_x && p + 1 < n;
    s << "\n# panel " << p << "\nreset\n";
    write_style(s, figure);
    const PlotBox box = plot_box(figure, plan, p, output);
    if (plan.has_density) {
      s << "set lmargin at screen " << num(box.left) << "\nset rmargin at screen " << num(box.right)
        << "\nset tmargin at screen " << num(box.top) << "\nset bmargin at screen "
        << num(box.bottom) << "\n";
    } else {
      s << "set lmargin " << plan.left_margin_chars << "\nset rmargin " << plan.right_margin_chars
        << "\nset tmargin at screen " << num(panel.top) << "\nset bmargin at screen "
        << num(panel.bottom) << "\n";
    }
    if (!axes.title.empty()) {
      s << "set title " << gnuplot_quote(axes.title) << " noenhanced";
      if (panel.legend == LegendPosition::kAbove) {
        s << " offset 0," << num(static_cast<double>(panel.key_rows) * 1.15 + 0.6);
      }
      s << "\n";
    }
    if (!axes.x_label.empty() && !hide_x) {
      s << "set xlabel " << gnuplot_quote(axes.x_label) << " noenhanced offset 0,0.3\n";
    }
    if (!axes.y_label.empty()) {
      s << "set ylabel " << gnuplot_quote(axes.y_label) << " noenhanced\n";
    }
    write_axis(s, "x", panel.x, axes.log_x, panel.x_tics, hide_x);
    write_axis(s, "y", panel.y, axes.log_y, panel.y_tics, false);
    s << "set grid back ls 100, ls 101\n" << key_command(figure, panel) << "\n";
    if (!panel.has_data) {
      s << "set label 1 'no data' at graph 0.5, graph 0.5 center textcolor rgb '#808080'\n";
    }

    std::ostringstream plot;
    std::size_t terms = 0;
    // Density images first, so every other series draws over them; each spans the x2/y2
    // axes' [0, width_px] x [0, height_px], i.e. the plot area (see PlotBox).
    const PlotBox raster_box =
        raster == output_index ? box : plot_box(figure, plan, p, outputs[raster]);
    bool x2y2 = false;
    for (std::size_t k = 0; k < axes.series.size(); ++k) {
      if (axes.series[k].style != SeriesStyle::kDensity || panel.series[k].drawable == 0) continue;
      if (!x2y2) {
        s << "set x2range [0:" << raster_box.width_px
          << "]\nset y2range [0:" << raster_box.height_px << "]\n";
        x2y2 = true;
      }
      plot << (terms++ ? ", \\\n     " : "plot ")
           << gnuplot_quote(density_image_path(data_dir, raster, p, k).string())
           << " binary array=(" << raster_box.width_px << "," << raster_box.height_px
           << ") format='%uchar%uchar%uchar%uchar' flipy origin=(0.5,0.5) dx=1 dy=1 axes x2y2"
           << " with rgbalpha notitle";
    }
    if (!panel.has_data) {
      // An empty first term: gnuplot 5.4 asserts (uses_axis) on a plot of only keyentry.
      plot << "plot NaN notitle";
      ++terms;
    }
    for (std::size_t k = 0; k < axes.series.size(); ++k) {
      const Series& series = axes.series[k];
      if (series.style == SeriesStyle::kDensity && series.label.empty()) continue;
      const std::string colour = series_colour(series, k);
      const std::string title =
          series.label.empty()
              ? "notitle"
              : "title " +
                    gnuplot_quote(series.label + (panel.series[k].drawable ? "" : " (no data)")) +
                    " noenhanced";
      plot << (terms++ ? ", \\\n     " : "plot ");
      if (panel.series[k].drawable == 0 || series.style == SeriesStyle::kDensity) {
        // Nothing to draw (gnuplot would stop on an empty file), or a density series, drawn
        // as an image above: only the legend entry.
        plot << "keyentry " << with_clause(series, colour, format) << " " << title;
      } else {
        plot << gnuplot_quote(series_data_path(data_dir, p, k).string())
             << " binary format='%float64%float64' using 1:2 "
             << with_clause(series, colour, format) << " " << title;
      }
    }
    s << plot.str() << "\n";
  }
}

}  // namespace

std::string gnuplot_script(const Figure& figure, const FigurePlan& plan,
                           const std::vector<ImageOutput>& outputs,
                           const std::filesystem::path& data_dir) {
  std::ostringstream s;
  s << "# chatterlab figure: " << figure.panels.size() << " panel(s)\n";
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const ImageOutput& output = outputs[i];
    s << "\n"
      << terminal_command(figure, output.format, output.png_dpi) << "\n"
      << "set output " << gnuplot_quote(output.path.string()) << "\n"
      << "set multiplot\n";
    write_panels(s, figure, plan, outputs, i, data_dir);
    s << "\nunset multiplot\nset output\n";
  }
  return s.str();
}

}  // namespace chatterlab::render
