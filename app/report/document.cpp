#include "app/report/document.h"

#include <ctime>
#include <fstream>

#include "analysis/common/summary.h"
#include "app/core/checked_write.h"
#include "app/core/format.h"
#include "app/report/html_pages.h"
#include "render/html_to_pdf.h"
#include "render/mustache_template.h"
#include "render/render_error.h"

namespace chatterlab::app {

std::filesystem::path templates_dir() {
  if (const char* env = std::getenv("CHATTERLAB_TEMPLATES"); env && *env) return env;
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (const auto& cand : {exe.parent_path().parent_path() / "templates",
                             exe.parent_path().parent_path().parent_path() / "templates"}) {
      if (std::filesystem::exists(cand / "report.html")) return cand;
    }
  }
  return std::filesystem::path(CHATTERLAB_SOURCE_DIR) / "templates";
}

std::string utc_timestamp() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%d %H:%M UTC", std::gmtime(&t));
  return buf;
}

namespace {

// Every step checked (app/core/checked_write.h): throws InputError naming the file.
void write_text(const std::filesystem::path& path, const std::string& text) {
  write_file_checked(path, text);
}

}  // namespace

std::string utc_timestamp_iso() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

bool write_documents(const std::string& template_name, const nlohmann::json& ctx,
                     const std::filesystem::path& out, const DocumentOptions& options,
                     const std::string& command, std::ostream& log) {
  const auto tdir = templates_dir();
  std::error_code css_error;
  std::filesystem::copy_file(tdir / "report.css", out / "report.css",
                             std::filesystem::copy_options::overwrite_existing, css_error);
  if (css_error) {
    throw InputError("cannot copy " + (tdir / "report.css").string() + " to " +
                     (out / "report.css").string() + ": " + css_error.message());
  }
  const std::string html = render::render_template_file(tdir / template_name, ctx);
  const std::string screen = screen_page(html, out);
  write_text(out / "index.html", screen);
  if (options.single_file) write_text(out / "report.html", single_file_page(screen, out));
  if (!options.pdf) return false;
  // The print page lives beside index.html while WeasyPrint reads it, so that its relative
  // links (figures/, report.css) resolve the same way.
  const std::filesystem::path print = out / ".print.html";
  std::error_code ec;
  try {
    write_text(print, print_page(html));
    // PDF/A-3b for the archive, carrying the machine-readable results (docs/rendering.md).
    render::PdfOptions pdf_options;
    pdf_options.variant = "pdf/a-3b";
    if (std::filesystem::is_regular_file(out / "results.json", ec)) {
      render::PdfAttachment results;
      results.file = out / "results.json";
      results.description = "chatterlab results, machine-readable (docs/results.schema.json)";
      pdf_options.attachments.push_back(results);
    }
    for (const auto& w : render::html_to_pdf(print, out / "report.pdf", pdf_options)) {
      log << "  weasyprint: " << w << "\n";
    }
    std::filesystem::remove(print, ec);
    return true;
  } catch (const render::RenderError& e) {
    std::filesystem::remove(print, ec);
    log << "chatterlab " << command << ": PDF not written: " << e.what() << "\n";
    return false;
  }
}

nlohmann::json spec_document_context(const std::filesystem::path& spec_file,
                                     const std::string& spec_sha256) {
  nlohmann::json ctx;
  ctx["name"] = spec_file.stem().string();
  ctx["generated_utc"] = utc_timestamp();
  ctx["generated_iso"] = utc_timestamp_iso();
  ctx["version"] = CHATTERLAB_VERSION;
  ctx["spec_file"] = spec_file.filename().string();
  ctx["spec_sha256"] = spec_sha256;
  return ctx;
}

void set_spec_title(nlohmann::json& ctx, const SpecTitle& title) {
  ctx["product"] = title.product;
  ctx["kicker"] = title.kicker;
  ctx["keywords"] = title.keywords;
  ctx["setup_label"] = title.setup_label;
  ctx["setup"] = title.setup;
}

std::string tooth_coefficients_text(const std::vector<double>& Kt_N_m2,
                                    const std::vector<double>& Kr_N_m2) {
  std::string k;
  for (std::size_t p = 0; p < Kt_N_m2.size() && p < Kr_N_m2.size(); ++p) {
    k += (p ? "; " : "") + std::string("tooth ") + std::to_string(p + 1) +
         ": Kt = " + fmt_sig(Kt_N_m2[p], 4) + ", Kr = " + fmt_sig(Kr_N_m2[p], 4) + " N/m\u00b2";
  }
  return k;
}

void write_results_json(const std::filesystem::path& file, const nlohmann::json& results) {
  write_file_checked(file,
                     results.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

}  // namespace chatterlab::app
