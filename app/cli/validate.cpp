#include "app/cli/validate.h"

#include <algorithm>
#include <iomanip>

#include "app/pipeline/pipeline.h"

namespace chatterlab::app {

int validate_campaign(CampaignSpec& c, std::ostream& out) {
  out << "campaign " << (c.name.empty() ? "(unnamed)" : c.name) << " at " << c.root.string()
      << "\n";
  for (const auto& e : c.errors) out << "  error: " << e << "\n";
  int block_errors = 0;
  for (const auto& [block, errors] : c.block_errors) {
    for (const auto& e : errors) {
      out << "  error: " << e << " (the steps that use campaign.yaml '" << block
          << "' would be skipped)\n";
      ++block_errors;
    }
  }
  for (const auto& w : c.warnings) out << "  warning: " << w << "\n";
  int unusable = 0;
  for (auto& t : c.tests) {
    check_signals(t);
    const std::vector<std::string>& errors = t.errors;
    const std::vector<std::string>& warnings = t.warnings;
    const bool usable = errors.empty();
    const char* status = !usable ? "UNUSABLE" : "ok";
    // An id longer than its column keeps one space before the kind.
    out << "  " << std::left << std::setw(9) << status << std::setw(27)
        << (t.id.empty() ? "." : t.id) << ' ' << (t.kind.empty() ? "?" : t.kind) << "\n";
    for (const auto& e : errors) out << "      error: " << e << "\n";
    for (const auto& w : warnings) out << "      warning: " << w << "\n";
    if (!usable) ++unusable;
  }
  const int found = static_cast<int>(c.tests.size());
  out << found << " tests found, " << (found - unusable) << " usable, " << unusable
      << " unusable\n";
  if (c.tests.empty() && c.errors.empty()) out << "  warning: no test.yaml found below the root\n";
  return (!c.errors.empty() || block_errors > 0 || unusable > 0) ? 1 : 0;
}

}  // namespace chatterlab::app
