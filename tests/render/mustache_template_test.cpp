#include "render/mustache_template.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "render/render_error.h"
#include "render/temp_dir.h"

namespace chatterlab::render {
namespace {

using nlohmann::json;

TEST(RenderTemplate, NestedObjectsListsBooleansAndNumbers) {
  const json context = {
      {"campaign", {{"name", "demo"}, {"tests", 5}}},
      {"modes", json::array({{{"axis", "x"}, {"fn_hz", 801.25}, {"ok", true}},
                             {{"axis", "y"}, {"fn_hz", 2304.0}, {"ok", false}}})},
      {"warnings", json::array()},
      {"skipped", nullptr},
  };
  const std::string text =
      "{{campaign.name}} ({{campaign.tests}} tests)\n"
      "{{#modes}}{{axis}}={{fn_hz}}{{#ok}} ok{{/ok}}{{^ok}} failed{{/ok}};{{/modes}}\n"
      "{{#warnings}}never{{/warnings}}{{^warnings}}no warnings{{/warnings}}\n"
      "{{^skipped}}nothing skipped{{/skipped}}[{{skipped}}]";
  EXPECT_EQ(render_template(text, context),
            "demo (5 tests)\n"
            "x=801.25 ok;y=2304 failed;\n"
            "no warnings\n"
            "nothing skipped[]");
}

TEST(RenderTemplate, EscapesHtmlUnlessTripleMustache) {
  const json context = {{"label", "a < b & \"c\""}};
  EXPECT_EQ(render_template("{{label}}|{{{label}}}", context),
            "a &lt; b &amp; &quot;c&quot;|a < b & \"c\"");
}

TEST(RenderTemplate, ListOfScalarsUsesDot) {
  EXPECT_EQ(render_template("{{#xs}}[{{.}}]{{/xs}}", json{{"xs", {1, 2.5, "three"}}}),
            "[1][2.5][three]");
}

TEST(FormatNumber, ReadableForms) {
  EXPECT_EQ(format_number(3.0), "3");
  EXPECT_EQ(format_number(-0.0), "0");
  EXPECT_EQ(format_number(0.1 + 0.2), "0.3");
  EXPECT_EQ(format_number(1234567.8), "1.23457e+06");
  EXPECT_EQ(format_number(12000.0), "12000");
  EXPECT_EQ(format_number(2.5e-7), "2.5e-07");
  EXPECT_EQ(format_number(std::numeric_limits<double>::quiet_NaN()), "NaN");
  EXPECT_EQ(format_number(-std::numeric_limits<double>::infinity()), "-inf");
}

TEST(RenderTemplate, PartialsFromMapSeeTheCurrentContext) {
  const Partials partials{{"row", "<tr><td>{{axis}}</td></tr>"}};
  const json context = {{"modes", {{{"axis", "x"}}, {{"axis", "y"}}}}};
  EXPECT_EQ(render_template("{{#modes}}{{> row}}{{/modes}}", context, partials),
            "<tr><td>x</td></tr><tr><td>y</td></tr>");
}

TEST(RenderTemplate, MissingPartialThrows) {
  try {
    render_template("a {{> nowhere}} b", json::object());
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_STREQ(e.what(), "template partial 'nowhere' not found");
  }
}

TEST(RenderTemplate, SyntaxErrorThrowsWithKainjowMessage) {
  try {
    render_template("{{#open}}never closed", json::object());
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_STREQ(e.what(), "template error: Unclosed section \"open\" at 0");
  }
  EXPECT_THROW(render_template("{{#a}}x{{/b}}", json::object()), RenderError);
}

TEST(RenderTemplateFile, ReadsFileAndPartialsBesideIt) {
  const TempDir dir;
  std::ofstream(dir.path() / "report.html") << "<h1>{{title}}</h1>{{> footer}}";
  std::ofstream(dir.path() / "footer.mustache") << "<footer>{{version}}</footer>";
  EXPECT_EQ(render_template_file(dir.path() / "report.html",
                                 json{{"title", "Demo"}, {"version", "0.1.0"}}),
            "<h1>Demo</h1><footer>0.1.0</footer>");
}

TEST(RenderTemplateFile, ErrorsNameTheFile) {
  const TempDir dir;
  const auto missing = dir.path() / "missing.html";
  try {
    render_template_file(missing, json::object());
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_EQ(std::string(e.what()), "cannot read " + missing.string());
  }
  const auto bad = dir.path() / "bad.html";
  std::ofstream(bad) << "{{> absent}}";
  try {
    render_template_file(bad, json::object());
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_EQ(std::string(e.what()), bad.string() +
                                         ": template partial 'absent' not found (looked in " +
                                         dir.path().string() + ")");
  }
}

}  // namespace
}  // namespace chatterlab::render
