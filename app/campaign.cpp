#include "app/campaign.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>

#include "app/yaml_reader.h"

namespace chatterlab::app {
namespace {

constexpr double kMm = 1e-3;
const char* kCampaignFormat = "chatterlab-campaign/1";

YAML::Node load_yaml(const fs::path& file, const std::string& label,
                     std::vector<std::string>* errors) {
  try {
    YAML::Node n = YAML::LoadFile(file.string());
    if (!n.IsMap()) {
      errors->push_back(label + ": must be a YAML mapping of keys");
      return YAML::Node();
    }
    return n;
  } catch (const YAML::Exception& e) {
    errors->push_back(label + ": not valid YAML (" + e.what() + ")");
    return YAML::Node();
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
    const auto name = kv.first.as<std::string>();
    const std::string path = "channels." + name;
    ChannelSpec c;
    if (!kv.second.IsMap()) {
      r.error(path, "must be a mapping such as {scale: 1.0, offset: 0.0}");
      continue;
    }
    r.check_keys(kv.second, {"scale", "offset", "threshold"}, path);
    c.scale = r.optional_double(kv.second, "scale", path).value_or(1.0);
    c.offset = r.optional_double(kv.second, "offset", path).value_or(0.0);
    c.threshold = r.optional_double(kv.second, "threshold", path);
    t.channels[name] = c;
  }
}

void read_tap(const YAML::Node& root, YamlReader& r, TestSpec& t) {
  TapSpec s;
  s.axis = r.required_string(root, "axis");
  if (!s.axis.empty() && s.axis != "x" && s.axis != "y") {
    r.error("axis", "must be x or y, got '" + s.axis + "'");
  }
  s.response = r.required_string(root, "response");
  if (!s.response.empty() && s.response != "acceleration" && s.response != "velocity" &&
      s.response != "displacement") {
    r.error("response", "must be acceleration, velocity or displacement, got '" + s.response + "'");
  }
  const YAML::Node hits = root["hits"];
  if (hits && hits.IsScalar() && hits.Scalar() != "auto") {
    r.error("hits", "must be 'auto' or a list of [start_s, end_s], got '" + hits.Scalar() + "'");
  } else if (hits && hits.IsSequence()) {
    s.hits_auto = false;
    for (const auto& h : hits) {
      if (!h.IsSequence() || h.size() != 2) {
        r.error("hits", "each hit must be a list [start_s, end_s]");
        break;
      }
      try {
        const double a = h[0].as<double>(), b = h[1].as<double>();
        if (!(b > a)) r.error("hits", "each hit window needs end_s > start_s");
        s.hit_windows_s.emplace_back(a, b);
      } catch (const YAML::Exception&) {
        r.error("hits", "each hit must be a list of two numbers [start_s, end_s]");
        break;
      }
    }
  } else if (hits && !hits.IsScalar()) {
    r.error("hits", "must be 'auto' or a list of [start_s, end_s]");
  }
  s.band_hz = r.optional_pair(root, "band_hz");
  if (s.band_hz && !(s.band_hz->second > s.band_hz->first && s.band_hz->first >= 0)) {
    r.error("band_hz", "must be [low, high] with 0 <= low < high");
  }
  const YAML::Node modes = root["modes"];
  if (modes && !(modes.IsScalar() && modes.Scalar() == "auto")) {
    try {
      s.modes = modes.as<int>();
      if (s.modes < 1 || s.modes > 20) r.error("modes", "must be 'auto' or a number from 1 to 20");
    } catch (const YAML::Exception&) {
      r.error("modes", "must be 'auto' or a whole number of modes");
    }
  }
  t.tap = s;
}

// spindle_rpm and feed_per_tooth_mm, shared by cut and dyno-slot tests.
void read_speed_and_feed(const YAML::Node& root, YamlReader& r, double* rpm, double* feed_m) {
  *rpm = r.required_double(root, "spindle_rpm");
  if (*rpm <= 0) r.error("spindle_rpm", "must be > 0");
  *feed_m = r.required_double(root, "feed_per_tooth_mm") * kMm;
  if (*feed_m <= 0) r.error("feed_per_tooth_mm", "must be > 0");
}

void read_cut(const YAML::Node& root, YamlReader& r, TestSpec& t) {
  CutSpec s;
  s.operation = r.required_string(root, "operation");
  if (!s.operation.empty() && s.operation != "up-milling" && s.operation != "down-milling") {
    r.error("operation", "must be up-milling or down-milling, got '" + s.operation + "'");
  }
  read_speed_and_feed(root, r, &s.spindle_rpm, &s.feed_per_tooth_m);
  s.radial_immersion_m = r.required_double(root, "radial_immersion_mm") * kMm;
  if (s.radial_immersion_m <= 0) r.error("radial_immersion_mm", "must be > 0");
  if (auto d = r.optional_number_or_pair(root, "axial_depth_mm")) {
    s.axial_depth_m = {d->first * kMm, d->second * kMm};
    if (d->first < 0 || d->second < 0) r.error("axial_depth_mm", "must be >= 0");
  } else if (!root["axial_depth_mm"]) {
    r.error("axial_depth_mm", "is missing");
  }
  if (auto w = r.optional_pair(root, "cut_window_s")) {
    s.cut_window_s = *w;
    if (!(w->second > w->first)) r.error("cut_window_s", "must be [start, end] with end > start");
  } else if (!root["cut_window_s"]) {
    r.error("cut_window_s", "is missing");
  }
  s.air_window_s = r.optional_pair(root, "air_window_s");
  s.sensor_to_tip = r.optional_double(root, "sensor_to_tip").value_or(1.0);
  if (!(s.sensor_to_tip > 0)) r.error("sensor_to_tip", "must be > 0");
  s.estimation_window_s = r.optional_pair(root, "estimation_window_s");
  if (s.estimation_window_s) {
    const auto& [a, b] = *s.estimation_window_s;
    if (!(b > a) || a < s.cut_window_s.first || b > s.cut_window_s.second) {
      r.error("estimation_window_s", "must be [start, end] with end > start inside cut_window_s");
    }
  }
  t.cut = s;
}

void read_dyno(const YAML::Node& root, YamlReader& r, TestSpec& t) {
  DynoSlotSpec s;
  read_speed_and_feed(root, r, &s.spindle_rpm, &s.feed_per_tooth_m);
  s.axial_depth_m = r.required_double(root, "axial_depth_mm") * kMm;
  if (s.axial_depth_m <= 0) r.error("axial_depth_mm", "must be > 0");
  t.dyno = s;
}

// campaign.yaml `estimation:` (docs/formats.md): every key optional.
void read_estimation(const YAML::Node& e, YamlReader& r, EstimationOptions& o) {
  if (!e.IsMap()) {
    r.error("estimation", "must be a mapping (docs/formats.md)");
    return;
  }
  r.check_keys(e,
               {"window_s", "resample_step_s", "settle_revolutions", "max_passes", "repeat_runs",
                "repeat_spread", "seed"},
               "estimation");
  const auto positive = [&](const char* key, double& into) {
    if (const auto v = r.optional_double(e, key, "estimation")) {
      if (*v > 0 && std::isfinite(*v)) {
        into = *v;
      } else {
        r.error(std::string("estimation.") + key, "must be > 0");
      }
    }
  };
  const auto whole = [&](const char* key, double lowest) -> std::optional<double> {
    const auto v = r.optional_double(e, key, "estimation");
    if (v && !(*v >= lowest && *v == std::floor(*v) && *v < 1e9)) {
      r.error(std::string("estimation.") + key,
              "must be a whole number >= " + std::to_string(static_cast<int>(lowest)));
      return std::nullopt;
    }
    return v;
  };
  positive("window_s", o.window_s);
  positive("resample_step_s", o.resample_step_s);
  if (const auto v = r.optional_double(e, "settle_revolutions", "estimation")) {
    if (*v >= 0 && std::isfinite(*v)) {
      o.settle_revolutions = *v;
    } else {
      r.error("estimation.settle_revolutions", "must be >= 0");
    }
  }
  if (const auto v = whole("max_passes", 1)) o.max_passes = static_cast<int>(*v);
  if (const auto v = r.optional_double(e, "repeat_runs", "estimation")) {
    if (*v == 0 || (*v >= 2 && *v == std::floor(*v) && *v < 1e6)) {
      o.repeat.runs = static_cast<int>(*v);
    } else {
      r.error("estimation.repeat_runs", "must be 0 (no repeatability runs) or a whole number >= 2");
    }
  }
  if (const auto v = r.optional_double(e, "repeat_spread", "estimation")) {
    if (*v > 0 && *v < 1) {
      o.repeat.spread = *v;
    } else {
      r.error("estimation.repeat_spread", "must be in (0, 1)");
    }
  }
  if (const auto v = whole("seed", 0)) o.repeat.seed = static_cast<std::uint64_t>(*v);
}

}  // namespace

ChannelSpec TestSpec::channel(const std::string& name) const {
  const auto it = channels.find(name);
  return it == channels.end() ? ChannelSpec{} : it->second;
}

TestSpec load_test(const fs::path& campaign_root, const fs::path& test_yaml) {
  TestSpec t;
  t.folder = test_yaml.parent_path();
  t.id = fs::relative(t.folder, campaign_root).generic_string();
  if (t.id == ".") t.id = "";
  t.yaml_label = (t.id.empty() ? "" : t.id + "/") + "test.yaml";
  const YAML::Node root = load_yaml(test_yaml, t.yaml_label, &t.errors);
  if (!root) return t;

  YamlReader r(t.yaml_label);
  t.kind = r.required_string(root, "kind");
  std::set<std::string> known = {"kind", "sample_rate_hz", "data", "channels", "reference"};
  t.sample_rate_hz = r.required_double(root, "sample_rate_hz");
  if (!(t.sample_rate_hz > 0)) {
    if (!std::isnan(t.sample_rate_hz)) {
      r.error("sample_rate_hz", "= " + std::to_string(t.sample_rate_hz) + ": must be > 0");
    }
  }

  const YAML::Node data = root["data"];
  if (!data) {
    r.error("data", "is missing");
  } else if (!data.IsMap()) {
    r.error("data", "must be a mapping such as {file: signals.f32, channels: [x, y, tach]}");
  } else {
    r.check_keys(data, {"file", "channels"}, "data");
    t.data.relative_file = r.required_string(data, "file", "data");
    if (!t.data.relative_file.empty()) t.data.file = t.folder / t.data.relative_file;
    t.data.channels = r.string_list(data, "channels", false, "data");
    const auto ext = t.data.file.extension().string();
    if (!t.data.relative_file.empty()) {
      if (ext == ".f32" || ext == ".f64") {
        if (t.data.channels.empty()) r.error("data.channels", "is required for a raw binary file");
      } else if (ext != ".csv") {
        r.error("data.file", "'" + t.data.relative_file +
                                 "': unsupported signal format (use .csv, .f32 or .f64)");
      }
      if (!fs::exists(t.data.file)) {
        r.error("data.file", "'" + t.data.relative_file + "': file not found");
      }
    }
  }
  read_channels(root, r, t);
  if (const YAML::Node ref = root["reference"]; ref && ref.IsMap()) {
    for (const auto& kv : ref) {
      try {
        t.reference[kv.first.as<std::string>()] = kv.second.as<double>();
      } catch (const YAML::Exception&) {
        r.warn("reference." + kv.first.as<std::string>(), "is not a number and is ignored");
      }
    }
  }

  if (t.kind == "tap") {
    read_tap(root, r, t);
    known.insert({"axis", "response", "hits", "band_hz", "modes"});
  } else if (t.kind == "cut") {
    read_cut(root, r, t);
    known.insert({"operation", "spindle_rpm", "feed_per_tooth_mm", "radial_immersion_mm",
                  "axial_depth_mm", "cut_window_s", "air_window_s", "sensor_to_tip",
                  "estimation_window_s"});
  } else if (t.kind == "dyno-slot") {
    read_dyno(root, r, t);
    known.insert({"spindle_rpm", "feed_per_tooth_mm", "axial_depth_mm"});
  } else if (!t.kind.empty()) {
    r.error("kind", "'" + t.kind + "' is not a known test kind (tap, cut, dyno-slot)");
  }
  r.check_keys(root, known);
  t.errors.insert(t.errors.end(), r.errors().begin(), r.errors().end());
  t.warnings.insert(t.warnings.end(), r.warnings().begin(), r.warnings().end());
  return t;
}

CampaignSpec load_campaign(const fs::path& root_in) {
  CampaignSpec c;
  c.root = fs::absolute(root_in).lexically_normal();
  const fs::path yaml = c.root / "campaign.yaml";
  if (!fs::is_directory(c.root)) {
    c.errors.push_back(root_in.string() + ": not a folder");
    return c;
  }
  if (!fs::exists(yaml)) {
    c.errors.push_back("campaign.yaml: file not found in " + c.root.string());
    return c;
  }
  const YAML::Node root = load_yaml(yaml, "campaign.yaml", &c.errors);
  if (root) {
    YamlReader r("campaign.yaml");
    r.check_keys(root,
                 {"format", "name", "description", "tool", "workpiece", "machine", "estimation"});
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
        const double teeth = r.required_double(tool, "teeth", "tool");
        if (!(teeth >= 1) || teeth != std::floor(teeth)) {
          if (!std::isnan(teeth)) r.error("tool.teeth", "must be a whole number >= 1");
        }
        ts.teeth = std::isnan(teeth) ? 0 : static_cast<int>(teeth);
        ts.radius_m = r.required_double(tool, "radius_mm", "tool") * kMm;
        if (!(ts.radius_m > 0) && !std::isnan(ts.radius_m))
          r.error("tool.radius_mm", "must be > 0");
        ts.helix_deg = r.optional_double(tool, "helix_deg", "tool");
        if (r.errors().empty()) c.tool = ts;
      }
    }
    c.errors.insert(c.errors.end(), r.errors().begin(), r.errors().end());
    c.warnings.insert(c.warnings.end(), r.warnings().begin(), r.warnings().end());
    if (const YAML::Node e = root["estimation"]; e) {
      YamlReader er("campaign.yaml");
      read_estimation(e, er, c.estimation);
      c.estimation_errors = er.errors();
      c.warnings.insert(c.warnings.end(), er.warnings().begin(), er.warnings().end());
    }
  }
  c.truth_file = c.root / "truth.yaml";
  c.has_truth = fs::exists(c.truth_file);

  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(
           c.root, fs::directory_options::skip_permission_denied, ec);
       it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) break;
    if (it->is_regular_file() && it->path().filename() == "test.yaml") {
      c.tests.push_back(load_test(c.root, it->path()));
    }
  }
  std::sort(c.tests.begin(), c.tests.end(),
            [](const TestSpec& a, const TestSpec& b) { return a.id < b.id; });
  for (auto& t : c.tests) {
    if ((t.kind == "cut" || t.kind == "dyno-slot") && !c.tool) {
      t.errors.push_back(t.yaml_label + ": a " + t.kind +
                         " test needs campaign.yaml key 'tool' (teeth, radius_mm)");
    }
  }
  return c;
}

}  // namespace chatterlab::app
