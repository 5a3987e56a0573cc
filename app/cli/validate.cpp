#include "app/cli/validate.h"

#include <algorithm>
#include <iomanip>

#include "app/pipeline/pipeline.h"

namespace chatterlab::app {
namespace {

// The kinds format version 1 defines that this version reads but does not analyse
// (docs/format/test-kinds.md#kinds-of-the-contract-not-implemented-yet).
bool contract_kind_not_analysed(const std::string& kind) {
  static const char* const kinds[] = {"dyno-frf", "force-record", "frf", "sweep-frf",
                                      "spindle-current"};
  return std::find(std::begin(kinds), std::end(kinds), kind) != std::end(kinds) &&
         builtin_kinds().find(kind) == nullptr;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

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
  int unusable = 0, not_analysed = 0;
  for (auto& t : c.tests) {
    check_signals(t);
    std::vector<std::string> errors = t.errors, warnings = t.warnings;
    const bool later = contract_kind_not_analysed(t.kind);
    if (later) {
      // Not a problem of the campaign: the kind is part of the format. Its own keys are too,
      // so the loader's "not part of the format" warnings about them are dropped.
      const std::string unknown = "key 'kind' '" + t.kind + "' is not a known test kind";
      errors.erase(std::remove_if(errors.begin(), errors.end(),
                                  [&](const std::string& e) { return contains(e, unknown); }),
                   errors.end());
      warnings.erase(std::remove_if(warnings.begin(), warnings.end(),
                                    [](const std::string& w) {
                                      return contains(w,
                                                      "is not part of the format and is ignored");
                                    }),
                     warnings.end());
    }
    const bool usable = errors.empty();
    const char* status = !usable ? "UNUSABLE" : (later ? "-" : "ok");
    out << "  " << std::left << std::setw(9) << status << std::setw(28)
        << (t.id.empty() ? "." : t.id) << (t.kind.empty() ? "?" : t.kind)
        << (later ? " (not analysed by this version)" : "") << "\n";
    for (const auto& e : errors) out << "      error: " << e << "\n";
    for (const auto& w : warnings) out << "      warning: " << w << "\n";
    if (!usable) {
      ++unusable;
    } else if (later) {
      ++not_analysed;
    }
  }
  const int found = static_cast<int>(c.tests.size());
  out << found << " tests found, " << (found - unusable - not_analysed) << " usable, " << unusable
      << " unusable";
  if (not_analysed > 0) {
    out << ", " << not_analysed << " of a kind not analysed by this version (report skips "
        << (not_analysed == 1 ? "it" : "them") << ")";
  }
  out << "\n";
  if (c.tests.empty() && c.errors.empty()) out << "  warning: no test.yaml found below the root\n";
  return (!c.errors.empty() || block_errors > 0 || unusable > 0) ? 1 : 0;
}

}  // namespace chatterlab::app
