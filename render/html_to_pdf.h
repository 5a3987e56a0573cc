// PDF from the report's HTML through WeasyPrint (Debian package weasyprint, 57.x), so the
// PDF and the HTML are the same document: report.css carries the print rules. Optionally a
// PDF/A variant with embedded files (PDF/A-3b with results.json), finished with qpdf.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace chatterlab::render {

// A file embedded in the PDF (an "associated file" of the document in PDF/A-3 terms).
struct PdfAttachment {
  std::filesystem::path file;         // embedded under its file name ("results.json")
  std::string description;            // the file specification's /Desc; empty: none
  std::string mime_type;              // the embedded file's /Subtype; empty: from the extension
                                      // (.json application/json, .csv text/csv, else octet-stream)
  std::string relationship = "Data";  // /AFRelationship: Data, Source, Alternative,
                                      // Supplement or Unspecified
};

struct PdfOptions {
  std::string weasyprint = "weasyprint";  // the program, found in PATH
  std::string qpdf = "qpdf";              // finishes a variant or attachments; found in PATH
  // WeasyPrint's --pdf-variant: "" (a plain PDF), "pdf/a-1b", "pdf/a-2b", "pdf/a-3b",
  // "pdf/a-4b" or "pdf/ua-1". Only "pdf/a-3b" may carry attachments among the PDF/A ones
  // (PDF/A-1 forbids embedded files, PDF/A-2 allows only PDF/A files).
  std::string variant;
  std::vector<PdfAttachment> attachments;
};

// Converts `html` to `pdf`. Relative links in the HTML (figures, report.css) resolve against
// the HTML file's folder. The PDF is written next to its destination and renamed into place,
// so a failed run never leaves a truncated PDF. Returns WeasyPrint's warnings (one per line,
// e.g. an image it could not load), which the caller should report. Throws RenderError
// naming the HTML file when it is missing, when WeasyPrint is not installed or fails (with
// its stderr), or when the PDF cannot be written.
//
// With a variant or attachments, WeasyPrint writes them (--pdf-variant, --attachment) and qpdf
// then adds what WeasyPrint 57 leaves out (docs/rendering.md, "PDF/A-3b"): each embedded
// file's /F, /AFRelationship, MIME /Subtype and /ModDate, the catalog's /AF array, "D:" on the
// Info dates (CreationDate: now when the HTML gives no dcterms.created), for PDF/A-1b/2b/3b XMP
// metadata rewritten from the Info dictionary (dc:title, dc:creator, dc:description, pdf:Keywords,
// xmp:CreatorTool, dates, pdfaid part and conformance), and the trailer /ID. Also throws when an
// attachment is missing or not allowed by the variant, the variant is unknown, or qpdf is missing
// or fails. WeasyPrint's "PDF/A support is experimental" line is not returned as a warning.
std::vector<std::string> html_to_pdf(const std::filesystem::path& html,
                                     const std::filesystem::path& pdf,
                                     const PdfOptions& options = {});

}  // namespace chatterlab::render
