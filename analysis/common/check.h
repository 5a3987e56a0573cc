// Always-on invariant checks (CONVENTIONS.md): a broken internal invariant, one that would
// otherwise produce a wrong number, stops the step in every build type. The error is an
// InvariantError (a std::logic_error, not an InputError), which the pipeline reports as an
// internal error of the test: status `error`, exit status 3.
#pragma once

#include <stdexcept>
#include <string>

namespace chatterlab {

class InvariantError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

// Throws InvariantError "invariant '<condition>' broken at <file>:<line>: <what>" (the file
// without its folders).
[[noreturn]] void invariant_failed(const char* condition, const std::string& what, const char* file,
                                   int line);

}  // namespace chatterlab

#define CHATTERLAB_CHECK(condition, what)                                     \
  do {                                                                        \
    if (!(condition)) {                                                       \
      ::chatterlab::invariant_failed(#condition, (what), __FILE__, __LINE__); \
    }                                                                         \
  } while (false)
