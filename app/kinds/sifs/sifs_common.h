// Shared pieces of the sifs kinds (app/kinds/sifs): key parsing and the record's calibrated
// forces.
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/sifs/calibration.h"
#include "analysis/sifs/compensator.h"
#include "app/core/campaign.h"
#include "app/core/signals.h"
#include "app/core/yaml_reader.h"
#include "app/kinds/common/conditions.h"

namespace chatterlab::app {

// The washer channel names of format section 6, in the column order of sifs::Washers.
inline const std::vector<std::string> kWasherChannels{"x1", "x2", "y1", "y2", "z1", "z2"};

// `axis` (x | y | z, or x | y when !allow_z); an error through r otherwise.
sifs::Axis read_sifs_axis(const YAML::Node& root, YamlReader& r, bool allow_z);

// The washer channels of a record, calibrated by test.yaml (washer newtons).
sifs::Washers read_washers(const SignalTable& table, const TestSpec& t);

struct SifsTapData;

struct SifsCalibration;

// The calibration of test t at its tool length (SifsCalibration::at): an InputError names t's
// test.yaml; the note of a matrix from the tool-length law goes to warnings.
Eigen::Matrix3d calibration_for(const SifsCalibration& cal, const TestSpec& t,
                                const std::optional<double>& length_mm,
                                std::vector<std::string>& warnings);

// Optional `tool_length_mm` (> 0); errors through r.
std::optional<double> read_tool_length(const YAML::Node& root, YamlReader& r);

// The tap record of `tap` at `filter_rate_hz` (anti-aliased resampling when the rates differ)
// as the input of the tuning sweep (format step 4): windows and pre-impact ends mapped to the
// new rate (the pre-impact part ends 1 ms before each impact), with the tap's R.
sifs::TapSweepInput tap_sweep_input(const SifsTapData& tap, double filter_rate_hz,
                                    double band_lo_hz, double band_hi_hz, sifs::GainMode gain);

}  // namespace chatterlab::app
