#include "render/gnuplot_backend.h"

#include <fstream>
#include <system_error>

#include "render/density_raster.h"
#include "render/plot_layout.h"
#include "render/render_error.h"
#include "render/subprocess.h"
#include "render/temp_dir.h"

namespace chatterlab::render {
namespace {

const char* extension(ImageFormat format) {
  switch (format) {
    case ImageFormat::kSvg:
      return ".svg";
    case ImageFormat::kPng:
      return ".png";
    case ImageFormat::kPdf:
      return ".pdf";
  }
  return "";
}

void write_file(const std::filesystem::path& path, const char* data, std::size_t bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(data, static_cast<std::streamsize>(bytes));
  out.close();  // checked after closing: the last buffered block is written then
  if (!out) throw RenderError("cannot write " + path.string());
}

// x0 y0 x1 y1 ...: gnuplot's `binary format='%float64%float64'`.
void write_series(const std::filesystem::path& path, const XY& data) {
  std::vector<double> interleaved(2 * data.x.size());
  for (std::size_t i = 0; i < data.x.size(); ++i) {
    interleaved[2 * i] = data.x[i];
    interleaved[2 * i + 1] = data.y[i];
  }
  write_file(path, reinterpret_cast<const char*>(interleaved.data()),
             interleaved.size() * sizeof(double));
}

}  // namespace

void run_gnuplot(const std::filesystem::path& script, const std::string& gnuplot) {
  const ProcessResult result = run_process({gnuplot, "-d", script.string()});
  if (result.exit_code != 0) {
    throw RenderError("gnuplot failed on " + script.string() + " (exit code " +
                      std::to_string(result.exit_code) + "): " + tail_of(result.err));
  }
}

namespace {

void check_dpi(double dpi) {
  if (!(dpi >= 10.0 && dpi <= 2400.0)) {
    throw RenderError("png dpi = " + std::to_string(dpi) + ": must be in [10, 2400]");
  }
}

// Rasterizes every density series of the figure for each output at the size of its plot
// area there (density_image_path; SVG and PDF share a PNG's raster when rendered with one):
// the points never reach gnuplot.
void write_density_images(const Figure& figure, const FigurePlan& plan,
                          const std::vector<ImageOutput>& outputs,
                          const std::filesystem::path& dir) {
  for (std::size_t p = 0; p < plan.panels.size(); ++p) {
    const Axes& axes = figure.panels[p];
    for (std::size_t k = 0; k < axes.series.size(); ++k) {
      const Series& s = axes.series[k];
      if (s.style != SeriesStyle::kDensity || plan.panels[p].series[k].drawable == 0) continue;
      DensityOptions options;
      options.log_x = axes.log_x;
      options.log_y = axes.log_y;
      options.color = series_colour(s, k);
      options.style = s.density_style;
      for (std::size_t i = 0; i < outputs.size(); ++i) {
        if (raster_source(outputs, i) != i) continue;  // shares a PNG's raster
        const PlotBox box = plot_box(figure, plan, p, outputs[i]);
        const Range& xr = plan.panels[p].x;
        const Range& yr = plan.panels[p].y;
        const RgbaImage image =
            s.xf.empty()
                ? rasterize_density(s.x, s.y, xr, yr, box.width_px, box.height_px, options)
                : rasterize_density(s.xf, s.yf, xr, yr, box.width_px, box.height_px, options);
        write_file(density_image_path(dir, i, p, k),
                   reinterpret_cast<const char*>(image.rgba.data()), image.rgba.size());
      }
    }
  }
}

// Plans the figure, writes its data and a script in a temporary folder, runs gnuplot once
// for all outputs and copies each image to its destination.
void render_outputs(const Figure& figure, const std::vector<ImageOutput>& outputs) {
  const FigurePlan plan = plan_figure(figure);
  const TempDir temp;
  for (std::size_t p = 0; p < plan.panels.size(); ++p) {
    for (std::size_t k = 0; k < plan.panels[p].series.size(); ++k) {
      if (plan.panels[p].series[k].drawable > 0 &&
          figure.panels[p].series[k].style != SeriesStyle::kDensity) {
        write_series(series_data_path(temp.path(), p, k), plan.panels[p].series[k].data);
      }
    }
  }
  write_density_images(figure, plan, outputs, temp.path());
  std::vector<ImageOutput> in_temp = outputs;
  for (std::size_t i = 0; i < in_temp.size(); ++i) {
    in_temp[i].path = temp.path() / ("figure" + std::to_string(i) + extension(outputs[i].format));
  }
  const std::filesystem::path script = temp.path() / "figure.gp";
  const std::string text = gnuplot_script(figure, plan, in_temp, temp.path());
  write_file(script, text.data(), text.size());
  run_gnuplot(script);

  for (std::size_t i = 0; i < outputs.size(); ++i) {
    std::error_code ec;
    if (!std::filesystem::exists(in_temp[i].path, ec)) {
      throw RenderError("gnuplot wrote no image for " + outputs[i].path.string());
    }
    std::filesystem::copy_file(in_temp[i].path, outputs[i].path,
                               std::filesystem::copy_options::overwrite_existing, ec);
    if (ec) {
      throw RenderError("cannot write figure " + outputs[i].path.string() + ": " + ec.message());
    }
  }
}

}  // namespace

void render_figure(const Figure& figure, ImageFormat format, const std::filesystem::path& out,
                   double png_dpi) {
  if (format == ImageFormat::kPng) check_dpi(png_dpi);
  render_outputs(figure, {ImageOutput{format, out, png_dpi}});
}

ReportFigure render_report_figure(const Figure& figure, const std::filesystem::path& stem,
                                  double print_dpi) {
  check_dpi(print_dpi);
  ReportFigure files;
  files.svg = stem;
  files.svg += ".svg";
  files.png = stem;
  files.png += ".png";
  render_outputs(figure, {ImageOutput{ImageFormat::kSvg, files.svg, 0.0},
                          ImageOutput{ImageFormat::kPng, files.png, print_dpi}});
  return files;
}

void render_svg(const Figure& figure, const std::filesystem::path& out_svg) {
  render_figure(figure, ImageFormat::kSvg, out_svg);
}

void render_png(const Figure& figure, const std::filesystem::path& out_png, double dpi) {
  render_figure(figure, ImageFormat::kPng, out_png, dpi);
}

void render_pdf(const Figure& figure, const std::filesystem::path& out_pdf) {
  render_figure(figure, ImageFormat::kPdf, out_pdf);
}

}  // namespace chatterlab::render
