// The `hits` key of hammer tests whose record keeps each hit with its bounce (sifs-tap,
// format section 6; dyno-frf, format section 4): `auto` or a list of [start_s, end_s]
// windows, and the equal-length sample windows the FRF step takes.
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "analysis/sifs/sensor_model.h"
#include "app/core/campaign.h"
#include "app/core/yaml_reader.h"

namespace chatterlab::app {

struct HammerHits {
  bool automatic = false;
  std::vector<std::pair<double, double>> windows_s;  // [start, end] s, as written
};

// Reads the required key `hits`; errors through r.
HammerHits read_hammer_hits(const YAML::Node& root, YamlReader& r);

// The windows that end after the record, one message each naming the key.
std::vector<std::string> hammer_hits_outside(const TestSpec& t, const HammerHits& hits,
                                             double duration_s);

// The sample windows of the record: automatic (sifs::auto_tap_windows: bounces stay with their
// hit) or as written, every window the length of the shortest. Adds a warning when the windows
// are shorter than 0.1 s (a coarse FRF).
// @throws InputError naming t's test.yaml and key (`label`: the data file, for auto's errors)
std::vector<sifs::TapWindow> hammer_windows(const TestSpec& t, const HammerHits& hits,
                                            const Eigen::VectorXd& hammer_n,
                                            const std::string& label,
                                            std::vector<std::string>& warnings);

}  // namespace chatterlab::app
