// PDF/A-3b with results.json attached: each requirement of ISO 19005-3 that Debian's tools
// can check (docs/rendering.md, "PDF/A-3b"), read back with qpdf and poppler. There is no
// full PDF/A validator (veraPDF) in Debian: these checks are the validator.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "render/html_to_pdf.h"
#include "render/mustache_template.h"
#include "render/render_error.h"
#include "render/rgba_image.h"
#include "render/subprocess.h"
#include "render/temp_dir.h"

namespace chatterlab::render {
namespace {

using nlohmann::json;

const std::filesystem::path kTemplates = std::filesystem::path(CHATTERLAB_SOURCE_DIR) / "templates";

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The PDF's objects as qpdf's JSON v2 ("obj:N 0 R" -> {"value": ...} or {"stream": {"dict":
// ...}}, and "trailer").
json pdf_objects(const std::filesystem::path& pdf) {
  const ProcessResult r =
      run_process({"qpdf", "--json=2", "--json-key=qpdf", "--json-stream-data=none", pdf.string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return json::parse(r.out).at("qpdf").at(1);
}

const json& deref(const json& objects, const json& ref) {
  return objects.at("obj:" + ref.get<std::string>());
}

// The decoded data of stream `ref` ("12 0 R").
std::string stream_data(const std::filesystem::path& pdf, const json& ref) {
  const std::string r = ref.get<std::string>();
  const ProcessResult p = run_process({"qpdf", "--show-object=" + r.substr(0, r.find(' ')),
                                       "--filtered-stream-data", pdf.string()});
  EXPECT_EQ(p.exit_code, 0) << p.err;
  return p.out;
}

// The text of XMP property `name` (an element, or an attribute as WeasyPrint writes pdfaid).
std::string xmp_value(const std::string& xmp, const std::string& name) {
  std::smatch m;
  if (std::regex_search(xmp, m, std::regex("<" + name + ">([^<]*)</" + name + ">"))) return m[1];
  if (std::regex_search(xmp, m, std::regex(name + "=\"([^\"]*)\""))) return m[1];
  // dc:title and dc:description hold an rdf:Alt, dc:creator an rdf:Seq of rdf:li.
  if (std::regex_search(xmp, m,
                        std::regex("<" + name +
                                   ">\\s*<rdf:(Alt|Seq|Bag)>\\s*<rdf:li[^>]*>([^<]*)"
                                   "</rdf:li>"))) {
    return m[2];
  }
  return "(absent)";
}

class HtmlToPdfPdfaTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::copy_file(kTemplates / "report.css", dir_.path() / "report.css");
    RgbaImage img;
    img.width = 120;
    img.height = 60;
    for (int r = 0; r < img.height; ++r) {
      for (int c = 0; c < img.width; ++c) {
        img.rgba.insert(img.rgba.end(), {static_cast<std::uint8_t>(2 * c),
                                         static_cast<std::uint8_t>(4 * r), 128, 255});
      }
    }
    write_png(img, dir_.path() / "figure.png");
    results_ = dir_.path() / "results.json";
    // Unicode and a trailing newline: the attachment must come back byte for byte.
    std::ofstream(results_, std::ios::binary)
        << "{\n  \"campaign\": \"Stahl \xC3\xBC 42\",\n  \"fn_Hz\": [801.25, 1203.5]\n}\n";
  }

  std::filesystem::path write_html(const std::string& head) {
    const auto html = dir_.path() / "index.html";
    std::ofstream(html) << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                        << head << "<link rel=\"stylesheet\" href=\"report.css\">\n</head>\n"
                        << "<body><h1>Campaign &amp; results</h1><p>Text with &#956;m.</p>"
                        << "<figure class=\"fig\"><img src=\"figure.png\" alt=\"f\">"
                        << "<figcaption>A PNG figure.</figcaption></figure></body></html>\n";
    return html;
  }

  PdfOptions pdfa_options() const {
    PdfOptions o;
    o.variant = "pdf/a-3b";
    PdfAttachment results;
    results.file = results_;
    results.description = "Results of the campaign, machine-readable";
    o.attachments.push_back(results);
    return o;
  }

  TempDir dir_{"chatterlab-pdfa-test-"};
  std::filesystem::path results_;
};

const char* const kHead =
    "<title>Spindle 3 &lt;run&gt;: chatterlab report</title>\n"
    "<meta name=\"author\" content=\"chatterlab 1.2.3\">\n"
    "<meta name=\"description\" content=\"Tap tests and slot cuts, Stahl \xC3\xBC\">\n"
    "<meta name=\"keywords\" content=\"chatterlab, machining dynamics\">\n"
    "<meta name=\"generator\" content=\"chatterlab 1.2.3\">\n"
    "<meta name=\"dcterms.created\" content=\"2026-12-02T01:29:00Z\">\n";

TEST_F(HtmlToPdfPdfaTest, Pdfa3bWithResultsJsonPassesEveryCheck) {
  const auto pdf = dir_.path() / "report.pdf";
  const std::vector<std::string> warnings = html_to_pdf(write_html(kHead), pdf, pdfa_options());
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "report.pdf.partial"));
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "report.pdf.finished.partial"));

  // Structure: PDF 1.7, no syntax or stream errors, not encrypted (ISO 19005-3 6.1).
  EXPECT_EQ(read_file(pdf).substr(0, 8), "%PDF-1.7");
  const ProcessResult check = run_process({"qpdf", "--check", pdf.string()});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  EXPECT_NE(check.out.find("File is not encrypted"), std::string::npos) << check.out;
  EXPECT_NE(check.out.find("No syntax or stream encoding errors found"), std::string::npos)
      << check.out;

  const json objects = pdf_objects(pdf);
  const json& trailer = objects.at("trailer").at("value");
  EXPECT_FALSE(trailer.contains("/Encrypt"));
  EXPECT_EQ(trailer.value("/ID", json::array()).size(), 2u)
      << "6.1.3: the trailer has a file identifier";
  const json& catalog = deref(objects, trailer.at("/Root")).at("value");
  const json& info = deref(objects, trailer.at("/Info")).at("value");

  // Output intent with an RGB ICC profile (6.2.3).
  ASSERT_TRUE(catalog.contains("/OutputIntents"));
  ASSERT_EQ(catalog["/OutputIntents"].size(), 1u);
  const json& intent = catalog["/OutputIntents"][0];
  EXPECT_EQ(intent.at("/S"), "/GTS_PDFA1");
  EXPECT_EQ(deref(objects, intent.at("/DestOutputProfile")).at("stream").at("dict").at("/N"), 3);
  const std::string icc = stream_data(pdf, intent.at("/DestOutputProfile"));
  ASSERT_GT(icc.size(), 128u);
  EXPECT_EQ(icc.substr(36, 4), "acsp") << "an ICC profile";
  EXPECT_EQ(icc.substr(16, 4), "RGB ");

  // Metadata: XMP, unfiltered, PDF/A-3B, the same title and description as Info (6.6).
  ASSERT_TRUE(catalog.contains("/Metadata"));
  const json& meta_dict = deref(objects, catalog["/Metadata"]).at("stream").at("dict");
  EXPECT_EQ(meta_dict.at("/Subtype"), "/XML");
  EXPECT_FALSE(meta_dict.contains("/Filter"));
  const std::string xmp = stream_data(pdf, catalog["/Metadata"]);
  EXPECT_EQ(xmp.rfind("<?xpacket begin=", 0), 0u) << xmp;
  EXPECT_EQ(xmp.find(" bytes="), std::string::npos);
  EXPECT_EQ(xmp.find(" encoding="), std::string::npos);
  EXPECT_EQ(xmp_value(xmp, "pdfaid:part"), "3") << xmp;
  EXPECT_EQ(xmp_value(xmp, "pdfaid:conformance"), "B") << xmp;
  EXPECT_EQ(info.at("/Title"), "u:Spindle 3 <run>: chatterlab report");
  EXPECT_EQ(xmp_value(xmp, "dc:title"), "Spindle 3 &lt;run&gt;: chatterlab report");
  EXPECT_EQ(info.at("/Subject"), "u:Tap tests and slot cuts, Stahl \xC3\xBC");
  EXPECT_EQ(xmp_value(xmp, "dc:description"), "Tap tests and slot cuts, Stahl \xC3\xBC") << xmp;
  EXPECT_EQ(info.at("/Author"), "u:chatterlab 1.2.3");
  EXPECT_EQ(xmp_value(xmp, "dc:creator"), "chatterlab 1.2.3");
  EXPECT_EQ(info.at("/Keywords"), "u:chatterlab, machining dynamics");
  EXPECT_EQ(xmp_value(xmp, "pdf:Keywords"), "chatterlab, machining dynamics");
  EXPECT_EQ(info.at("/Creator"), "u:chatterlab 1.2.3");
  EXPECT_EQ(xmp_value(xmp, "xmp:CreatorTool"), "chatterlab 1.2.3");
  EXPECT_EQ(info.at("/Producer"), "u:WeasyPrint 57.2");
  EXPECT_EQ(xmp_value(xmp, "pdf:Producer"), "WeasyPrint 57.2");
  EXPECT_EQ(info.at("/CreationDate"), "u:D:20261202012900Z");
  EXPECT_EQ(xmp_value(xmp, "xmp:CreateDate"), "2026-12-02T01:29:00Z");
  const ProcessResult pdfinfo = run_process({"pdfinfo", pdf.string()});
  EXPECT_NE(pdfinfo.out.find("Title:           Spindle 3 <run>: chatterlab report\n"),
            std::string::npos)
      << pdfinfo.out;

  // Every font embedded (6.2.11.4): pdffonts' "emb" column, and a font file per descriptor.
  const ProcessResult fonts = run_process({"pdffonts", pdf.string()});
  ASSERT_EQ(fonts.exit_code, 0) << fonts.err;
  std::istringstream rows(fonts.out);
  std::string row;
  std::getline(rows, row);
  const std::size_t emb = row.find("emb");
  ASSERT_NE(emb, std::string::npos) << fonts.out;
  std::getline(rows, row);  // the rule
  int font_count = 0;
  for (; std::getline(rows, row); ++font_count) {
    EXPECT_EQ(row.substr(emb, 3), "yes") << row;
  }
  EXPECT_GE(font_count, 2) << fonts.out;  // bold heading and body text
  int descriptors = 0;
  for (const auto& [key, entry] : objects.items()) {
    if (!entry.contains("value") || !entry["value"].is_object()) continue;
    const json& v = entry["value"];
    if (v.value("/Type", "") != "/FontDescriptor") continue;
    ++descriptors;
    EXPECT_TRUE(v.contains("/FontFile") || v.contains("/FontFile2") || v.contains("/FontFile3"))
        << key;
  }
  EXPECT_EQ(descriptors, font_count);

  // The attachment (6.8): results.json, byte for byte, with MIME type, relationship and date,
  // associated with the document through the catalog's /AF.
  const ProcessResult list = run_process({"pdfdetach", "-list", pdf.string()});
  EXPECT_EQ(list.out, "1 embedded files\n1: results.json\n");
  const auto extracted = dir_.path() / "extracted.json";
  const ProcessResult save =
      run_process({"pdfdetach", "-save", "1", "-o", extracted.string(), pdf.string()});
  ASSERT_EQ(save.exit_code, 0) << save.err;
  EXPECT_EQ(read_file(extracted), read_file(results_));
  const json& files = deref(objects, catalog.at("/Names").at("/EmbeddedFiles")).at("value");
  ASSERT_EQ(files.at("/Names").size(), 2u);
  const json& spec_ref = files["/Names"][1];
  const json& spec = deref(objects, spec_ref).at("value");
  EXPECT_EQ(spec.at("/Type"), "/Filespec");
  EXPECT_EQ(spec.at("/F"), "u:results.json");
  EXPECT_EQ(spec.at("/UF"), "u:results.json");
  EXPECT_EQ(spec.at("/AFRelationship"), "/Data");
  EXPECT_EQ(spec.at("/Desc"), "u:Results of the campaign, machine-readable");
  ASSERT_TRUE(catalog.contains("/AF"));
  EXPECT_EQ(catalog["/AF"], json::array({spec_ref}));
  const json& file = deref(objects, spec.at("/EF").at("/F")).at("stream").at("dict");
  EXPECT_EQ(file.at("/Type"), "/EmbeddedFile");
  EXPECT_EQ(file.at("/Subtype"), "/application/json");  // qpdf shows #2F decoded
  EXPECT_EQ(file.at("/Params").at("/Size"), static_cast<int>(read_file(results_).size()));
  EXPECT_TRUE(std::regex_match(file.at("/Params").at("/ModDate").get<std::string>(),
                               std::regex("u:D:\\d{14}Z")))
      << file.dump();

  // The PNG figure is in the PDF (and no other image).
  const ProcessResult images = run_process({"pdfimages", "-list", pdf.string()});
  EXPECT_TRUE(std::regex_search(images.out, std::regex(" 120 +60 +rgb "))) << images.out;
}

// Without a variant or attachments the PDF is what it was before: no XMP, no output intent.
TEST_F(HtmlToPdfPdfaTest, PlainPdfHasNoPdfaParts) {
  const auto pdf = dir_.path() / "plain.pdf";
  EXPECT_TRUE(html_to_pdf(write_html(kHead), pdf).empty());
  const json objects = pdf_objects(pdf);
  const json& catalog = deref(objects, objects.at("trailer").at("value").at("/Root")).at("value");
  EXPECT_FALSE(catalog.contains("/Metadata"));
  EXPECT_FALSE(catalog.contains("/OutputIntents"));
  EXPECT_FALSE(catalog.contains("/AF"));
  EXPECT_EQ(run_process({"pdfdetach", "-list", pdf.string()}).out, "0 embedded files\n");
}

// The <head> of both templates gives the PDF its title, description, author and generator.
TEST_F(HtmlToPdfPdfaTest, TemplateHeadsCarryTheMetadata) {
  struct Case {
    const char* file;
    json context;
    const char* title;
    const char* subject;
  };
  const std::vector<Case> cases = {
      {"report.html",
       {{"campaign", {{"name", "lab_2026"}, {"description", "Spindle 3 tap tests"}}},
        {"version", "9.8.7"},
        {"generated_utc", "2026-12-02 01:29 UTC"},
        {"generated_iso", "2026-12-02T01:29:00Z"}},
       "lab_2026: chatterlab report",
       "Spindle 3 tap tests"},
      {"simulation.html",
       {{"name", "incline"},
        {"product", "simulation"},
        {"summary_line", "Bifurcation depth 2.31 mm"},
        {"version", "9.8.7"},
        {"generated_utc", "2026-12-02 01:29 UTC"},
        {"generated_iso", "2026-12-02T01:29:00Z"}},
       "incline: chatterlab simulation",
       "Bifurcation depth 2.31 mm"},
      {"lobes.html",
       {{"name", "slot"},
        {"product", "stability lobes"},
        {"summary_line", "Semi-discretization minimum 0.31 mm at 9000 rpm"},
        {"version", "9.8.7"},
        {"generated_utc", "2026-12-02 01:29 UTC"},
        {"generated_iso", "2026-12-02T01:29:00Z"}},
       "slot: chatterlab stability lobes",
       "Semi-discretization minimum 0.31 mm at 9000 rpm"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    // The spec documents (simulation, lobes) take their head from the shared partial.
    std::string text = read_file(kTemplates / c.file);
    if (text.find("{{> spec_title}}") != std::string::npos) {
      text = read_file(kTemplates / "spec_title.mustache");
    }
    const std::size_t begin = text.find("<head>"), end = text.find("</head>");
    ASSERT_NE(begin, std::string::npos);
    ASSERT_NE(end, std::string::npos);
    const auto html = dir_.path() / "index.html";
    std::ofstream(html) << "<!DOCTYPE html>\n<html lang=\"en\">\n"
                        << render_template(text.substr(begin, end + 7 - begin), c.context)
                        << "<body><p>x</p></body></html>\n";
    const auto pdf = dir_.path() / "t.pdf";
    PdfOptions options = pdfa_options();
    EXPECT_TRUE(html_to_pdf(html, pdf, options).empty());
    const json objects = pdf_objects(pdf);
    const json& trailer = objects.at("trailer").at("value");
    const json& info = deref(objects, trailer.at("/Info")).at("value");
    EXPECT_EQ(info.value("/Title", ""), std::string("u:") + c.title);
    EXPECT_EQ(info.value("/Subject", ""), std::string("u:") + c.subject);
    EXPECT_EQ(info.value("/Author", ""), "u:chatterlab 9.8.7");
    EXPECT_EQ(info.value("/Creator", ""), "u:chatterlab 9.8.7");
    // dcterms.created: the report's own time, not the conversion's.
    EXPECT_EQ(info.value("/CreationDate", "").rfind("u:D:202612020129", 0), 0u)
        << info.value("/CreationDate", "");
    EXPECT_NE(info.value("/Keywords", "").find("chatterlab"), std::string::npos);
    const json& catalog = deref(objects, trailer.at("/Root")).at("value");
    const std::string xmp = stream_data(pdf, catalog.at("/Metadata"));
    EXPECT_EQ(xmp_value(xmp, "dc:title"), c.title);
  }
}

TEST_F(HtmlToPdfPdfaTest, AttachmentsNeedPdfa3) {
  const auto html = write_html(kHead);
  PdfOptions options = pdfa_options();
  options.variant = "pdf/a-2b";
  EXPECT_THROW(html_to_pdf(html, dir_.path() / "a.pdf", options), RenderError);
  options.variant = "pdf/a-3";
  EXPECT_THROW(html_to_pdf(html, dir_.path() / "a.pdf", options), RenderError);
  options.variant = "pdf/a-3b";
  options.attachments[0].relationship = "data";  // the PDF name is case-sensitive
  EXPECT_THROW(html_to_pdf(html, dir_.path() / "a.pdf", options), RenderError);
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "a.pdf"));
}

TEST_F(HtmlToPdfPdfaTest, MissingAttachmentThrowsNamingIt) {
  PdfOptions options = pdfa_options();
  options.attachments[0].file = dir_.path() / "no_results.json";
  try {
    html_to_pdf(write_html(kHead), dir_.path() / "a.pdf", options);
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("no_results.json does not exist"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "a.pdf"));
}

TEST_F(HtmlToPdfPdfaTest, MissingQpdfThrowsAndLeavesNoPdf) {
  PdfOptions options = pdfa_options();
  options.qpdf = "/nonexistent/qpdf";
  EXPECT_THROW(html_to_pdf(write_html(kHead), dir_.path() / "a.pdf", options), RenderError);
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "a.pdf"));
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "a.pdf.partial"));
}

}  // namespace
}  // namespace chatterlab::render
