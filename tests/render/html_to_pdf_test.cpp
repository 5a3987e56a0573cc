// WeasyPrint with templates/report.css: page numbers, table of contents, numbered figures
// and tables, print figures. Each test converts a small document (~1-2 s).
#include "render/html_to_pdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

#include "render/gnuplot_backend.h"
#include "render/mustache_template.h"
#include "render/render_error.h"
#include "render/subprocess.h"
#include "render/temp_dir.h"

namespace chatterlab::render {
namespace {

const std::filesystem::path kReportCss =
    std::filesystem::path(CHATTERLAB_SOURCE_DIR) / "templates" / "report.css";

// The PDF's text, one string per page (pdftotext separates pages with form feeds).
std::vector<std::string> pdf_pages(const std::filesystem::path& pdf) {
  const ProcessResult r = run_process({"pdftotext", "-layout", pdf.string(), "-"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> pages;
  std::istringstream in(r.out);
  for (std::string page; std::getline(in, page, '\f');) pages.push_back(page);
  if (!pages.empty() && pages.back().find_first_not_of(" \n") == std::string::npos) {
    pages.pop_back();
  }
  return pages;
}

// 1-based page holding `text`, 0 when absent.
std::size_t page_of(const std::vector<std::string>& pages, const std::string& text) {
  for (std::size_t i = 0; i < pages.size(); ++i) {
    if (pages[i].find(text) != std::string::npos) return i + 1;
  }
  return 0;
}

Figure sine_figure(const std::string& title, double frequency_hz) {
  Figure fig;
  fig.height_in = 3.0;
  Axes& a = fig.panels.emplace_back();
  a.title = title;
  a.x_label = "time [s]";
  a.y_label = "deflection [um]";
  std::vector<double> t, y, fit;
  for (int i = 0; i <= 400; ++i) {
    t.push_back(i * 1e-3);
    y.push_back(std::sin(2 * M_PI * frequency_hz * t.back()) + 0.1 * std::sin(i * 1.7));
    fit.push_back(std::sin(2 * M_PI * frequency_hz * t.back()));
  }
  a.series.push_back({t, y, "measured"});
  a.series.push_back({t, fit, "simulated", SeriesStyle::kDashedLine});
  return fig;
}

// The page skeleton of a report: report.css, a title page, a table of contents.
const char* const kDocument = R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{{title}}</title>
<link rel="stylesheet" href="report.css"></head>
<body>
<section class="title-page">
  <h1>{{title}}</h1>
  <p class="subtitle">Machining-dynamics report</p>
  <dl class="meta">{{#meta}}<dt>{{key}}</dt><dd>{{value}}</dd>{{/meta}}</dl>
</section>
<nav class="toc"><h2>Contents</h2><ol>
{{#sections}}<li><a href="#{{id}}">{{heading}}</a></li>
{{/sections}}</ol></nav>
{{#sections}}<section id="{{id}}"{{#new_page}} class="chapter"{{/new_page}}>
<h2>{{heading}}</h2>
{{#skipped}}<div class="skipped">{{skipped}}</div>{{/skipped}}
{{#figures}}<figure class="fig">
  <img class="screen-only" src="{{stem}}.svg" alt="{{caption}}">
  <img class="print-only" src="{{stem}}.png" alt="{{caption}}">
  <figcaption>{{caption}}</figcaption></figure>
{{/figures}}
{{#table}}<table class="data"><caption>{{caption}}</caption>
<thead><tr><th>axis</th><th class="num">f<sub>n</sub> [Hz]</th><th class="num">&#950; [%]</th></tr></thead>
<tbody>{{#rows}}<tr><td>{{axis}}</td><td class="num">{{fn}}</td><td class="num">{{zeta}}</td></tr>{{/rows}}</tbody>
</table>{{/table}}
</section>
{{/sections}}
</body></html>
)";

class HtmlToPdfTest : public ::testing::Test {
 protected:
  void SetUp() override { std::filesystem::copy_file(kReportCss, dir_.path() / "report.css"); }
  std::filesystem::path write_html(const nlohmann::json& context) {
    const auto html = dir_.path() / "index.html";
    std::ofstream(html) << render_template(kDocument, context);
    return html;
  }
  TempDir dir_{"chatterlab-pdf-test-"};
};

TEST_F(HtmlToPdfTest, TitlePageContentsFigureAndTable) {
  render_report_figure(sine_figure("deflection of cut_01", 10), dir_.path() / "fig1");
  const nlohmann::json context = {
      {"title", "Campaign demo"},
      {"meta", {{{"key", "version"}, {"value", "0.1.0"}}}},
      {"sections",
       {{{"id", "results"},
         {"heading", "Results"},
         {"figures", {{{"stem", "fig1"}, {"caption", "Deflection of cut_01."}}}},
         {"table",
          {{"caption", "Modes of the tool."},
           {"rows", {{{"axis", "x"}, {"fn", "801.2"}, {"zeta", "3.01"}}}}}}}}},
  };
  const auto pdf = dir_.path() / "report.pdf";
  const std::vector<std::string> warnings = html_to_pdf(write_html(context), pdf);
  EXPECT_TRUE(warnings.empty()) << "report.css uses only what WeasyPrint 57 supports: "
                                << warnings.front();

  const std::vector<std::string> pages = pdf_pages(pdf);
  ASSERT_EQ(pages.size(), 3u);  // title page, contents, results
  EXPECT_EQ(page_of(pages, "Campaign demo"), 1u);
  EXPECT_EQ(pages[0].find("page 1 of"), std::string::npos) << "no number on the title page";
  EXPECT_NE(pages[1].find("page 2 of 3"), std::string::npos) << pages[1];
  EXPECT_NE(pages[2].find("page 3 of 3"), std::string::npos);
  EXPECT_TRUE(std::regex_search(pages[1], std::regex("Results \\.{5,} *3"))) << pages[1];
  EXPECT_NE(pages[2].find("Figure 1. Deflection of cut_01."), std::string::npos) << pages[2];
  EXPECT_NE(pages[2].find("Table 1. Modes of the tool."), std::string::npos) << pages[2];
  EXPECT_NE(pages[2].find("801.2"), std::string::npos);
}

// The sample report of docs/rendering.md: two sections, two figures, a table, a skipped
// test. Set CHATTERLAB_RENDER_DEMO_DIR to keep its HTML, figures and PDF for viewing
// (pdftoppm -png -r 60 report.pdf page).
TEST_F(HtmlToPdfTest, DemoReportNumbersAndContentsAgree) {
  render_report_figure(sine_figure("deflection of cut_01", 10), dir_.path() / "fig1");
  render_report_figure(sine_figure("deflection of cut_02", 25), dir_.path() / "fig2");
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 12; ++i) {
    rows.push_back({{"axis", "mode " + std::to_string(i + 1)},
                    {"fn", format_number(800.0 + 150.0 * i)},
                    {"zeta", format_number(2.0 + 0.25 * i)}});
  }
  const nlohmann::json context = {
      {"title", "Campaign demo_2024 \"spindle A\""},
      {"meta",
       {{{"key", "campaign"}, {"value", "experiments/demo"}},
        {{"key", "generated"}, {"value", "2024-05-01 12:00"}},
        {{"key", "chatterlab"}, {"value", "0.1.0"}}}},
      {"sections",
       {{{"id", "summary"},
         {"heading", "Campaign summary"},
         {"skipped", "cut_07: no tachometer edges in tach.csv (key channels.tach)."},
         {"table", {{"caption", "Modes identified from the tap tests."}, {"rows", rows}}}},
        {{"id", "cuts"},
         {"heading", "Cut tests"},
         {"new_page", true},
         {"figures",
          {{{"stem", "fig1"}, {"caption", "Deflection of cut_01, measured and simulated."}},
           {{"stem", "fig2"}, {"caption", "Deflection of cut_02, measured and simulated."}}}}}}},
  };
  const auto html = write_html(context);
  const auto pdf = dir_.path() / "report.pdf";
  EXPECT_TRUE(html_to_pdf(html, pdf).empty());

  const std::vector<std::string> pages = pdf_pages(pdf);
  ASSERT_GE(pages.size(), 4u);
  for (std::size_t p = 2; p <= pages.size(); ++p) {
    EXPECT_NE(
        pages[p - 1].find("page " + std::to_string(p) + " of " + std::to_string(pages.size())),
        std::string::npos)
        << "page " << p;
  }
  // Every contents entry points at the page where its heading is (searched after the
  // contents page, where the heading text also appears).
  for (const char* heading : {"Campaign summary", "Cut tests"}) {
    std::size_t actual = 0;
    for (std::size_t p = 3; p <= pages.size() && actual == 0; ++p) {
      if (pages[p - 1].find(heading) != std::string::npos) actual = p;
    }
    const std::regex entry(std::string(heading) + " \\.{5,} *([0-9]+)");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(pages[1], m, entry)) << pages[1];
    EXPECT_EQ(std::stoul(m[1]), actual) << heading;
  }
  EXPECT_GT(page_of(pages, "Figure 2. Deflection of cut_02"), page_of(pages, "Table 1."));
  EXPECT_NE(page_of(pages, "Skipped: cut_07"), 0u);
  // The print figures are the PNGs: two images of 6.3 in at 200 dpi, no SVG drawn.
  const ProcessResult images = run_process({"pdfimages", "-list", pdf.string()});
  ASSERT_EQ(images.exit_code, 0) << images.err;
  const std::regex image_row("\\n +[0-9]+ +[0-9]+ image +1260 +600 ");
  EXPECT_EQ(std::distance(std::sregex_iterator(images.out.begin(), images.out.end(), image_row),
                          std::sregex_iterator()),
            2)
      << images.out;

  if (const char* keep = std::getenv("CHATTERLAB_RENDER_DEMO_DIR")) {
    std::filesystem::create_directories(keep);
    for (const auto& e : std::filesystem::directory_iterator(dir_.path())) {
      std::filesystem::copy_file(e.path(), std::filesystem::path(keep) / e.path().filename(),
                                 std::filesystem::copy_options::overwrite_existing);
    }
  }
}

TEST_F(HtmlToPdfTest, MissingImageIsAWarning) {
  const auto html = dir_.path() / "broken.html";
  std::ofstream(html) << "<html><body><p>text</p><img src=\"missing_figure.png\"></body></html>";
  const std::vector<std::string> warnings = html_to_pdf(html, dir_.path() / "broken.pdf");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("missing_figure.png"), std::string::npos) << warnings[0];
  EXPECT_TRUE(std::filesystem::exists(dir_.path() / "broken.pdf"));
}

// WeasyPrint 57 cannot draw gnuplot's SVG point markers; the error says what to do.
TEST_F(HtmlToPdfTest, GnuplotSvgWithPointsInPrintFailsWithAHint) {
  Figure fig;
  fig.panels.emplace_back().series.push_back(
      Series{{1, 2, 3}, {1, 4, 9}, "points", SeriesStyle::kPoints});
  render_svg(fig, dir_.path() / "points.svg");
  const auto html = dir_.path() / "points.html";
  std::ofstream(html) << "<p>x</p><img src=\"points.svg\">";
  try {
    html_to_pdf(html, dir_.path() / "points.pdf");
    FAIL() << "WeasyPrint drew the SVG: the PNG detour in docs/rendering.md may be obsolete";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("give print a PNG figure"), std::string::npos) << e.what();
  }
}

TEST_F(HtmlToPdfTest, MissingHtmlThrowsNamingIt) {
  const auto html = dir_.path() / "nothing.html";
  try {
    html_to_pdf(html, dir_.path() / "nothing.pdf");
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_EQ(std::string(e.what()),
              "html_to_pdf: " + html.string() + " does not exist or is not a file");
  }
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "nothing.pdf"));
}

TEST_F(HtmlToPdfTest, MissingWeasyprintThrowsNamingTheFile) {
  const auto html = dir_.path() / "small.html";
  std::ofstream(html) << "<p>x</p>";
  PdfOptions options;
  options.weasyprint = "/nonexistent/weasyprint";
  try {
    html_to_pdf(html, dir_.path() / "small.pdf", options);
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("html_to_pdf " + html.string() + ": cannot run", 0), 0u) << what;
  }
}

TEST_F(HtmlToPdfTest, WeasyprintFailureCarriesItsStderr) {
  // Not HTML at all is still parsed by WeasyPrint; an unwritable output makes it fail.
  const auto html = dir_.path() / "small.html";
  std::ofstream(html) << "<p>x</p>";
  try {
    html_to_pdf(html, dir_.path() / "no_such_folder" / "small.pdf");
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("weasyprint failed on " + html.string(), 0), 0u) << what;
    EXPECT_NE(what.find("No such file or directory"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace chatterlab::render
