// The one error type of the render layer: a figure, template or document could not be made.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace chatterlab::render {

// Thrown for bad figure input (the message names the field, its value and the rule), a
// template that does not parse, and an external tool (gnuplot, WeasyPrint) that is missing
// or fails (the message names the file and quotes the tool's stderr).
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A value as the messages show it (an ostream's default: 6 significant digits).
inline std::string message_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace chatterlab::render
