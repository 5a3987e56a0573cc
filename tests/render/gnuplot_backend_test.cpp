// The gnuplot backend end to end: real gnuplot runs on small figures (each well under 1 s).
#include "render/gnuplot_backend.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <regex>

#include "render/mustache_template.h"
#include "render/render_error.h"
#include "render/subprocess.h"
#include "render/temp_dir.h"
#include "tests/support/scratch_tmpdir.h"

namespace chatterlab::render {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string slurp(const std::filesystem::path& p) { return read_text_file(p); }

// FRF-like figure: magnitude on log-log axes with a NaN gap, coherence below, sharing x.
Figure two_panel_figure() {
  Figure fig;
  fig.share_x = true;
  std::vector<double> f, mag, coh;
  for (int i = 0; i < 41; ++i) {
    f.push_back(10.0 * std::pow(10.0, i / 20.0));  // 10 Hz .. 1 kHz
    mag.push_back(i == 20 ? kNaN : 1e-6 / (1.0 + std::pow(f.back() / 300.0, 2)));
    coh.push_back(0.9);
  }
  Axes& top = fig.panels.emplace_back();
  top.title = "FRF of tap_x";
  top.y_label = "|H| [m/N]";
  top.log_x = top.log_y = true;
  top.relative_height = 2.0;
  top.series.push_back({f, mag, "it's \"H1\" a_b^c @x $1 50%", SeriesStyle::kLine, "#123456"});
  Axes& bottom = fig.panels.emplace_back();
  bottom.x_label = "frequency [Hz]";
  bottom.y_label = "coherence [-]";
  bottom.log_x = true;
  bottom.y_range = Range{0.0, 1.0};
  bottom.series.push_back({f, coh, "coherence", SeriesStyle::kLinePoints});
  return fig;
}

// A scratch folder that is also TMPDIR, so the backend's own temp folders land in it and
// the test can see that they are removed.
class GnuplotBackendTest : public chatterlab::testing::ScratchTmpdirTest {
 protected:
  GnuplotBackendTest() : ScratchTmpdirTest("chatterlab-backend-test-") {}
  // Entries of the scratch folder other than out/: leftovers of the backend.
  std::size_t leftovers() const {
    std::size_t n = 0;
    for (const auto& e : std::filesystem::directory_iterator(scratch_.path())) {
      n += e.path() != out_;
    }
    return n;
  }
};

TEST_F(GnuplotBackendTest, WritesSvgWithLabelsLegendAndGap) {
  const auto svg_path = out_ / "frf.svg";
  render_svg(two_panel_figure(), svg_path);
  ASSERT_TRUE(std::filesystem::exists(svg_path));
  const std::string svg = slurp(svg_path);
  EXPECT_TRUE(svg.rfind("<?xml", 0) == 0 || svg.rfind("<svg", 0) == 0) << svg.substr(0, 80);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  // 96 user units per inch: the default 6.3 in x 3.6 in figure.
  EXPECT_NE(svg.find("width=\"605\" height=\"346\""), std::string::npos);
  EXPECT_NE(svg.find("FRF of tap_x"), std::string::npos);
  EXPECT_NE(svg.find("frequency [Hz]"), std::string::npos);
  EXPECT_NE(svg.find("coherence [-]"), std::string::npos);
  EXPECT_NE(svg.find("|H| [m/N]"), std::string::npos);
  // The legend text drawn literally: no enhanced-text markup, no macro or format expansion.
  EXPECT_NE(svg.find("it's \"H1\" a_b^c @x $1 50%"), std::string::npos);
  EXPECT_NE(svg.find("font-family=\"DejaVu Sans\""), std::string::npos);
  // The #123456 series: one data path that starts twice (M), once on each side of the NaN,
  // and the legend's sample line.
  const std::regex path_re("stroke='rgb\\( 18,  52,  86\\)'\\s+d='([^']*)'");
  std::size_t moves = 0, paths = 0;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), path_re);
       it != std::sregex_iterator(); ++it) {
    ++paths;
    const std::string d = (*it)[1];
    moves += static_cast<std::size_t>(std::count(d.begin(), d.end(), 'M'));
  }
  EXPECT_EQ(paths, 2u) << "data path and legend sample";
  EXPECT_EQ(moves, 3u) << "two data runs around the NaN, one legend sample";
  EXPECT_EQ(leftovers(), 0u) << "the temporary data and script folder is removed";
}

TEST_F(GnuplotBackendTest, ReportFigureWritesSvgAndPrintPng) {
  const ReportFigure files = render_report_figure(two_panel_figure(), out_ / "frf", 200.0);
  EXPECT_EQ(files.svg, out_ / "frf.svg");
  EXPECT_EQ(files.png, out_ / "frf.png");
  const std::string png = slurp(files.png);
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  // IHDR width and height, big-endian: 6.3 in and 3.6 in at 200 dpi.
  const auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned>(static_cast<unsigned char>(png[at])) << 24) |
           (static_cast<unsigned>(static_cast<unsigned char>(png[at + 1])) << 16) |
           (static_cast<unsigned>(static_cast<unsigned char>(png[at + 2])) << 8) |
           static_cast<unsigned>(static_cast<unsigned char>(png[at + 3]));
  };
  EXPECT_EQ(be32(16), 1260u);
  EXPECT_EQ(be32(20), 720u);
  EXPECT_NE(slurp(files.svg).find("frequency [Hz]"), std::string::npos);
  EXPECT_EQ(leftovers(), 0u);
}

TEST_F(GnuplotBackendTest, PdfFigureCarriesItsTextAtTheFigureFontSize) {
  const auto pdf = out_ / "frf.pdf";
  render_pdf(two_panel_figure(), pdf);
  EXPECT_EQ(slurp(pdf).substr(0, 5), "%PDF-");
  const ProcessResult text = run_process({"pdftotext", "-bbox", pdf.string(), "-"});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  // pdftotext's word box for 9 pt DejaVu Sans is 9 * 1.163 = 10.47 pt high (ascent plus
  // descent of the font); 0.1 pt allows for rounding in the PDF.
  const std::regex word_re(
      "yMin=\"([0-9.]+)\" xMax=\"[0-9.]+\" yMax=\"([0-9.]+)\">frequency</word>");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text.out, m, word_re)) << text.out;
  EXPECT_NEAR(std::stod(m[2]) - std::stod(m[1]), 9.0 * 1.163, 0.1);
}

TEST_F(GnuplotBackendTest, ManyPointsStaySmallAndFast) {
  Figure fig;
  Axes& axes = fig.panels.emplace_back();
  axes.x_label = "time [s]";
  axes.y_label = "deflection [um]";
  std::vector<double> t(1000000), y(1000000);
  for (std::size_t i = 0; i < t.size(); ++i) {
    t[i] = static_cast<double>(i) * 1e-5;
    y[i] = std::sin(2 * M_PI * 50 * t[i]) + (i % 7 == 0 ? 0.2 : 0.0);
  }
  axes.series.push_back({t, y, "measured"});
  render_svg(fig, out_ / "long.svg");
  // Envelope reduction to 2000 bins keeps at most 4 points a bin: ~8000 points, far from
  // the ~15 MB a million-point path would take.
  EXPECT_LT(std::filesystem::file_size(out_ / "long.svg"), 1'000'000u);
}

TEST_F(GnuplotBackendTest, PanelWithoutDataSaysSo) {
  Figure fig;
  Axes& axes = fig.panels.emplace_back();
  axes.series.push_back({{1.0, 2.0}, {kNaN, kNaN}, "estimator A"});
  axes.series.push_back({{}, {}, "estimator B"});
  render_svg(fig, out_ / "empty.svg");
  const std::string svg = slurp(out_ / "empty.svg");
  EXPECT_NE(svg.find("no data"), std::string::npos);
  EXPECT_NE(svg.find("estimator A (no data)"), std::string::npos);
  EXPECT_NE(svg.find("estimator B (no data)"), std::string::npos);
}

TEST_F(GnuplotBackendTest, InvalidFigureNamesTheField) {
  Figure fig = two_panel_figure();
  fig.panels[1].series[0].y.pop_back();
  try {
    render_svg(fig, out_ / "bad.svg");
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_STREQ(e.what(), "figure.panels[1].series[0]: x has 41 values, y has 40: must be equal");
  }
  EXPECT_FALSE(std::filesystem::exists(out_ / "bad.svg"));
}

TEST_F(GnuplotBackendTest, GnuplotErrorIsThrownWithItsMessage) {
  const auto script = out_ / "broken.gp";
  std::ofstream(script) << "set terminal svg\nset output '/dev/null'\nplot no_such_function(x)\n";
  try {
    run_gnuplot(script);
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("gnuplot failed on " + script.string()), std::string::npos) << what;
    EXPECT_NE(what.find("undefined function: no_such_function"), std::string::npos) << what;
  }
}

TEST_F(GnuplotBackendTest, MissingGnuplotIsThrown) {
  const auto script = out_ / "ok.gp";
  std::ofstream(script) << "print 1\n";
  EXPECT_THROW(run_gnuplot(script, "/nonexistent/gnuplot"), RenderError);
  try {
    run_gnuplot(script, "/nonexistent/gnuplot");
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot run '/nonexistent/gnuplot"), std::string::npos);
  }
}

TEST_F(GnuplotBackendTest, UnwritableDestinationNamesTheFile) {
  const auto target = out_ / "no_such_folder" / "fig.svg";
  try {
    render_svg(two_panel_figure(), target);
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write figure " + target.string()),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(leftovers(), 0u);
}

}  // namespace
}  // namespace chatterlab::render

namespace chatterlab::render {
namespace {

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + 1)) ++n;
  return n;
}

// Shared x over less than a decade on a log axis: the tics are an explicit list, whose labels
// `set format` does not hide; only the bottom panel may carry them.
TEST_F(GnuplotBackendTest, SharedLogXWithinADecadeLabelsOnlyTheBottomPanel) {
  Figure fig;
  fig.share_x = true;
  std::vector<double> f, y;
  for (int i = 0; i <= 50; ++i) {
    f.push_back(300.0 * std::pow(10.0, i / 50.0 * 0.9));  // 300 Hz .. 2.4 kHz
    y.push_back(1.0 + i);
  }
  for (int p = 0; p < 3; ++p) {
    Axes& a = fig.panels.emplace_back();
    a.log_x = true;
    a.y_label = "y" + std::to_string(p) + " [-]";
    a.series.push_back({f, y, ""});
  }
  fig.panels.back().x_label = "frequency [Hz]";
  const auto svg = out_ / "shared.svg";
  render_svg(fig, svg);
  EXPECT_EQ(count_of(slurp(svg), ">1000<"), 1u);
}

}  // namespace
}  // namespace chatterlab::render
