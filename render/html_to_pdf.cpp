#include "render/html_to_pdf.h"

#include <sys/stat.h>

#include <cctype>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>

#include "render/render_error.h"
#include "render/subprocess.h"
#include "render/temp_dir.h"

namespace chatterlab::render {
namespace {

using nlohmann::json;

// WeasyPrint 57 logs this on every PDF/A run; the finishing step and the tests cover it.
const char* const kExperimentalWarning = "PDF/A support is experimental";

bool known_variant(const std::string& v) {
  for (const char* k : {"", "pdf/a-1b", "pdf/a-2b", "pdf/a-3b", "pdf/a-4b", "pdf/ua-1"}) {
    if (v == k) return true;
  }
  return false;
}

// 1, 2 or 3 for pdf/a-1b, -2b, -3b (the variants whose XMP is rewritten); 0 otherwise.
int pdfa_b_part(const std::string& v) {
  if (v.size() == 8 && v.compare(0, 6, "pdf/a-") == 0 && v[7] == 'b' && v[6] >= '1' &&
      v[6] <= '3') {
    return v[6] - '0';
  }
  return 0;
}

std::string mime_of(const std::string& name) {
  const std::string ext = std::filesystem::path(name).extension().string();
  if (ext == ".json") return "application/json";
  if (ext == ".csv") return "text/csv";
  if (ext == ".txt") return "text/plain";
  if (ext == ".xml") return "application/xml";
  if (ext == ".yaml" || ext == ".yml") return "application/yaml";
  if (ext == ".html") return "text/html";
  return "application/octet-stream";
}

// A PDF name in qpdf's JSON: "/" and the text with delimiters escaped as #XX.
std::string name_token(const std::string& text) {
  std::string out = "/";
  for (unsigned char c : text) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '+') {
      out += static_cast<char>(c);
    } else {
      char buf[4];
      std::snprintf(buf, sizeof(buf), "#%02X", c);
      out += buf;
    }
  }
  return out;
}

std::string base64(const std::string& in) {
  static const char* const t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) |
                       (static_cast<unsigned char>(in[i + 1]) << 8) |
                       static_cast<unsigned char>(in[i + 2]);
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
  }
  if (i + 1 == in.size()) {
    const unsigned v = static_cast<unsigned char>(in[i]) << 16;
    out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const unsigned v =
        (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8);
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
  }
  return out;
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// "D:YYYYMMDDHHmmSSZ" (UTC) of a file's modification time; empty when it cannot be read.
std::string pdf_date_of_file(const std::filesystem::path& file) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) return {};
  std::tm tm{};
  gmtime_r(&st.st_mtime, &tm);
  char buf[32];
  std::strftime(buf, sizeof(buf), "D:%Y%m%d%H%M%SZ", &tm);
  return buf;
}

// A PDF date ("D:20261202012900Z", "D:2026120201+01'00'") as an XMP date
// ("2026-12-02T01:29:00Z", "2026-12-02T01:00+01:00"); empty when it does not parse.
std::string xmp_date(std::string d) {
  if (d.compare(0, 2, "D:") == 0) d.erase(0, 2);
  std::size_t n = 0;
  while (n < d.size() && n < 14 && std::isdigit(static_cast<unsigned char>(d[n]))) ++n;
  if (n < 4 || n % 2 != 0) return {};
  std::string out = d.substr(0, 4);
  if (n >= 6) out += "-" + d.substr(4, 2);
  if (n >= 8) out += "-" + d.substr(6, 2);
  if (n >= 10) out += "T" + d.substr(8, 2) + ":" + (n >= 12 ? d.substr(10, 2) : "00");
  if (n >= 14) out += ":" + d.substr(12, 2);
  const std::string tz = d.substr(n);
  if (n < 10 || tz.empty()) return out;
  if (tz[0] == 'Z') return out + "Z";
  if ((tz[0] == '+' || tz[0] == '-') && tz.size() >= 3) {
    std::string mm = "00";
    if (tz.size() >= 6 && tz[3] == '\'') mm = tz.substr(4, 2);
    return out + tz.substr(0, 3) + ":" + mm;
  }
  return {};
}

// A text string of qpdf's JSON ("u:..."); empty for anything else.
std::string text_of(const json& v) {
  if (!v.is_string()) return {};
  const std::string s = v.get<std::string>();
  return s.compare(0, 2, "u:") == 0 ? s.substr(2) : std::string();
}

// XMP for PDF/A-<part>B, equivalent to the Info dictionary (ISO 19005-1 6.7.3, kept by
// 19005-2/-3): Title dc:title, Author dc:creator, Subject dc:description, Keywords
// pdf:Keywords, Creator xmp:CreatorTool, Producer pdf:Producer, the dates xmp:CreateDate and
// xmp:ModifyDate.
std::string pdfa_xmp(int part, const json& info) {
  auto field = [&](const char* key) { return text_of(info.value(key, json())); };
  std::ostringstream x;
  x << "<?xpacket begin=\"\xEF\xBB\xBF\" id=\"W5M0MpCehiHzreSzNTczkc9d\"?>\n"
    << "<x:xmpmeta xmlns:x=\"adobe:ns:meta/\">\n"
    << "<rdf:RDF xmlns:rdf=\"http://www.w3.org/1999/02/22-rdf-syntax-ns#\">\n"
    << "<rdf:Description rdf:about=\"\" xmlns:pdfaid=\"http://www.aiim.org/pdfa/ns/id/\">\n"
    << "<pdfaid:part>" << part << "</pdfaid:part>\n"
    << "<pdfaid:conformance>B</pdfaid:conformance>\n"
    << "</rdf:Description>\n"
    << "<rdf:Description rdf:about=\"\" xmlns:dc=\"http://purl.org/dc/elements/1.1/\">\n"
    << "<dc:format>application/pdf</dc:format>\n";
  if (const auto t = field("/Title"); !t.empty()) {
    x << "<dc:title><rdf:Alt><rdf:li xml:lang=\"x-default\">" << xml_escape(t)
      << "</rdf:li></rdf:Alt></dc:title>\n";
  }
  if (const auto a = field("/Author"); !a.empty()) {
    x << "<dc:creator><rdf:Seq><rdf:li>" << xml_escape(a) << "</rdf:li></rdf:Seq></dc:creator>\n";
  }
  if (const auto s = field("/Subject"); !s.empty()) {
    x << "<dc:description><rdf:Alt><rdf:li xml:lang=\"x-default\">" << xml_escape(s)
      << "</rdf:li></rdf:Alt></dc:description>\n";
  }
  x << "</rdf:Description>\n"
    << "<rdf:Description rdf:about=\"\" xmlns:pdf=\"http://ns.adobe.com/pdf/1.3/\">\n";
  if (const auto p = field("/Producer"); !p.empty()) {
    x << "<pdf:Producer>" << xml_escape(p) << "</pdf:Producer>\n";
  }
  if (const auto k = field("/Keywords"); !k.empty()) {
    x << "<pdf:Keywords>" << xml_escape(k) << "</pdf:Keywords>\n";
  }
  x << "</rdf:Description>\n"
    << "<rdf:Description rdf:about=\"\" xmlns:xmp=\"http://ns.adobe.com/xap/1.0/\">\n";
  if (const auto c = field("/Creator"); !c.empty()) {
    x << "<xmp:CreatorTool>" << xml_escape(c) << "</xmp:CreatorTool>\n";
  }
  if (const auto d = xmp_date(field("/CreationDate")); !d.empty()) {
    x << "<xmp:CreateDate>" << d << "</xmp:CreateDate>\n";
  }
  if (const auto d = xmp_date(field("/ModDate")); !d.empty()) {
    x << "<xmp:ModifyDate>" << d << "</xmp:ModifyDate>\n";
  }
  x << "</rdf:Description>\n</rdf:RDF>\n</x:xmpmeta>\n<?xpacket end=\"w\"?>";
  return x.str();
}

ProcessResult run_tool(const std::vector<std::string>& argv, const std::filesystem::path& html) {
  try {
    return run_process(argv);
  } catch (const RenderError& e) {
    throw RenderError("html_to_pdf " + html.string() + ": " + e.what());
  }
}

// Adds to WeasyPrint's PDF `in` what PDF/A-3 asks of embedded files and metadata (see the
// header), writing `out` with qpdf --update-from-json. Returns qpdf's warnings.
std::vector<std::string> finish_pdf(const std::filesystem::path& in,
                                    const std::filesystem::path& out, const PdfOptions& options,
                                    const std::filesystem::path& html) {
  ProcessResult r = run_tool(
      {options.qpdf, "--json=2", "--json-key=qpdf", "--json-stream-data=none", in.string()}, html);
  // qpdf exits 3 for warnings, 2 for errors.
  if (r.exit_code != 0 && r.exit_code != 3) {
    throw RenderError("qpdf cannot read WeasyPrint's PDF of " + html.string() + " (exit code " +
                      std::to_string(r.exit_code) + "): " + tail_of(r.err));
  }
  json doc;
  try {
    doc = json::parse(r.out);
    json& objects = doc.at("qpdf").at(1);
    auto object = [&](const json& ref) -> json& {
      return objects.at("obj:" + ref.get<std::string>());
    };
    const json trailer = objects.at("trailer").at("value");
    json update = json::object();

    // Embedded files: match WeasyPrint's file specifications to the attachments by name.
    json af = json::array();
    std::vector<bool> embedded(options.attachments.size(), false);
    for (auto& [key, entry] : objects.items()) {
      if (key.compare(0, 4, "obj:") != 0 || !entry.contains("value")) continue;
      const json& value = entry["value"];
      if (!value.is_object() || value.value("/Type", "") != "/Filespec" || !value.contains("/EF")) {
        continue;
      }
      json spec = value;
      std::string name = text_of(spec.value("/UF", json()));
      if (name.empty()) name = text_of(spec.value("/F", json()));
      const PdfAttachment* match = nullptr;
      for (std::size_t i = 0; i < options.attachments.size() && !match; ++i) {
        if (!embedded[i] && options.attachments[i].file.filename().string() == name) {
          embedded[i] = true;
          match = &options.attachments[i];
        }
      }
      spec["/F"] = "u:" + name;
      spec["/UF"] = "u:" + name;
      spec["/AFRelationship"] = name_token(match ? match->relationship : "Unspecified");
      if (match && !match->description.empty()) spec["/Desc"] = "u:" + match->description;
      update[key] = {{"value", spec}};
      af.push_back(key.substr(4));

      const json& ref = spec.at("/EF").at("/F");
      json stream = object(ref).at("stream").at("dict");
      stream["/Subtype"] =
          name_token(match && !match->mime_type.empty() ? match->mime_type : mime_of(name));
      if (match) {
        if (const std::string d = pdf_date_of_file(match->file); !d.empty()) {
          json params = stream.value("/Params", json::object());
          params["/ModDate"] = "u:" + d;
          stream["/Params"] = params;
        }
      }
      stream.erase("/Length");
      update["obj:" + ref.get<std::string>()] = {{"stream", {{"dict", stream}}}};
    }
    for (std::size_t i = 0; i < options.attachments.size(); ++i) {
      if (!embedded[i]) {
        throw RenderError("html_to_pdf " + html.string() + ": WeasyPrint did not embed " +
                          options.attachments[i].file.string());
      }
    }

    json info = json::object();
    if (trailer.contains("/Info")) {
      info = object(trailer["/Info"]).at("value");
      // WeasyPrint 57 writes dates without their "D:" prefix.
      for (const char* key : {"/CreationDate", "/ModDate"}) {
        const std::string d = text_of(info.value(key, json()));
        if (!d.empty() && d.compare(0, 2, "D:") != 0) info[key] = "u:D:" + d;
      }
      // Without <meta name="dcterms.created">: the time of this conversion.
      if (!info.contains("/CreationDate")) {
        const std::time_t now = std::time(nullptr);
        std::tm tm{};
        gmtime_r(&now, &tm);
        char buf[32];
        std::strftime(buf, sizeof(buf), "u:D:%Y%m%d%H%M%SZ", &tm);
        info["/CreationDate"] = buf;
      }
      update["obj:" + trailer["/Info"].get<std::string>()] = {{"value", info}};
    }

    json catalog = object(trailer.at("/Root")).at("value");
    if (!af.empty()) {
      catalog["/AF"] = af;
      update["obj:" + trailer["/Root"].get<std::string>()] = {{"value", catalog}};
    }
    if (const int part = pdfa_b_part(options.variant); part && catalog.contains("/Metadata")) {
      update["obj:" + catalog["/Metadata"].get<std::string>()] = {
          {"stream",
           {{"dict", {{"/Type", "/Metadata"}, {"/Subtype", "/XML"}}},
            {"data", base64(pdfa_xmp(part, info))}}}};
    }
    doc["qpdf"][1] = update;
  } catch (const json::exception& e) {
    throw RenderError("html_to_pdf " + html.string() + ": unexpected qpdf JSON: " + e.what());
  }

  TempDir scratch("chatterlab-pdf-");
  const auto update_file = scratch.path() / "update.json";
  {
    std::ofstream f(update_file);
    f << doc.dump();
    f.close();
    if (!f)
      throw RenderError("html_to_pdf " + html.string() + ": cannot write " + update_file.string());
  }
  r = run_tool(
      {options.qpdf, in.string(), "--update-from-json=" + update_file.string(), out.string()},
      html);
  if (r.exit_code != 0 && r.exit_code != 3) {
    throw RenderError("qpdf failed on the PDF of " + html.string() + " (exit code " +
                      std::to_string(r.exit_code) + "): " + tail_of(r.err));
  }
  std::vector<std::string> warnings;
  std::istringstream lines(r.err);
  for (std::string line; std::getline(lines, line);) {
    if (!line.empty()) warnings.push_back("qpdf: " + line);
  }
  return warnings;
}

}  // namespace

std::vector<std::string> html_to_pdf(const std::filesystem::path& html,
                                     const std::filesystem::path& pdf, const PdfOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(html, ec)) {
    throw RenderError("html_to_pdf: " + html.string() + " does not exist or is not a file");
  }
  if (!known_variant(options.variant)) {
    throw RenderError("html_to_pdf " + html.string() + ": unknown PDF variant \"" +
                      options.variant +
                      "\" (one of pdf/a-1b, pdf/a-2b, pdf/a-3b, pdf/a-4b, pdf/ua-1)");
  }
  if (!options.attachments.empty() &&
      (options.variant == "pdf/a-1b" || options.variant == "pdf/a-2b")) {
    throw RenderError("html_to_pdf " + html.string() + ": " + options.variant +
                      " cannot carry attachments (PDF/A-3b can)");
  }
  for (const auto& a : options.attachments) {
    const std::string& rel = a.relationship;
    if (rel != "Data" && rel != "Source" && rel != "Alternative" && rel != "Supplement" &&
        rel != "Unspecified") {
      throw RenderError("html_to_pdf " + html.string() + ": attachment " + a.file.string() +
                        ": relationship \"" + rel +
                        "\" is not one of Data, Source, Alternative, Supplement, Unspecified");
    }
    if (!std::filesystem::is_regular_file(a.file, ec)) {
      throw RenderError("html_to_pdf " + html.string() + ": attachment " + a.file.string() +
                        " does not exist or is not a file");
    }
  }
  const std::filesystem::path source = std::filesystem::absolute(html, ec);
  // A folder URL needs its trailing slash, or relative links resolve one level up.
  const std::string base_url = source.parent_path().string() + "/";
  std::filesystem::path partial = pdf;
  partial += ".partial";

  std::vector<std::string> argv = {options.weasyprint, "--base-url", base_url};
  if (!options.variant.empty()) {
    argv.insert(argv.end(), {"--pdf-variant", options.variant});
  }
  for (const auto& a : options.attachments) {
    argv.insert(argv.end(), {"--attachment", std::filesystem::absolute(a.file, ec).string()});
  }
  argv.insert(argv.end(), {source.string(), partial.string()});
  const ProcessResult result = run_tool(argv, html);
  if (result.exit_code != 0) {
    std::filesystem::remove(partial, ec);
    // WeasyPrint 57 stops on gnuplot's SVG point markers: say what to do instead.
    const bool svg = result.err.find("/svg/") != std::string::npos;
    throw RenderError("weasyprint failed on " + html.string() + " (exit code " +
                      std::to_string(result.exit_code) + "): " + tail_of(result.err) +
                      (svg ? "\n(an SVG image it cannot draw: give print a PNG figure, see "
                             "render_report_figure and docs/rendering.md)"
                           : ""));
  }

  std::vector<std::string> warnings;
  std::istringstream lines(result.err);
  for (std::string line; std::getline(lines, line);) {
    if (line.empty()) continue;
    if (!options.variant.empty() && line.find(kExperimentalWarning) != std::string::npos) {
      continue;
    }
    warnings.push_back(line);
  }

  if (!options.variant.empty() || !options.attachments.empty()) {
    std::filesystem::path finished = pdf;
    finished += ".finished.partial";
    try {
      for (auto& w : finish_pdf(partial, finished, options, html)) warnings.push_back(w);
    } catch (...) {
      std::filesystem::remove(partial, ec);
      std::filesystem::remove(finished, ec);
      throw;
    }
    std::filesystem::remove(partial, ec);
    partial = finished;
  }

  std::filesystem::rename(partial, pdf, ec);
  if (ec) {
    std::filesystem::remove(partial, ec);
    throw RenderError("html_to_pdf " + html.string() + ": cannot write " + pdf.string());
  }
  return warnings;
}

}  // namespace chatterlab::render
