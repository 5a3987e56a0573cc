#include "render/mustache_template.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <kainjow/mustache.hpp>
#include <memory>
#include <sstream>

#include "render/render_error.h"

namespace chatterlab::render {
namespace {

namespace mustache = kainjow::mustache;

mustache::data to_data(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::object: {
      mustache::data obj{mustache::data::type::object};
      for (const auto& [key, value] : j.items()) obj.set(key, to_data(value));
      return obj;
    }
    case nlohmann::json::value_t::array: {
      mustache::data list{mustache::data::type::list};
      for (const auto& value : j) list.push_back(to_data(value));
      return list;
    }
    case nlohmann::json::value_t::string:
      return mustache::data{j.get_ref<const std::string&>()};
    case nlohmann::json::value_t::boolean:
      return mustache::data{j.get<bool>()};
    case nlohmann::json::value_t::number_integer:
      return mustache::data{std::to_string(j.get<std::int64_t>())};
    case nlohmann::json::value_t::number_unsigned:
      return mustache::data{std::to_string(j.get<std::uint64_t>())};
    case nlohmann::json::value_t::number_float:
      return mustache::data{format_number(j.get<double>())};
    case nlohmann::json::value_t::null:
    case nlohmann::json::value_t::binary:
    case nlohmann::json::value_t::discarded:
      break;
  }
  return mustache::data{false};
}

// Resolves `{{> name}}` from the given partials, then from files, and refuses unknown
// names: a missing partial is a broken report, not an empty string.
class PartialContext : public mustache::context<std::string> {
 public:
  PartialContext(const mustache::data* data, const Partials& partials,
                 std::filesystem::path partial_dir)
      : mustache::context<std::string>(data), partials_(partials), dir_(std::move(partial_dir)) {}

  const mustache::data* get_partial(const std::string& name) const override {
    auto cached = loaded_.find(name);
    if (cached != loaded_.end()) return cached->second.get();
    std::string text;
    if (auto it = partials_.find(name); it != partials_.end()) {
      text = it->second;
    } else if (!dir_.empty() && std::filesystem::is_regular_file(dir_ / (name + ".mustache"))) {
      text = read_text_file(dir_ / (name + ".mustache"));
    } else if (!dir_.empty() && std::filesystem::is_regular_file(dir_ / name)) {
      text = read_text_file(dir_ / name);
    } else {
      throw RenderError("template partial '" + name + "' not found" +
                        (dir_.empty() ? std::string() : " (looked in " + dir_.string() + ")"));
    }
    return loaded_.emplace(name, std::make_unique<mustache::data>(text)).first->second.get();
  }

 private:
  const Partials& partials_;
  std::filesystem::path dir_;
  mutable std::map<std::string, std::unique_ptr<mustache::data>> loaded_;
};

}  // namespace

std::string format_number(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  std::array<char, 40> buffer{};
  if (std::fabs(value) < 1e15 && value == std::trunc(value)) {
    std::snprintf(buffer.data(), buffer.size(), "%.0f", value == 0.0 ? 0.0 : value);
  } else {
    std::snprintf(buffer.data(), buffer.size(), "%.6g", value);
  }
  return buffer.data();
}

std::string read_text_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RenderError("cannot read " + path.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string render_template(const std::string& mustache_text, const nlohmann::json& context,
                            const Partials& partials, const std::filesystem::path& partial_dir) {
  mustache::mustache tmpl{mustache_text};
  if (!tmpl.is_valid()) throw RenderError("template error: " + tmpl.error_message());
  const mustache::data data = to_data(context);
  PartialContext ctx{&data, partials, partial_dir};
  std::string out = tmpl.render(ctx);
  if (!tmpl.is_valid()) throw RenderError("template error: " + tmpl.error_message());
  return out;
}

std::string render_template_file(const std::filesystem::path& path, const nlohmann::json& context,
                                 const Partials& partials) {
  const std::string text = read_text_file(path);
  try {
    return render_template(text, context, partials, path.parent_path());
  } catch (const RenderError& e) {
    throw RenderError(path.string() + ": " + e.what());
  }
}

}  // namespace chatterlab::render
