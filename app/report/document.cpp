#include "app/report/document.h"

#include <ctime>
#include <fstream>

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

bool write_documents(const std::string& template_name, const nlohmann::json& ctx,
                     const std::filesystem::path& out, bool pdf, const std::string& command,
                     std::ostream& log) {
  const auto tdir = templates_dir();
  std::filesystem::copy_file(tdir / "report.css", out / "report.css",
                             std::filesystem::copy_options::overwrite_existing);
  {
    std::ofstream html(out / "index.html");
    html << render::render_template_file(tdir / template_name, ctx);
  }
  if (!pdf) return false;
  try {
    for (const auto& w : render::html_to_pdf(out / "index.html", out / "report.pdf")) {
      log << "  weasyprint: " << w << "\n";
    }
    return true;
  } catch (const render::RenderError& e) {
    log << "chatterlab " << command << ": PDF not written: " << e.what() << "\n";
    return false;
  }
}

}  // namespace chatterlab::app
