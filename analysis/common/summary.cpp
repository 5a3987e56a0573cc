#include "analysis/common/summary.h"

namespace chatterlab {

const char* to_string(StepStatus s) {
  switch (s) {
    case StepStatus::kNotRun:
      return "not run";
    case StepStatus::kOk:
      return "ok";
    case StepStatus::kFailed:
      return "failed";
  }
  return "?";
}

std::string StepSummary::full_report() const {
  std::string r = std::string(to_string(status));
  if (status != StepStatus::kNotRun || message != "not run") r += ": " + message;
  if (!details.empty()) r += "\n" + details;
  for (const auto& w : warnings) r += "\nwarning: " + w;
  return r;
}

}  // namespace chatterlab
