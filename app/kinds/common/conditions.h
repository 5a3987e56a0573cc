// test.yaml keys that several kinds share (docs/formats.md).
#pragma once

#include <yaml-cpp/yaml.h>

#include <optional>
#include <string>
#include <utility>

#include "app/core/campaign.h"
#include "app/core/yaml_reader.h"

namespace chatterlab::app {

inline constexpr double kMm = 1e-3;  // m per mm (test.yaml lengths are in mm)

// spindle_rpm and feed_per_tooth_mm (cut and dyno-slot tests), both required and > 0.
void read_speed_and_feed(const YAML::Node& root, YamlReader& r, double* rpm, double* feed_m);

// The problem of a test that needs campaign.yaml's tool, when it has none.
std::optional<std::string> needs_tool(const CampaignSpec& c, const TestSpec& t);

// A [lo, hi] pair of seconds or hertz with 0 <= lo < hi; errors through r.
std::optional<std::pair<double, double>> read_interval(const YAML::Node& root, YamlReader& r,
                                                       const std::string& key, bool required);

// "<test.yaml>: key '<key>' ends at b s, after the record (c s)" when [lo, hi] ends after
// the record.
std::optional<std::string> window_outside(const TestSpec& t, const std::string& key, double hi,
                                          double duration_s);

}  // namespace chatterlab::app
