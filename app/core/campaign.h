// The campaign folder of EXPERIMENT_FORMAT.md section 1: campaign.yaml, recursive test.yaml
// discovery, and the typed, validated description of every test.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/common/check.h"

namespace chatterlab::app {

namespace fs = std::filesystem;

struct ToolSpec {
  int teeth = 0;
  double radius_m = 0.0;
  std::optional<double> helix_deg;
};

// The column that feeds a channel (test.yaml `channels.<name>.column`): the header text of a
// column, or its 0-based index (counting every column, a time column too).
struct ColumnRef {
  std::string header;  // used when index < 0
  int index = -1;
  bool by_index() const { return index >= 0; }
};

struct ChannelSpec {
  double scale = 1.0;  // physical = scale * raw + offset
  double offset = 0.0;
  std::optional<double> threshold;  // pulse channels (tach, zero): rising-edge threshold
  std::optional<ColumnRef> column;  // absent: the column whose header is the channel's name
  // EXPERIMENT_FORMAT.md section 1: .uff/.unv `record` (1-based dataset 58 order in the file);
  // .mat `variable` (a vector, or with `column` the 0-based column of a matrix).
  std::optional<int> record;
  std::optional<std::string> variable;
};

struct DataSpec {
  fs::path file;                      // absolute path, checked by check_input_file (empty: refused)
  std::string relative_file;          // as written in test.yaml
  std::vector<std::string> channels;  // required for raw binary files
  // Delimited text (CSV) dialect, EXPERIMENT_FORMAT.md section 1.
  char delimiter = 0;  // ',', ';' or '\t'; 0: detected from the header and the first rows
  char decimal = '.';  // '.' or ','
  int skip_lines = 0;  // lines before the header row
  // test.yaml's sample_rate_hz, checked against the rate a file states (UFF dx); 0: unchecked.
  double sample_rate_hz = 0.0;
};

// A kind's own test.yaml keys, parsed (TapSpec, CutSpec, ...: each kind derives its own).
struct KindSpec {
  virtual ~KindSpec() = default;
};

struct TestSpec {
  std::string id;  // folder relative to campaign root, '/' separated
  fs::path folder;
  fs::path campaign_root;  // every file the test names lies inside (app/core/input_boundary.h)
  std::string yaml_label;  // "<id>/test.yaml", used in messages
  std::string kind;
  double sample_rate_hz = 0.0;
  DataSpec data;
  std::map<std::string, ChannelSpec> channels;
  std::map<std::string, double> reference;
  // The kind's own keys (TestKind::parse; always set once the kind is known, even when the
  // keys had errors). Shared: specs are copied with their campaign and never changed after
  // loading.
  std::shared_ptr<const KindSpec> params;

  std::vector<std::string> errors;    // any error makes the test unusable
  std::vector<std::string> warnings;  // ignored keys and the like
  bool usable() const { return errors.empty(); }

  // Calibration of `name` (defaults when test.yaml names none).
  ChannelSpec channel(const std::string& name) const;

  // "<id>/<file>" for a file of the test given relative to its folder ("<file>" for a test at
  // the campaign root): how messages and the report name it.
  std::string file_label(const std::string& relative_file) const {
    return (id.empty() ? "" : id + "/") + relative_file;
  }
  // The label of the test's data file.
  std::string data_label() const { return file_label(data.relative_file); }

  // The kind's keys as its own type. A spec of another type is a broken invariant (the kind
  // asked for another kind's keys): an InvariantError, an internal error.
  template <class T>
  const T& kind_spec() const {
    const T* p = dynamic_cast<const T*>(params.get());
    CHATTERLAB_CHECK(p != nullptr, yaml_label + ": the test's keys are not of kind " + kind);
    return *p;
  }
};

struct CampaignSpec {
  fs::path root;
  // The root is a folder and its campaign.yaml a file the input boundary accepts (whether or
  // not its YAML then parses): false, `errors` says why, and nothing below the root was read.
  bool campaign_yaml_found = false;
  std::string name;
  std::string description;
  std::optional<ToolSpec> tool;
  std::string workpiece;
  std::string machine;
  bool has_truth = false;
  fs::path truth_file;
  // campaign.yaml blocks owned by kinds (TestKind::campaign_blocks, e.g. the cut kind's
  // `estimation:`), parsed by their kind, defaults when absent. Their errors do not stop the
  // campaign: the steps that use a block fail with them and everything else runs.
  std::map<std::string, std::shared_ptr<const KindSpec>> blocks;
  std::map<std::string, std::vector<std::string>> block_errors;

  std::vector<TestSpec> tests;      // sorted by id
  std::vector<std::string> errors;  // campaign-level: the campaign cannot be run
  std::vector<std::string> warnings;

  // Block `key` as its kind's type; nullptr when absent or of another type.
  template <class T>
  const T* block(const std::string& key) const {
    const auto it = blocks.find(key);
    return it == blocks.end() ? nullptr : dynamic_cast<const T*>(it->second.get());
  }
  // The problems of block `key` (empty when it is fine).
  const std::vector<std::string>& errors_of_block(const std::string& key) const;
};

class KindRegistry;
const KindRegistry& builtin_kinds();

// Reads campaign.yaml and every test.yaml below `root`, each test's own keys through its kind
// in `kinds`. Never throws for bad content: problems are collected in the specs (campaign
// errors, or per-test errors).
CampaignSpec load_campaign(const fs::path& root, const KindRegistry& kinds = builtin_kinds());

// Parses one test.yaml (exposed for tests).
TestSpec load_test(const fs::path& campaign_root, const fs::path& test_yaml,
                   const KindRegistry& kinds = builtin_kinds());

}  // namespace chatterlab::app
