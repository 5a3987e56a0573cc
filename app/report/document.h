// Writing a report folder's documents: index.html from a template in templates_dir() with
// report.css beside it, then report.pdf from the same HTML (used by `report` and `simulate`).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace chatterlab::app {

// Folder holding the report templates and report.css: $CHATTERLAB_TEMPLATES, else templates/
// beside the executable's parent folder, else the source tree's templates/.
std::filesystem::path templates_dir();

// "2026-11-23 01:57 UTC": when a report was generated.
std::string utc_timestamp();

// "2026-11-23T01:57:09Z": the same moment as a W3C date (the PDF's creation date).
std::string utc_timestamp_iso();

// The title-page keys of a spec command's report (simulate, lobes): name (the spec's stem),
// generated_utc, generated_iso, version, spec_file (its name only: no path of the machine) and
// spec_sha256.
nlohmann::json spec_document_context(const std::filesystem::path& spec_file,
                                     const std::string& spec_sha256);

// What templates/spec_title.mustache (the head and title page of the spec documents) needs
// beside spec_document_context's keys and tool, modal, coefficients, cut, summary_line:
// product ("stability lobes": the title), kicker, keywords, and the title page's fifth row.
struct SpecTitle {
  std::string product;
  std::string kicker;
  std::string keywords;
  std::string setup_label;  // "Grid", "Model"
  std::string setup;
};
void set_spec_title(nlohmann::json& ctx, const SpecTitle& title);

// "tooth 1: Kt = 6e+08, Kr = 2e+08 N/m²; tooth 2: ..." (one entry per tooth, 4 digits).
std::string tooth_coefficients_text(const std::vector<double>& Kt_N_m2,
                                    const std::vector<double>& Kr_N_m2);

// results.json as the spec commands write it: two-space indent, invalid UTF-8 replaced.
void write_results_json(const std::filesystem::path& file, const nlohmann::json& results);

struct DocumentOptions {
  bool pdf = true;           // write out/report.pdf through WeasyPrint
  bool single_file = false;  // also write out/report.html: stylesheet and figures inside it
};

// Renders `template_name` (e.g. "report.html") with `ctx`, copies report.css, and writes the
// pages of app/report/html_pages.h: out/index.html (the screen page), with options.single_file
// out/report.html, and with options.pdf out/report.pdf through WeasyPrint from the print page
// (written beside it as a temporary file and removed): PDF/A-3b with out/results.json, when
// present, attached (write it first). Returns whether the PDF was written; a
// PDF failure and WeasyPrint's warnings go to `log` prefixed by `command`. Throws RenderError
// when the single-file page cannot be made.
bool write_documents(const std::string& template_name, const nlohmann::json& ctx,
                     const std::filesystem::path& out, const DocumentOptions& options,
                     const std::string& command, std::ostream& log);

}  // namespace chatterlab::app
