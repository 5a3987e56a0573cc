#include "app/kinds/common/conditions.h"

#include "app/core/format.h"

namespace chatterlab::app {

void read_speed_and_feed(const YAML::Node& root, YamlReader& r, double* rpm, double* feed_m) {
  *rpm = r.required_double(root, "spindle_rpm");
  if (*rpm <= 0) r.error("spindle_rpm", "must be > 0");
  *feed_m = r.required_double(root, "feed_per_tooth_mm") * kMm;
  if (*feed_m <= 0) r.error("feed_per_tooth_mm", "must be > 0");
}

std::optional<std::string> needs_tool(const CampaignSpec& c, const TestSpec& t) {
  if (c.tool) return std::nullopt;
  return t.yaml_label + ": a " + t.kind + " test needs campaign.yaml key 'tool' (teeth, radius_mm)";
}

std::optional<std::pair<double, double>> read_interval(const YAML::Node& root, YamlReader& r,
                                                       const std::string& key, bool required) {
  if (!root[key]) {
    if (required) r.error(key, "is required: [start, end]");
    return std::nullopt;
  }
  const auto p = r.optional_pair(root, key);
  if (!p) return std::nullopt;
  if (!(p->first >= 0 && p->second > p->first)) {
    r.error(key, "must be [start, end] with 0 <= start < end, not [" + fmt_sig(p->first, 6) + ", " +
                     fmt_sig(p->second, 6) + "]");
    return std::nullopt;
  }
  return p;
}

std::optional<std::string> window_outside(const TestSpec& t, const std::string& key, double hi,
                                          double duration_s) {
  if (hi <= duration_s * 1.0001) return std::nullopt;
  return t.yaml_label + ": key '" + key + "' ends at " + fmt_sig(hi, 6) + " s, after the record (" +
         fmt_sig(duration_s, 6) + " s)";
}

}  // namespace chatterlab::app
