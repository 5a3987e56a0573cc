#include "render/html_to_pdf.h"

#include <sstream>
#include <system_error>

#include "render/render_error.h"
#include "render/subprocess.h"

namespace chatterlab::render {

std::vector<std::string> html_to_pdf(const std::filesystem::path& html,
                                     const std::filesystem::path& pdf, const PdfOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(html, ec)) {
    throw RenderError("html_to_pdf: " + html.string() + " does not exist or is not a file");
  }
  const std::filesystem::path source = std::filesystem::absolute(html, ec);
  // A folder URL needs its trailing slash, or relative links resolve one level up.
  const std::string base_url = source.parent_path().string() + "/";
  std::filesystem::path partial = pdf;
  partial += ".partial";

  ProcessResult result;
  try {
    result = run_process(
        {options.weasyprint, "--base-url", base_url, source.string(), partial.string()});
  } catch (const RenderError& e) {
    throw RenderError("html_to_pdf " + html.string() + ": " + e.what());
  }
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
  std::filesystem::rename(partial, pdf, ec);
  if (ec) {
    std::filesystem::remove(partial, ec);
    throw RenderError("html_to_pdf " + html.string() + ": cannot write " + pdf.string());
  }

  std::vector<std::string> warnings;
  std::istringstream lines(result.err);
  for (std::string line; std::getline(lines, line);) {
    if (!line.empty()) warnings.push_back(line);
  }
  return warnings;
}

}  // namespace chatterlab::render
