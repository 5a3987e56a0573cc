// The screen, print and single-file pages made from one rendered report (app/report/html_pages.h).
#include "app/report/html_pages.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::TempDir;

// One figure as the templates draw it, inside a closed family, and one figure with its own id.
constexpr const char* kPage =
    "<head><link rel=\"stylesheet\" href=\"report.css\"></head>\n"
    "<details class=\"family\">\n<summary>2 figures</summary>\n"
    "<figure class=\"fig\">\n"
    "  <img class=\"screen-only\" src=\"figures/a/b.svg\" alt=\"A\"><img class=\"print-only\" "
    "src=\"figures/a/b.png\" alt=\"A\">\n"
    "  <figcaption>a/b: caption.</figcaption>\n</figure>\n</details>\n"
    "<figure class=\"fig\" id=\"own\"><img class=\"screen-only\" src=\"figures/c.svg\" alt=\"C\">"
    "<img class=\"print-only\" src=\"figures/c.png\" alt=\"C\"><figcaption>c.</figcaption></figure>"
    "<img src=\"logo.png\" alt=\"kept\">";

void write(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

TEST(HtmlPages, ScreenPageLoadsOnlyTheSvgsLazilyAndLabelsFigures) {
  TempDir d;
  write(d.path() / "figures/a/b.csv", "x,y\n");  // c has no data file
  const std::string s = screen_page(kPage, d.path());
  EXPECT_EQ(s.find(".png\" alt=\"A\""), std::string::npos);
  EXPECT_EQ(s.find("figures/c.png"), std::string::npos);
  EXPECT_NE(
      s.find("<img loading=\"lazy\" class=\"screen-only\" src=\"figures/a/b.svg\" alt=\"A\">"),
      std::string::npos);
  EXPECT_NE(s.find("<img src=\"logo.png\" alt=\"kept\">"), std::string::npos);  // not a figure pair
  // "a/b" -> "fig-a-b"; the data link only where the CSV exists; an id already set is kept.
  EXPECT_NE(s.find("<figure class=\"fig\" id=\"fig-a-b\">"), std::string::npos);
  EXPECT_NE(s.find("a/b: caption. <a class=\"fig-data\" href=\"figures/a/b.csv\">Data (CSV)</a> "
                   "<a class=\"fig-link\" href=\"#fig-a-b\""),
            std::string::npos);
  EXPECT_NE(s.find("<figure class=\"fig\" id=\"own\">"), std::string::npos);
  EXPECT_EQ(s.find("figures/c.csv"), std::string::npos);
  EXPECT_NE(s.find("<details class=\"family\">"), std::string::npos);  // closed on screen
}

TEST(HtmlPages, PrintPageKeepsThePngsAndOpensFamilies) {
  const std::string p = print_page(kPage);
  EXPECT_EQ(p.find(".svg"), std::string::npos);
  EXPECT_NE(p.find("<img class=\"print-only\" src=\"figures/a/b.png\" alt=\"A\">"),
            std::string::npos);
  EXPECT_NE(p.find("<details open class=\"family\">"), std::string::npos);
  EXPECT_EQ(print_page("<details open><details>").find("<details open><details open>"), 0u);
  EXPECT_NE(p.find("<figure class=\"fig\" id=\"fig-a-b\">"), std::string::npos);
  EXPECT_EQ(p.find("fig-data"), std::string::npos);  // no links to local files in the PDF
}

TEST(HtmlPages, DuplicateStemsGetUniqueIds) {
  const std::string fig =
      "<figure class=\"fig\"><img class=\"print-only\" src=\"figures/x.png\" alt=\"\">"
      "<figcaption>x</figcaption></figure>";
  const std::string p = print_page(fig + fig);
  EXPECT_NE(p.find("id=\"fig-x\""), std::string::npos);
  EXPECT_NE(p.find("id=\"fig-x-2\""), std::string::npos);
}

TEST(HtmlPages, SingleFilePageEmbedsStylesheetAndFigures) {
  TempDir d;
  write(d.path() / "report.css", "body { color: red; }\n");
  write(d.path() / "figures/a/b.svg", "<svg/>");
  write(d.path() / "figures/c.svg", "ab");
  const std::string one = single_file_page(screen_page(kPage, d.path()), d.path());
  EXPECT_NE(one.find("<style>\nbody { color: red; }\n</style>"), std::string::npos);
  EXPECT_EQ(one.find("report.css"), std::string::npos);
  EXPECT_NE(one.find("src=\"data:image/svg+xml;base64,PHN2Zy8+\""), std::string::npos);
  EXPECT_NE(one.find("src=\"data:image/svg+xml;base64,YWI=\""), std::string::npos);
  EXPECT_EQ(one.find("loading=\"lazy\""), std::string::npos);
  EXPECT_NE(one.find("<img src=\"logo.png\" alt=\"kept\">"), std::string::npos);
}

TEST(HtmlPages, SingleFilePageNamesAMissingFigure) {
  TempDir d;
  write(d.path() / "report.css", "");
  try {
    single_file_page(screen_page(kPage, d.path()), d.path());
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("b.svg"), std::string::npos) << e.what();
  }
}

TEST(HtmlPages, Base64MatchesRfc4648Vectors) {
  // RFC 4648 section 10.
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foob"), "Zm9vYg==");
  EXPECT_EQ(base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64(std::string("\xff\x00\x80", 3)), "/wCA");
}

TEST(HtmlPages, TestAnchorsAreSafeFragments) {
  EXPECT_EQ(test_anchor("cuts/constant-1mm"), "test-cuts-constant-1mm");
  EXPECT_EQ(test_anchor("a b.c_d"), "test-a-b-c_d");
  EXPECT_EQ(test_anchor(""), "test--");
}

}  // namespace
}  // namespace chatterlab::app
