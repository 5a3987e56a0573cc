// Step summaries and errors shared by every analysis step (CONVENTIONS.md: a summary's
// default state is "not run", so a step that did not run can never look like a success).
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

// What became of a step.
enum class StepStatus { kNotRun, kOk, kFailed };

// "not run", "ok", "failed".
const char* to_string(StepStatus s);

// Result status of one analysis step (Ceres Solver::Summary style): its status, a brief report
// (one line: why it failed, or "ok") and a full report (the brief, the details a step adds,
// and its warnings). Default-constructed: not run.
struct StepSummary {
  StepStatus status = StepStatus::kNotRun;
  std::string message = "not run";    // brief report
  std::string details;                // further lines for the full report (may be empty)
  std::vector<std::string> warnings;  // things a reader should know even when ok

  bool ok() const { return status == StepStatus::kOk; }
  bool ran() const { return status != StepStatus::kNotRun; }
  bool failed() const { return status == StepStatus::kFailed; }

  void succeed() {
    status = StepStatus::kOk;
    message = "ok";
  }
  void fail(std::string why, std::string more = "") {
    status = StepStatus::kFailed;
    message = std::move(why);
    details = std::move(more);
  }

  const std::string& brief_report() const { return message; }
  // "<status>: <brief>", then the details and one "warning: ..." line per warning.
  std::string full_report() const;
};

}  // namespace chatterlab
