// HTML from Mustache templates (kainjow mustache) and a JSON context (nlohmann json).
#pragma once

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace chatterlab::render {

// Partial templates by name: `{{> name}}` renders partials.at("name") in the current context.
using Partials = std::map<std::string, std::string>;

// Renders `mustache_text` with `context`. JSON maps to Mustache data as follows:
//   object -> object (dotted names `{{a.b}}` work), array -> list (a section repeats per
//   element, `{{.}}` is the element; an empty array is falsy),
//   string -> string (`{{x}}` HTML-escaped, `{{{x}}}` raw),
//   integer -> decimal digits, float -> format_number(), bool -> true/false (a variable
//   renders nothing), null -> false (falsy; a variable renders nothing).
// A partial that is neither in `partials` nor in `partial_dir` (when not empty: the file
// <partial_dir>/<name>.mustache, else <partial_dir>/<name>) throws, as does a template
// that does not parse. Errors are RenderError with kainjow's message.
std::string render_template(const std::string& mustache_text, const nlohmann::json& context,
                            const Partials& partials = {},
                            const std::filesystem::path& partial_dir = {});

// Reads the template file and renders it; partials come from `partials` and the file's own
// folder. Errors name the file.
std::string render_template_file(const std::filesystem::path& path, const nlohmann::json& context,
                                 const Partials& partials = {});

// How a JSON float appears in a template: integral values below 1e15 without a decimal
// point (3.0 -> "3"), others with 6 significant digits (%.6g: 0.1 + 0.2 -> "0.3",
// 1234567.8 -> "1.23457e+06"), "NaN", "inf", "-inf". A table that wants a fixed precision
// puts a preformatted string in the context instead.
std::string format_number(double value);

// The whole text of a file; throws RenderError naming the file.
std::string read_text_file(const std::filesystem::path& path);

}  // namespace chatterlab::render
