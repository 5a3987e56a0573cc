#include "app/validate.h"

#include <iomanip>

#include "analysis/common/summary.h"
#include "app/signals.h"

namespace chatterlab::app {

std::vector<std::string> required_channels(const TestSpec& t) {
  if (t.kind == "tap") return {"force", "response"};
  if (t.kind == "cut") return {"x", "y", "tach"};
  if (t.kind == "dyno-slot") return {"Fx", "Fy", "zero"};
  return {};
}

void check_signals(TestSpec& t) {
  if (!t.usable()) return;
  const std::string label = (t.id.empty() ? "" : t.id + "/") + t.data.relative_file;
  try {
    const SignalTable table = SignalTable::open(t.data, label);
    for (const auto& name : required_channels(t)) {
      if (!table.has(name)) {
        std::string have;
        for (const auto& n : table.names()) have += (have.empty() ? "" : ", ") + n;
        t.errors.push_back(label + ": channel '" + name + "' is required for a " + t.kind +
                           " test (channels: " + have + ")");
      }
    }
    const double duration = static_cast<double>(table.samples()) / t.sample_rate_hz;
    if (t.cut && t.cut->cut_window_s.second > duration * 1.0001) {
      t.errors.push_back(t.yaml_label + ": key 'cut_window_s' ends at " +
                         std::to_string(t.cut->cut_window_s.second) + " s, after the record (" +
                         std::to_string(duration) + " s)");
    }
  } catch (const InputError& e) {
    t.errors.push_back(e.what());
  }
}

int validate_campaign(CampaignSpec& c, std::ostream& out) {
  out << "campaign " << (c.name.empty() ? "(unnamed)" : c.name) << " at " << c.root.string()
      << "\n";
  for (const auto& e : c.errors) out << "  error: " << e << "\n";
  for (const auto& w : c.warnings) out << "  warning: " << w << "\n";
  int unusable = 0;
  for (auto& t : c.tests) {
    check_signals(t);
    out << "  " << std::left << std::setw(9) << (t.usable() ? "ok" : "UNUSABLE") << std::setw(28)
        << (t.id.empty() ? "." : t.id) << (t.kind.empty() ? "?" : t.kind) << "\n";
    for (const auto& e : t.errors) out << "      error: " << e << "\n";
    for (const auto& w : t.warnings) out << "      warning: " << w << "\n";
    if (!t.usable()) ++unusable;
  }
  out << c.tests.size() << " tests found, " << (c.tests.size() - static_cast<size_t>(unusable))
      << " usable, " << unusable << " unusable\n";
  if (c.tests.empty() && c.errors.empty()) out << "  warning: no test.yaml found below the root\n";
  return (!c.errors.empty() || unusable > 0) ? 1 : 0;
}

}  // namespace chatterlab::app
