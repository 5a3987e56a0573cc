#include "app/kinds/common/conditions.h"

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

}  // namespace chatterlab::app
