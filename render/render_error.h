// The one error type of the render layer: a figure, template or document could not be made.
#pragma once

#include <stdexcept>

namespace chatterlab::render {

// Thrown for bad figure input (the message names the field, its value and the rule), a
// template that does not parse, and an external tool (gnuplot, WeasyPrint) that is missing
// or fails (the message names the file and quotes the tool's stderr).
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace chatterlab::render
