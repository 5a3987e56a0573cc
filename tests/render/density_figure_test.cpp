// Density series composed into gnuplot figures: the raster fills the plot area exactly,
// behind the other series, in SVG, PNG and PDF; its points never reach gnuplot's files.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <regex>
#include <thread>

#include "render/density_raster.h"
#include "render/gnuplot_backend.h"
#include "render/mustache_template.h"
#include "render/plot_layout.h"
#include "render/render_error.h"
#include "render/rgba_image.h"
#include "render/subprocess.h"
#include "render/temp_dir.h"
#include "tests/support/scratch_tmpdir.h"

namespace chatterlab::render {
namespace {

constexpr const char* kBlue = "#0072B2";  // palette_colour(0)

// A band of points 1.5 <= y <= 2.5 over 0 <= x <= 10, on a grid finer than the pixels so
// every pixel of the band is hit, plus the line y = 6 + 0.2 x. Fixed ranges [0, 10] x [0, 10].
Figure band_figure(std::size_t columns = 3000, std::size_t rows = 200) {
  Figure fig;
  Axes& a = fig.panels.emplace_back();
  a.x_label = "angle [deg]";
  a.y_label = "deflection [um]";
  a.x_range = Range{0, 10};
  a.y_range = Range{0, 10};
  std::vector<float> x, y;
  x.reserve(columns * rows);
  y.reserve(columns * rows);
  for (std::size_t i = 0; i < columns; ++i) {
    for (std::size_t j = 0; j < rows; ++j) {
      x.push_back(static_cast<float>(10.0 * static_cast<double>(i) / (columns - 1)));
      y.push_back(static_cast<float>(1.5 + static_cast<double>(j) / (rows - 1)));
    }
  }
  a.series.push_back(Series::density(std::move(x), std::move(y), "every revolution"));
  // Every touched pixel at full opacity, so it shows the series colour itself.
  a.series.back().density_style.full_count = 1;
  a.series.push_back({{0, 10}, {6, 8}, "mean", SeriesStyle::kLine, "#000000"});
  a.legend = LegendPosition::kTopLeft;
  return fig;
}

struct Rgb {
  int r, g, b;
};
Rgb pixel(const RgbaImage& img, double col, double row) {
  const std::uint8_t* p = img.at(static_cast<int>(col), static_cast<int>(row));
  return {p[0], p[1], p[2]};
}
bool near(const Rgb& a, const Rgb& b, int tol) {
  return std::abs(a.r - b.r) <= tol && std::abs(a.g - b.g) <= tol && std::abs(a.b - b.b) <= tol;
}
std::ostream& operator<<(std::ostream& o, const Rgb& c) {
  return o << "(" << c.r << "," << c.g << "," << c.b << ")";
}
constexpr Rgb kBlueRgb{0x00, 0x72, 0xB2};
constexpr Rgb kWhite{255, 255, 255};
// cairo composites 8-bit colours; an opaque image pixel comes out within 2 of its value.
constexpr int kColourTol = 2;

class DensityFigureTest : public chatterlab::testing::ScratchTmpdirTest {
 protected:
  DensityFigureTest() : ScratchTmpdirTest("chatterlab-density-test-") {}
};

// Where data (x, y) of panel 0 lies on a PNG of `dpi`, in pixel coordinates (column, row),
// from the plot box the backend gives gnuplot and the linear ranges [0, 10] x [0, 10].
struct PngMap {
  PlotBox box;
  double w_px, h_px;
  double col(double x) const { return box.left * w_px + x / 10.0 * box.width_px; }
  double row(double y) const { return (1.0 - box.top) * h_px + (1.0 - y / 10.0) * box.height_px; }
};
PngMap png_map(const Figure& fig, double dpi) {
  const FigurePlan plan = plan_figure(fig);
  return {plot_box(fig, plan, 0, ImageOutput{ImageFormat::kPng, {}, dpi}),
          std::round(fig.width_in * dpi), std::round(fig.height_in * dpi)};
}

TEST_F(DensityFigureTest, PngShowsTheCloudInItsColourWherePointsAreAndNowhereElse) {
  const Figure fig = band_figure();
  const ReportFigure files = render_report_figure(fig, out_ / "band", 200.0);
  const RgbaImage img = read_png(files.png);
  ASSERT_EQ(img.width, 1260);
  const PngMap m = png_map(fig, 200.0);
  // Inside the band, away from grid lines (tics every 2 units): the series colour.
  for (double x : {0.3, 3.0, 5.0, 7.0, 9.7}) {
    for (double y : {1.65, 2.0, 2.35}) {
      EXPECT_TRUE(near(pixel(img, m.col(x), m.row(y)), kBlueRgb, kColourTol))
          << "x " << x << " y " << y << ": " << pixel(img, m.col(x), m.row(y));
    }
  }
  // Off the band by 0.15 units (~6 px), and far from it: white.
  for (double x : {1.0, 5.0, 9.0}) {
    for (double y : {1.35, 2.65, 5.0, 9.0}) {
      EXPECT_TRUE(near(pixel(img, m.col(x), m.row(y)), kWhite, 0))
          << "x " << x << " y " << y << ": " << pixel(img, m.col(x), m.row(y));
    }
  }
  // The line is drawn over the cloud's panel: black on y = 6 + 0.2 x.
  EXPECT_TRUE(near(pixel(img, m.col(5.0), m.row(7.0)), {0, 0, 0}, 10));
  // The raster ends where gnuplot's frame is: the frame (#404040, ~1.7 px wide on the box
  // edge) darkens column box.left - 1 or box.left at the band's height, and the pixel three
  // columns outside is white while three inside is the colour.
  const double band_row = m.row(2.0);
  const double left = m.box.left * m.w_px, right = m.box.right * m.w_px;
  EXPECT_LT(std::min(pixel(img, left - 1, band_row).r, pixel(img, left, band_row).r), 120);
  EXPECT_LT(std::min(pixel(img, right - 1, band_row).r, pixel(img, right, band_row).r), 120);
  EXPECT_TRUE(near(pixel(img, left - 3, band_row), kWhite, 0)) << pixel(img, left - 3, band_row);
  EXPECT_TRUE(near(pixel(img, right + 2, band_row), kWhite, 0)) << pixel(img, right + 2, band_row);
  EXPECT_TRUE(near(pixel(img, left + 3, band_row), kBlueRgb, kColourTol));
  EXPECT_TRUE(near(pixel(img, right - 4, band_row), kBlueRgb, kColourTol));
}

TEST_F(DensityFigureTest, SvgEmbedsTheImageAndTheLegendHasASquareInTheColour) {
  const ReportFigure files = render_report_figure(band_figure(), out_ / "band");
  const std::string svg = read_text_file(files.svg);
  EXPECT_NE(svg.find("<image"), std::string::npos);
  EXPECT_NE(svg.find("data:image/png;base64,"), std::string::npos);
  EXPECT_NE(svg.find(">every revolution<"), std::string::npos);
  EXPECT_NE(svg.find(">mean<"), std::string::npos);
  // The legend marker: gnuplot's point type 5 (filled square, #gpPt4) in the series colour.
  EXPECT_TRUE(std::regex_search(svg, std::regex("gpPt4[^>]*color='rgb\\(  0, 114, 178\\)'")))
      << svg.substr(0, 3000);
  // The image covers the frame exactly: gnuplot's border rectangle (#404040, closed path
  // from the top left corner down, right, up) has the image's corners.
  std::smatch image, frame;
  ASSERT_TRUE(std::regex_search(
      svg, image,
      std::regex("<image x='([0-9.]+)' y='([0-9.]+)' width='([0-9.]+)' height='([0-9.]+)'")));
  ASSERT_TRUE(
      std::regex_search(svg, frame,
                        std::regex("stroke='rgb\\( 64,  64,  64\\)'\\s+d='M([0-9.]+),([0-9.]+) "
                                   "L[0-9.]+,([0-9.]+) L([0-9.]+),[0-9.]+ L[0-9.]+,[0-9.]+ "
                                   "L[0-9.]+,[0-9.]+ Z")));
  // SVG coordinates have 2 decimals.
  EXPECT_NEAR(std::stod(image[1]), std::stod(frame[1]), 0.011);                        // left
  EXPECT_NEAR(std::stod(image[2]), std::stod(frame[2]), 0.011);                        // top
  EXPECT_NEAR(std::stod(image[1]) + std::stod(image[3]), std::stod(frame[4]), 0.021);  // right
  EXPECT_NEAR(std::stod(image[2]) + std::stod(image[4]), std::stod(frame[3]), 0.021);  // bottom
  // 600 000 points, none of them drawn as an SVG element: the file is the raster (~0.1 MB
  // base64) and the axes.
  EXPECT_LT(std::filesystem::file_size(files.svg), 400'000u);
}

TEST_F(DensityFigureTest, PdfEmbedsOneImageOfTheRasterSize) {
  const Figure fig = band_figure();
  const auto pdf = out_ / "band.pdf";
  render_pdf(fig, pdf);
  const ProcessResult list = run_process({"pdfimages", "-list", pdf.string()});
  ASSERT_EQ(list.exit_code, 0) << list.err;
  const PlotBox box = plot_box(fig, plan_figure(fig), 0, ImageOutput{ImageFormat::kPdf, {}, 0.0});
  // pdfimages: "page num type width height color ..."; cairo may add an soft mask (smask)
  // for the alpha channel, of the same size.
  const std::regex image_re("\\n\\s*1\\s+\\d+\\s+image\\s+(\\d+)\\s+(\\d+)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(list.out, m, image_re)) << list.out;
  EXPECT_EQ(std::stoi(m[1]), box.width_px);
  EXPECT_EQ(std::stoi(m[2]), box.height_px);
  // 200 dpi over the plot area's inches.
  EXPECT_NEAR(box.width_px / ((box.right - box.left) * fig.width_in), 200.0, 0.5);
}

TEST_F(DensityFigureTest, LogAxesPlaceTheCloudByDecade) {
  // A thin vertical stripe of points at x = 100 on a log axis over [10, 1000]: the middle
  // of the plot. And a stripe at y = 1e-4 on a log y axis over [1e-6, 1e-2], also the middle.
  Figure fig;
  Axes& a = fig.panels.emplace_back();
  a.log_x = a.log_y = true;
  a.x_range = Range{10, 1000};
  a.y_range = Range{1e-6, 1e-2};
  std::vector<double> x, y;
  for (int i = 0; i <= 2000; ++i) {
    const double t = i / 2000.0;
    x.push_back(100.0);  // vertical stripe
    y.push_back(std::pow(10.0, -6.0 + 4 * t));
    x.push_back(std::pow(10.0, 1.0 + 2 * t));  // horizontal stripe
    y.push_back(1e-4);
  }
  a.series.push_back({x, y, "", SeriesStyle::kDensity});
  a.series.back().density_style.full_count = 1;
  render_png(fig, out_ / "log.png", 200.0);
  const RgbaImage img = read_png(out_ / "log.png");
  const PlotBox box = plot_box(fig, plan_figure(fig), 0, ImageOutput{ImageFormat::kPng, {}, 200});
  const double mid_col = box.left * img.width + 0.5 * box.width_px;
  const double mid_row = (1.0 - box.top) * img.height + 0.5 * box.height_px;
  // On the stripes (a quarter of the plot from the centre), the colour; 5 px beside, white.
  EXPECT_TRUE(near(pixel(img, mid_col, mid_row - 0.25 * box.height_px), kBlueRgb, kColourTol));
  EXPECT_TRUE(near(pixel(img, mid_col + 0.25 * box.width_px, mid_row), kBlueRgb, kColourTol));
  EXPECT_TRUE(near(pixel(img, mid_col + 5, mid_row - 0.3 * box.height_px), kWhite, 0));
  // (x = 10^2.54 = 347, between the minor grid lines at 300 and 400.)
  EXPECT_TRUE(near(pixel(img, mid_col + 0.27 * box.width_px, mid_row + 5), kWhite, 0))
      << pixel(img, mid_col + 0.27 * box.width_px, mid_row + 5);
}

// A stand-in gnuplot in PATH records the size of the script's folder (the data, the images
// and the script) before running the real one.
TEST_F(DensityFigureTest, GnuplotFilesHoldTheRasterNotThePoints) {
  const auto bin = scratch_.path() / "bin";
  std::filesystem::create_directory(bin);
  const auto record = scratch_.path() / "du.txt";
  const auto wrapper = bin / "gnuplot";
  std::ofstream(wrapper) << "#!/bin/sh\ndu -sb \"$(dirname \"$2\")\" > '" << record.string()
                         << "'\nexec /usr/bin/gnuplot \"$@\"\n";
  std::filesystem::permissions(wrapper, std::filesystem::perms::owner_all);
  const std::string old_path = std::getenv("PATH");
  ::setenv("PATH", (bin.string() + ":" + old_path).c_str(), 1);
  // 3 million points: 48 MB as gnuplot's interleaved doubles.
  const Figure fig = band_figure(15000, 200);
  render_report_figure(fig, out_ / "big", 200.0);
  ::setenv("PATH", old_path.c_str(), 1);
  std::ifstream in(record);
  std::uintmax_t bytes = 0;
  ASSERT_TRUE(in >> bytes) << "the wrapper did not run";
  // One raster of 4 bytes a pixel (the SVG shares the PNG's), plus the script, the two-point
  // line and the folder entries: under 64 kB beyond the raster.
  const PlotBox b = plot_box(fig, plan_figure(fig), 0, ImageOutput{ImageFormat::kPng, {}, 200});
  const std::uintmax_t raster_bytes = 4u * static_cast<std::uintmax_t>(b.width_px) * b.height_px;
  EXPECT_GE(bytes, raster_bytes);
  EXPECT_LT(bytes, raster_bytes + 64'000u);
  EXPECT_LT(bytes, 48'000'000u / 4);
}

TEST_F(DensityFigureTest, CloudAloneAndCloudWithoutPointsStillRender) {
  Figure fig;
  Axes& a = fig.panels.emplace_back();
  std::vector<double> x(5000), y(5000);
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = n(rng);
    y[i] = n(rng);
  }
  a.series.push_back({x, y, "cloud", SeriesStyle::kDensity});
  Axes& b = fig.panels.emplace_back();
  b.series.push_back({{1.0}, {std::nan("")}, "empty cloud", SeriesStyle::kDensity});
  render_svg(fig, out_ / "alone.svg");
  const std::string svg = read_text_file(out_ / "alone.svg");
  EXPECT_NE(svg.find(">cloud<"), std::string::npos);
  EXPECT_NE(svg.find(">empty cloud (no data)<"), std::string::npos);
  EXPECT_NE(svg.find(">no data<"), std::string::npos);
}

TEST_F(DensityFigureTest, TwoThreadsRenderFiguresAtOnce) {
  const Figure fig = band_figure(500, 50);
  std::string error;
  std::thread other([&] {
    try {
      for (int i = 0; i < 3; ++i) render_png(fig, out_ / "t1.png", 100.0);
    } catch (const std::exception& e) {
      error = e.what();
    }
  });
  for (int i = 0; i < 3; ++i) render_png(fig, out_ / "t0.png", 100.0);
  other.join();
  EXPECT_EQ(error, "");
  EXPECT_EQ(read_png(out_ / "t0.png").rgba, read_png(out_ / "t1.png").rgba);
}

TEST(DensityFigureModel, FloatPointsAreForDensitySeriesOnly) {
  const auto message = [](const Figure& f) {
    try {
      validate(f);
    } catch (const RenderError& e) {
      return std::string(e.what());
    }
    return std::string("valid");
  };
  Figure fig;
  Axes& a = fig.panels.emplace_back();
  a.series.push_back(Series::density({1, 2}, {3, 4}, "cloud"));
  EXPECT_EQ(message(fig), "valid");
  a.series[0].style = SeriesStyle::kPoints;
  EXPECT_EQ(message(fig),
            "figure.panels[0].series[0]: xf/yf (float points) are for SeriesStyle::kDensity only");
  a.series[0].style = SeriesStyle::kDensity;
  a.series[0].x = {1, 2};
  a.series[0].y = {3, 4};
  EXPECT_EQ(message(fig), "figure.panels[0].series[0]: both x/y and xf/yf are set: set one pair");
  a.series[0].x.clear();
  a.series[0].y.clear();
  a.series[0].yf.pop_back();
  EXPECT_EQ(message(fig), "figure.panels[0].series[0]: xf has 2 values, yf has 1: must be equal");
  a.series[0].yf.push_back(4);
  a.series[0].density_style.min_alpha = 0;
  EXPECT_EQ(message(fig),
            "figure.panels[0].series[0].density_style.min_alpha = 0: must be in (0, 1]");
  a.series[0].density_style.min_alpha = 0.2;
  fig.raster_dpi = 5;
  EXPECT_EQ(message(fig), "figure.raster_dpi = 5: must be in [10, 2400]");
}

TEST(DensityFigurePlan, RangesFromTheFloatPointsAndLegendSamplesFromTouchedCells) {
  Figure fig;
  Axes& a = fig.panels.emplace_back();
  std::vector<float> x, y;
  for (int i = 0; i <= 100000; ++i) {
    x.push_back(static_cast<float>(360.0 * i / 100000));
    y.push_back(static_cast<float>(20.0 * std::sin(i * 2 * M_PI / 100000)));
  }
  a.series.push_back(Series::density(x, y, "every revolution"));
  const FigurePlan plan = plan_figure(fig);
  const PanelPlan& p = plan.panels[0];
  EXPECT_TRUE(plan.has_density);
  EXPECT_EQ(p.series[0].drawable, 100001u);
  // x spans the data exactly; y is padded by 5 % of its span (plot_layout.cpp).
  EXPECT_DOUBLE_EQ(p.x.min, 0.0);
  EXPECT_DOUBLE_EQ(p.x.max, 360.0);
  EXPECT_NEAR(p.y.min, -22.0, 1e-5);
  EXPECT_NEAR(p.y.max, 22.0, 1e-5);
  // The legend counts touched cells of the 100 x 100 grid, not 100 001 points: a sine
  // crosses each of the 100 columns through a few cells.
  EXPECT_GE(p.series[0].data.x.size(), 100u);
  EXPECT_LE(p.series[0].data.x.size(), 1000u);
}

}  // namespace
}  // namespace chatterlab::render
