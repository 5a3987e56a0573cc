// The campaign folder of EXPERIMENT_FORMAT.md section 1: campaign.yaml, recursive test.yaml
// discovery, and the typed, validated description of every test.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "app/estimation_options.h"

namespace chatterlab::app {

namespace fs = std::filesystem;

struct ToolSpec {
  int teeth = 0;
  double radius_m = 0.0;
  std::optional<double> helix_deg;
};

struct ChannelSpec {
  double scale = 1.0;  // physical = scale * raw + offset
  double offset = 0.0;
  std::optional<double> threshold;  // pulse channels (tach, zero): rising-edge threshold
};

struct DataSpec {
  fs::path file;                      // absolute path
  std::string relative_file;          // as written in test.yaml
  std::vector<std::string> channels;  // required for raw binary files
};

struct TapSpec {
  std::string axis;      // "x" or "y"
  std::string response;  // acceleration | velocity | displacement
  bool hits_auto = true;
  std::vector<std::pair<double, double>> hit_windows_s;
  std::optional<std::pair<double, double>> band_hz;
  int modes = 0;  // 0: automatic
};

struct CutSpec {
  std::string operation;  // up-milling | down-milling
  double spindle_rpm = 0.0;
  double feed_per_tooth_m = 0.0;
  double radial_immersion_m = 0.0;
  std::pair<double, double> axial_depth_m{0.0, 0.0};  // start, end of cut window
  std::pair<double, double> cut_window_s{0.0, 0.0};
  std::optional<std::pair<double, double>> air_window_s;
  double sensor_to_tip = 1.0;
  // Optional: the part of the record the estimators run over (docs/identification.md).
  std::optional<std::pair<double, double>> estimation_window_s;
};

struct DynoSlotSpec {
  double spindle_rpm = 0.0;
  double feed_per_tooth_m = 0.0;
  double axial_depth_m = 0.0;
};

struct TestSpec {
  std::string id;  // folder relative to campaign root, '/' separated
  fs::path folder;
  std::string yaml_label;  // "<id>/test.yaml", used in messages
  std::string kind;
  double sample_rate_hz = 0.0;
  DataSpec data;
  std::map<std::string, ChannelSpec> channels;
  std::map<std::string, double> reference;
  std::optional<TapSpec> tap;
  std::optional<CutSpec> cut;
  std::optional<DynoSlotSpec> dyno;

  std::vector<std::string> errors;    // any error makes the test unusable
  std::vector<std::string> warnings;  // ignored keys and the like
  bool usable() const { return errors.empty(); }

  // Calibration of `name` (defaults when test.yaml names none).
  ChannelSpec channel(const std::string& name) const;
};

struct CampaignSpec {
  fs::path root;
  std::string name;
  std::string description;
  std::optional<ToolSpec> tool;
  std::string workpiece;
  std::string machine;
  bool has_truth = false;
  fs::path truth_file;
  // campaign.yaml `estimation:` (docs/formats.md). Its errors do not stop the campaign: the cut
  // tests' estimation step fails with them and everything else runs.
  EstimationOptions estimation;
  std::vector<std::string> estimation_errors;

  std::vector<TestSpec> tests;      // sorted by id
  std::vector<std::string> errors;  // campaign-level: the campaign cannot be run
  std::vector<std::string> warnings;
};

// Reads campaign.yaml and every test.yaml below `root`. Never throws for bad content:
// problems are collected in the specs (campaign errors, or per-test errors).
CampaignSpec load_campaign(const fs::path& root);

// Parses one test.yaml (exposed for tests).
TestSpec load_test(const fs::path& campaign_root, const fs::path& test_yaml);

}  // namespace chatterlab::app
