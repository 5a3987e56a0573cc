#include "app/core/campaign.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <set>

#include "app/core/input_boundary.h"
#include "app/core/signals.h"
#include "app/core/utf8.h"
#include "app/core/yaml_load.h"
#include "app/core/yaml_reader.h"
#include "app/pipeline/registry.h"

namespace chatterlab::app {
namespace {

constexpr double kMm = 1e-3;
const char* kCampaignFormat = "chatterlab-campaign/1";
// tool.teeth: a milling tool, a slitting saw at most (docs/format/campaign.md).
constexpr long kMaxTeeth = 500;

YAML::Node load_yaml(const fs::path& file, const std::string& label,
                     std::vector<std::string>* errors) {
  // Size, non-scalar and duplicate keys, depth: the whole file is refused (app/core/yaml_load.h).
  // An unusable file gives an undefined node (`!node`): its reasons are the messages, with no
  // follow-on "key 'kind' must be a string, got null".
  YAML::Node n = load_yaml_file(file, label, errors);
  if (!n) return n;
  if (!n.IsMap()) {
    errors->push_back(label + ": must be a YAML mapping of keys");
    return YAML::Node(YAML::NodeType::Undefined);
  }
  return n;
}

// channels.<name>.column: a header text, or a 0-based index written as a plain integer.
std::optional<ColumnRef> read_column(const YAML::Node& n, YamlReader& r, const std::string& key) {
  if (!n) return std::nullopt;
  const std::string what = "must be the header text of a column or its 0-based index";
  if (!n.IsScalar() || n.Scalar().empty()) {
    r.error(key, what);
    return std::nullopt;
  }
  const std::string& text = n.Scalar();
  ColumnRef c;
  if (n.Tag() == "!") {  // quoted: always header text
    c.header = text;
    return c;
  }
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end && *end == '\0') {  // a number: an index
    if (!(v >= 0) || v != std::floor(v) || v > 1e6) {
      r.error(key, what + ", got '" + text + "'");
      return std::nullopt;
    }
    c.index = static_cast<int>(v);
    return c;
  }
  c.header = text;
  return c;
}

// data.delimiter, data.decimal and data.skip_lines (delimited text files only).
void read_dialect(const YAML::Node& data, YamlReader& r, DataSpec& d, bool text) {
  if (const auto s = r.optional_string(data, "delimiter", "data")) {
    if (*s == "," || *s == ";") {
      d.delimiter = (*s)[0];
    } else if (*s == "\t" || *s == "tab" || *s == "\\t") {
      d.delimiter = '\t';
    } else {
      r.error("data.delimiter", "must be \",\", \";\" or tab, got '" + *s + "'");
    }
  }
  if (const auto s = r.optional_string(data, "decimal", "data")) {
    if (*s == "." || *s == ",") {
      d.decimal = (*s)[0];
    } else {
      r.error("data.decimal", "must be \".\" or \",\", got '" + *s + "'");
    }
  }
  if (d.delimiter == ',' && d.decimal == ',') {
    r.error("data.decimal",
            "\",\" needs data.delimiter \";\" or tab (the cells are split at \",\")");
  }
  if (const auto n = r.optional_double(data, "skip_lines", "data")) {
    if (!(*n >= 0) || *n != std::floor(*n) || *n > 1e6) {
      r.error("data.skip_lines", "must be a whole number >= 0 (lines before the header row)");
    } else {
      d.skip_lines = static_cast<int>(*n);
    }
  }
  if (!text) {
    for (const char* k : {"delimiter", "decimal", "skip_lines"}) {
      if (data[k])
        r.warn(std::string("data.") + k,
               "applies to text files and is ignored for a raw binary file");
    }
  }
}

void read_channels(const YAML::Node& root, YamlReader& r, TestSpec& t) {
  const YAML::Node ch = root["channels"];
  if (!ch) return;
  if (!ch.IsMap()) {
    r.error("channels", "must be a mapping of channel names");
    return;
  }
  for (const auto& kv : ch) {
    if (!is_name_key(kv.first)) {
      r.error("channels", "has a key that is not a channel name");
      continue;
    }
    const auto name = kv.first.Scalar();
    const std::string path = "channels." + name;
    ChannelSpec c;
    if (!kv.second.IsMap()) {
      r.error(path, "must be a mapping such as {scale: 1.0, offset: 0.0}");
      continue;
    }
    r.check_keys(kv.second, {"scale", "offset", "threshold", "column", "record", "variable"}, path);
    c.scale = r.optional_double(kv.second, "scale", path).value_or(1.0);
    c.offset = r.optional_double(kv.second, "offset", path).value_or(0.0);
    c.threshold = r.optional_double(kv.second, "threshold", path);
    c.column = read_column(kv.second["column"], r, path + ".column");
    if (const auto rec = r.optional_double(kv.second, "record", path)) {
      if (!(*rec >= 1) || *rec != std::floor(*rec) || *rec > 1e6) {
        r.error(path + ".record", "must be a whole number >= 1 (1-based dataset 58 record)");
      } else {
        c.record = static_cast<int>(*rec);
      }
    }
    c.variable = r.optional_string(kv.second, "variable", path);
    if (c.record && (c.column || c.variable)) {
      r.error(path + ".record", "names the record alone: drop column and variable");
    }
    t.channels[name] = c;
  }
}

}  // namespace

const std::vector<std::string>& CampaignSpec::errors_of_block(const std::string& key) const {
  static const std::vector<std::string> kNone;
  const auto it = block_errors.find(key);
  return it == block_errors.end() ? kNone : it->second;
}

ChannelSpec TestSpec::channel(const std::string& name) const {
  const auto it = channels.find(name);
  return it == channels.end() ? ChannelSpec{} : it->second;
}

TestSpec load_test(const fs::path& campaign_root, const fs::path& test_yaml,
                   const KindRegistry& kinds) {
  TestSpec t;
  t.folder = test_yaml.parent_path();
  t.campaign_root = campaign_root;
  t.id = fs::relative(t.folder, campaign_root).generic_string();
  if (t.id == ".") t.id = "";
  // results.json, results.csv and the report are UTF-8: a folder named in another encoding
  // (Latin-1 on an old share) is a test with an error, shown with U+FFFD for each bad byte.
  const bool utf8_id = valid_utf8(t.id);
  if (!utf8_id) t.id = utf8_replaced(t.id);
  t.yaml_label = (t.id.empty() ? "" : t.id + "/") + "test.yaml";
  if (!utf8_id) {
    t.errors.push_back(t.yaml_label +
                       ": the folder's name is not valid UTF-8 (shown with U+FFFD for each bad "
                       "byte); rename the folder in UTF-8");
    return t;
  }
  const YAML::Node root = load_yaml(test_yaml, t.yaml_label, &t.errors);
  if (!root) return t;

  YamlReader r(t.yaml_label);
  t.kind = r.required_string(root, "kind");
  std::set<std::string> known = {"kind", "sample_rate_hz", "data", "channels", "reference"};
  // A tap test from a measured FRF (`frf:`, no `data`) has no time record: neither data nor
  // sample_rate_hz is required (the tap kind's parse refuses hits or data beside frf).
  const bool frf_input = t.kind == "tap" && root["frf"] && !root["data"];
  const bool has_rate = !frf_input || root["sample_rate_hz"];
  if (has_rate) t.sample_rate_hz = r.required_double(root, "sample_rate_hz");
  if (has_rate && !(t.sample_rate_hz > 0)) {
    if (!std::isnan(t.sample_rate_hz)) {
      r.error("sample_rate_hz", "= " + std::to_string(t.sample_rate_hz) + ": must be > 0");
    }
  }

  const YAML::Node data = root["data"];
  if (!data) {
    if (!frf_input) r.error("data", "is missing");
  } else if (!data.IsMap()) {
    r.error("data", "must be a mapping such as {file: signals.f32, channels: [x, y, tach]}");
  } else {
    r.check_keys(data, {"file", "channels", "delimiter", "decimal", "skip_lines"}, "data");
    t.data.relative_file = r.required_string(data, "file", "data");
    t.data.channels = r.string_list(data, "channels", false, "data");
    const auto ext = fs::path(t.data.relative_file).extension().string();
    const bool raw = ext == ".f32" || ext == ".f64";
    read_dialect(data, r, t.data, !raw);
    t.data.sample_rate_hz = t.sample_rate_hz > 0 ? t.sample_rate_hz : 0.0;
    if (!t.data.relative_file.empty()) {
      if (raw) {
        if (t.data.channels.empty()) r.error("data.channels", "is required for a raw binary file");
      } else if (!is_signal_file(fs::path(t.data.relative_file))) {
        r.error("data.file", "'" + t.data.relative_file +
                                 "': unsupported signal format (use text .csv, .txt, .tsv, .lvm, "
                                 "raw .f32, .f64, UFF .uff, .unv or MATLAB .mat)");
      }
      // The input boundary: inside the campaign, a regular file (nothing opened before).
      const InputFileCheck file = check_input_file(campaign_root, t.folder, t.data.relative_file);
      if (file.ok()) {
        t.data.file = file.path;
      } else {
        r.error("data.file", file.problem);
      }
    }
  }
  read_channels(root, r, t);
  const TestKind* kind = kinds.find(t.kind);
  if (const YAML::Node ref = root["reference"]; ref && ref.IsMap()) {
    const std::vector<std::string> blocks =
        kind ? kind->reference_blocks() : std::vector<std::string>{};
    for (const auto& kv : ref) {
      if (!is_name_key(kv.first)) continue;  // refused by load_yaml_file already
      const std::string key = kv.first.Scalar();
      if (std::find(blocks.begin(), blocks.end(), key) != blocks.end()) continue;  // the kind's
      double v = 0;
      if (kv.second.IsScalar() && YAML::convert<double>::decode(kv.second, v) && std::isfinite(v)) {
        t.reference[key] = v;
      } else {
        r.warn("reference." + key, "is not a finite number and is ignored");
      }
    }
  }

  if (kind) {
    t.params = kind->parse(root, r);
    for (const auto& k : kind->keys()) known.insert(k);
  } else if (!t.kind.empty()) {
    r.error("kind", "'" + t.kind + "' is not a known test kind (" + kinds.names() + ")");
  }
  r.check_keys(root, known);
  t.errors.insert(t.errors.end(), r.errors().begin(), r.errors().end());
  t.warnings.insert(t.warnings.end(), r.warnings().begin(), r.warnings().end());
  return t;
}

CampaignSpec load_campaign(const fs::path& root_in, const KindRegistry& kinds) {
  CampaignSpec c;
  c.root = fs::absolute(root_in).lexically_normal();
  const fs::path yaml = c.root / "campaign.yaml";
  std::error_code root_ec;  // status errors (a symlink loop) are problems, not exceptions
  if (!fs::is_directory(c.root, root_ec)) {
    c.errors.push_back(root_in.string() + ": not a folder");
    return c;
  }
  if (fs::symlink_status(yaml, root_ec).type() == fs::file_type::not_found) {
    c.errors.push_back("campaign.yaml: file not found in " + c.root.string());
    return c;
  }
  // campaign.yaml, truth.yaml and every test.yaml are inside the input boundary like the files
  // a test names: a regular file, a symlink only when it stays inside the campaign.
  if (const InputFileCheck own = check_input_file(c.root, c.root, "campaign.yaml"); !own.ok()) {
    c.errors.push_back("campaign.yaml: " + own.reason());
    return c;
  }
  c.campaign_yaml_found = true;
  const YAML::Node root = load_yaml(yaml, "campaign.yaml", &c.errors);
  if (root) {
    YamlReader r("campaign.yaml");
    std::set<std::string> known = {"format", "name", "description", "tool", "workpiece", "machine"};
    for (const auto& k : kinds.kinds()) {
      for (const auto& b : k->campaign_blocks()) known.insert(b);
    }
    r.check_keys(root, known);
    const auto format = r.required_string(root, "format");
    if (!format.empty() && format != kCampaignFormat) {
      r.error("format", "'" + format + "': must be '" + kCampaignFormat + "'");
    }
    c.name = r.required_string(root, "name");
    const bool name_ok = std::all_of(c.name.begin(), c.name.end(), [](char ch) {
      return std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '_' || ch == '-';
    });
    if (!c.name.empty() && !name_ok) {
      r.error("name", "'" + c.name + "': must match [A-Za-z0-9._-]+");
    }
    c.description = r.optional_string(root, "description").value_or("");
    c.workpiece = r.optional_string(root, "workpiece").value_or("");
    c.machine = r.optional_string(root, "machine").value_or("");
    if (const YAML::Node tool = root["tool"]; tool) {
      if (!tool.IsMap()) {
        r.error("tool", "must be a mapping {teeth, radius_mm, helix_deg}");
      } else {
        r.check_keys(tool, {"teeth", "radius_mm", "helix_deg"}, "tool");
        ToolSpec ts;
        ts.teeth =
            static_cast<int>(r.required_int(tool, "teeth", "tool", 1, kMaxTeeth).value_or(0));
        ts.radius_m = r.required_double(tool, "radius_mm", "tool") * kMm;
        if (!(ts.radius_m > 0) && !std::isnan(ts.radius_m))
          r.error("tool.radius_mm", "must be > 0");
        ts.helix_deg = r.optional_double(tool, "helix_deg", "tool");
        if (r.errors().empty()) c.tool = ts;
      }
    }
    c.errors.insert(c.errors.end(), r.errors().begin(), r.errors().end());
    c.warnings.insert(c.warnings.end(), r.warnings().begin(), r.warnings().end());
  }
  // Kinds' blocks, defaults when absent (or when campaign.yaml could not be read).
  for (const auto& k : kinds.kinds()) {
    for (const auto& b : k->campaign_blocks()) {
      YamlReader br("campaign.yaml");
      const YAML::Node node = root ? root[b] : YAML::Node(YAML::NodeType::Undefined);
      c.blocks[b] = k->parse_campaign_block(b, node, br);
      if (!br.errors().empty()) c.block_errors[b] = br.errors();
      c.warnings.insert(c.warnings.end(), br.warnings().begin(), br.warnings().end());
    }
  }
  c.truth_file = c.root / "truth.yaml";
  std::error_code truth_ec;
  if (fs::symlink_status(c.truth_file, truth_ec).type() != fs::file_type::not_found) {
    const InputFileCheck truth = check_input_file(c.root, c.root, "truth.yaml");
    c.has_truth = truth.ok();
    if (!truth.ok()) {
      c.warnings.push_back("truth.yaml: " + truth.reason() +
                           "; not read (no comparison with the truth)");
    }
  }

  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(
           c.root, fs::directory_options::skip_permission_denied, ec);
       it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) break;
    if (it->path().filename() != "test.yaml") continue;
    // A test.yaml is read only when it is a regular file and, a symlink, stays inside the
    // campaign (the input boundary); anything else of that name (a folder, a FIFO, a link
    // leading out) is a test skipped with the reason.
    const fs::path folder = it->path().parent_path();
    const InputFileCheck check = check_input_file(c.root, folder, "test.yaml");
    if (check.ok()) {
      c.tests.push_back(load_test(c.root, it->path(), kinds));
      continue;
    }
    TestSpec t;
    t.folder = folder;
    t.campaign_root = c.root;
    t.id = t.folder.lexically_relative(c.root).generic_string();
    if (t.id == ".") t.id = "";
    t.yaml_label = (t.id.empty() ? "" : t.id + "/") + "test.yaml";
    t.errors.push_back(t.yaml_label + ": " + check.reason());
    c.tests.push_back(std::move(t));
  }
  std::sort(c.tests.begin(), c.tests.end(),
            [](const TestSpec& a, const TestSpec& b) { return a.id < b.id; });
  for (auto& t : c.tests) {
    if (const TestKind* kind = kinds.find(t.kind)) {
      for (auto& e : kind->check_campaign(c, t)) t.errors.push_back(std::move(e));
    }
  }
  return c;
}

}  // namespace chatterlab::app
