// Step summaries and errors shared by every analysis step (CONVENTIONS.md: a summary's
// default state is failure, so a step that did not run can never look like a success).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace chatterlab {

// Bad input or configuration: the message names the field, its value and the rule.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Result status of one analysis step. Default-constructed: not run.
struct StepSummary {
  bool ok = false;
  std::string message = "not run";    // short report: why it failed, or "ok"
  std::vector<std::string> warnings;  // things a reader should know even when ok

  void succeed() {
    ok = true;
    message = "ok";
  }
  void fail(std::string why) {
    ok = false;
    message = std::move(why);
  }
};

}  // namespace chatterlab
