#include "app/report/html_pages.h"

#include <cctype>
#include <set>

#include "render/mustache_template.h"

namespace chatterlab::app {
namespace {

constexpr const char* kFigureOpen = "<figure class=\"fig\"";
constexpr const char* kFiguresSrc = "src=\"figures/";

// The value of attribute `name` in one tag's text, or "" when absent.
std::string attribute(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const auto at = tag.find(key);
  if (at == std::string::npos) return {};
  const auto begin = at + key.size();
  const auto end = tag.find('"', begin);
  return end == std::string::npos ? std::string() : tag.substr(begin, end - begin);
}

// Copies `html`, passing each `<img ...>` tag through `edit` (which returns its replacement).
template <typename Edit>
std::string edit_images(const std::string& html, Edit edit) {
  std::string out;
  out.reserve(html.size());
  std::size_t pos = 0;
  while (true) {
    const auto at = html.find("<img ", pos);
    const auto end = at == std::string::npos ? at : html.find('>', at);
    if (end == std::string::npos) break;
    out.append(html, pos, at - pos);
    out += edit(html.substr(at, end + 1 - at));
    pos = end + 1;
  }
  out.append(html, pos, std::string::npos);
  return out;
}

// "figures/a/b.svg" -> "a/b": the stem of the first figures/ image inside the figure that
// starts at `at`, or "" when it has none.
std::string figure_stem(const std::string& html, std::size_t at) {
  const auto close = html.find("</figure>", at);
  const auto src = html.find(kFiguresSrc, at);
  if (src == std::string::npos || (close != std::string::npos && src > close)) return {};
  const auto begin = src + std::string(kFiguresSrc).size();
  const auto end = html.find('"', begin);
  if (end == std::string::npos) return {};
  std::string path = html.substr(begin, end - begin);
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(0, dot);
}

std::string slug(const std::string& s) {
  std::string out = s;
  for (char& c : out) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '-';
  }
  return out;
}

// Gives every `<figure class="fig">` without an id the id "fig-<stem>" (made unique), and,
// when `out` is set and figures/<stem>.csv exists there, a link to it ending its caption.
std::string label_figures(const std::string& html, const std::filesystem::path* out) {
  std::string result;
  result.reserve(html.size() + 4096);
  std::set<std::string> used;
  std::size_t pos = 0;
  const std::string open = kFigureOpen;
  while (true) {
    const auto at = html.find(open, pos);
    if (at == std::string::npos) break;
    const auto tag_end = html.find('>', at);
    if (tag_end == std::string::npos) break;
    const std::string stem = figure_stem(html, at);
    const bool has_id = html.substr(at, tag_end - at).find(" id=\"") != std::string::npos;
    result.append(html, pos, at + open.size() - pos);
    std::string id;
    if (!has_id && !stem.empty()) {
      id = "fig-" + slug(stem);
      for (int n = 2; used.count(id) > 0; ++n) id = "fig-" + slug(stem) + "-" + std::to_string(n);
      used.insert(id);
      result += " id=\"" + id + "\"";
    }
    pos = at + open.size();
    std::error_code ec;
    const auto caption_end = html.find("</figcaption>", pos);
    const auto figure_end = html.find("</figure>", pos);
    if (out != nullptr && caption_end != std::string::npos && caption_end < figure_end) {
      result.append(html, pos, caption_end - pos);
      if (!stem.empty() &&
          std::filesystem::is_regular_file(*out / "figures" / (stem + ".csv"), ec)) {
        result += " <a class=\"fig-data\" href=\"figures/" + stem + ".csv\">Data (CSV)</a>";
      }
      if (!id.empty()) {
        result += " <a class=\"fig-link\" href=\"#" + id + "\" title=\"link to this figure\">#</a>";
      }
      pos = caption_end;
    }
  }
  result.append(html, pos, std::string::npos);
  return result;
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (auto at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size())) {
    s.replace(at, from.size(), to);
  }
  return s;
}

// Every <details> tag (with or without attributes) opened: print shows what the screen folds.
std::string open_details(const std::string& html) {
  std::string out;
  out.reserve(html.size() + 256);
  std::size_t pos = 0;
  for (auto at = html.find("<details", pos); at != std::string::npos;
       at = html.find("<details", pos)) {
    const auto end = html.find('>', at);
    if (end == std::string::npos) break;
    const std::string tag = html.substr(at, end + 1 - at);
    const char next = tag.size() > 8 ? tag[8] : '\0';
    out.append(html, pos, at - pos);
    if ((next == ' ' || next == '>') && tag.find(" open") == std::string::npos) {
      out += "<details open" + tag.substr(8);
    } else {
      out += tag;
    }
    pos = end + 1;
  }
  out.append(html, pos, std::string::npos);
  return out;
}

std::string mime_type(const std::filesystem::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
  return "application/octet-stream";
}

}  // namespace

std::string test_anchor(const std::string& id) { return "test-" + slug(id.empty() ? "." : id); }

std::string base64(const std::string& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16 |
                       static_cast<unsigned char>(bytes[i + 1]) << 8 |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += kAlphabet[v >> 6 & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16 |
                       (two ? static_cast<unsigned char>(bytes[i + 1]) << 8 : 0u);
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += two ? kAlphabet[v >> 6 & 63] : '=';
    out += '=';
  }
  return out;
}

std::string screen_page(const std::string& html, const std::filesystem::path& out) {
  const std::string kept = edit_images(html, [](const std::string& tag) -> std::string {
    const std::string cls = attribute(tag, "class");
    if (cls == "print-only") return {};
    if (cls == "screen-only") return "<img loading=\"lazy\"" + tag.substr(4);
    return tag;
  });
  return label_figures(kept, &out);
}

std::string print_page(const std::string& html) {
  const std::string kept = edit_images(html, [](const std::string& tag) -> std::string {
    return attribute(tag, "class") == "screen-only" ? std::string() : tag;
  });
  return label_figures(open_details(kept), nullptr);
}

std::string single_file_page(const std::string& screen_html, const std::filesystem::path& out) {
  const std::string link = "<link rel=\"stylesheet\" href=\"report.css\">";
  std::string html = screen_html;
  if (const auto at = html.find(link); at != std::string::npos) {
    html.replace(at, link.size(),
                 "<style>\n" + render::read_text_file(out / "report.css") + "</style>");
  }
  return edit_images(html, [&out](const std::string& tag) -> std::string {
    const std::string src = attribute(tag, "src");
    if (src.rfind("figures/", 0) != 0) return tag;
    const std::filesystem::path file = out / src;
    const std::string data =
        "data:" + mime_type(file) + ";base64," + base64(render::read_text_file(file));
    std::string t = replace_all(tag, "src=\"" + src + "\"", "src=\"" + data + "\"");
    return replace_all(t, " loading=\"lazy\"", "");
  });
}

}  // namespace chatterlab::app
