// PDF from the report's HTML through WeasyPrint (Debian package weasyprint, 57.x), so the
// PDF and the HTML are the same document: report.css carries the print rules.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace chatterlab::render {

struct PdfOptions {
  std::string weasyprint = "weasyprint";  // the program, found in PATH
};

// Converts `html` to `pdf`. Relative links in the HTML (figures, report.css) resolve against
// the HTML file's folder. The PDF is written next to its destination and renamed into place,
// so a failed run never leaves a truncated PDF. Returns WeasyPrint's warnings (one per line,
// e.g. an image it could not load), which the caller should report. Throws RenderError
// naming the HTML file when it is missing, when WeasyPrint is not installed or fails (with
// its stderr), or when the PDF cannot be written.
std::vector<std::string> html_to_pdf(const std::filesystem::path& html,
                                     const std::filesystem::path& pdf,
                                     const PdfOptions& options = {});

}  // namespace chatterlab::render
