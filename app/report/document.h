// Writing a report folder's documents: index.html from a template in templates_dir() with
// report.css beside it, then report.pdf from the same HTML (used by `report` and `simulate`).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

namespace chatterlab::app {

// Folder holding the report templates and report.css: $CHATTERLAB_TEMPLATES, else templates/
// beside the executable's parent folder, else the source tree's templates/.
std::filesystem::path templates_dir();

// "2026-11-23 01:57 UTC": when a report was generated.
std::string utc_timestamp();

// Renders `template_name` (e.g. "report.html") with `ctx` to out/index.html, copies
// report.css, and with `pdf` writes out/report.pdf through WeasyPrint. Returns whether the PDF
// was written; a PDF failure and WeasyPrint's warnings go to `log` prefixed by `command`.
bool write_documents(const std::string& template_name, const nlohmann::json& ctx,
                     const std::filesystem::path& out, bool pdf, const std::string& command,
                     std::ostream& log);

}  // namespace chatterlab::app
