#include "app/synth/synth.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include "analysis/common/constants.h"
#include "analysis/common/seed.h"
#include "analysis/common/summary.h"
#include "app/core/checked_write.h"
#include "app/core/yaml_load.h"
#include "app/core/yaml_reader.h"
#include "app/pipeline/registry.h"

namespace chatterlab::app {
namespace {

void write_text(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream out = open_for_writing(p);
  out << text;
  close_checked(out, p);
}

}  // namespace

std::string synth_number(double v) {
  std::ostringstream s;
  s.precision(kSynthDigits);
  s << v;
  return s.str();
}

YAML::Node synth_numbers(const std::vector<std::pair<std::string, double>>& values) {
  YAML::Node n(YAML::NodeType::Map);
  for (const auto& [key, v] : values) n[key] = synth_number(v);
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

std::string read_synth_folder(const YAML::Node& section, const std::string& name,
                              const std::string& fallback, YamlReader& r) {
  const std::string f = r.optional_string(section, "folder", name).value_or(fallback);
  if (f.empty() || f.front() == '/' || f.back() == '/' || f.find("..") != std::string::npos ||
      f.find('\\') != std::string::npos) {
    r.error(name + ".folder", "must be a relative folder path such as " + name + " or lab/" + name);
  }
  return f;
}

YAML::Node synth_number_list(const std::vector<double>& values) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (double v : values) n.push_back(synth_number(v));
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

void configure_synth_emitter(YAML::Emitter& e) {
  e.SetDoublePrecision(kSynthDigits);  // the same text as synth_number
}

void write_synth_yaml(const std::filesystem::path& path, const YAML::Emitter& e) {
  if (!e.good()) {
    throw std::logic_error(path.string() + ": YAML emitter: " + e.GetLastError());
  }
  write_text(path, std::string(e.c_str()) + "\n");
}

std::uint64_t SynthContext::stream_seed(std::string_view tag, std::uint64_t index) const {
  return derive_seed(seed, tag, index);
}

namespace {

// campaign.yaml's `tool` from the spec: teeth and radius required, helix optional.
std::optional<SynthTool> read_tool(const YAML::Node& n, YamlReader& r) {
  if (!n.IsMap()) {
    r.error("tool", "must be {teeth, radius_mm[, helix_deg]}");
    return std::nullopt;
  }
  r.check_keys(n, {"teeth", "radius_mm", "helix_deg"}, "tool");
  const std::size_t errors_before = r.errors().size();
  SynthTool t;
  // As campaign.yaml's tool.teeth (docs/format/campaign.md): 1 to 500.
  const auto teeth = r.required_int(n, "teeth", "tool", 1, 500);
  t.radius_mm = r.required_double(n, "radius_mm", "tool");
  t.helix_deg = r.optional_double(n, "helix_deg", "tool");
  if (r.errors().size() != errors_before) return std::nullopt;
  if (!(t.radius_mm > 0)) {
    r.error("tool.radius_mm", "must be > 0");
    return std::nullopt;
  }
  t.teeth = static_cast<int>(*teeth);
  return t;
}

// The largest synth seed: 2^53, every whole number up to it exact in a YAML float.
constexpr long kMaxSynthSeed = 9007199254740992L;

// campaign.yaml's text keys, read (a scalar string each) before anything is written.
struct CampaignText {
  std::optional<std::string> description, workpiece, machine;
};

void write_campaign_yaml(const CampaignText& text, const SynthContext& ctx,
                         const std::string& name) {
  YAML::Emitter campaign;
  configure_synth_emitter(campaign);
  campaign << YAML::BeginMap << YAML::Key << "format" << YAML::Value << "chatterlab-campaign/1";
  campaign << YAML::Key << "name" << YAML::Value << name;
  if (text.description) {
    campaign << YAML::Key << "description" << YAML::Value << YAML::Literal << *text.description;
  }
  if (ctx.tool) {
    campaign << YAML::Key << "tool" << YAML::Value << YAML::Flow << YAML::BeginMap;
    campaign << YAML::Key << "teeth" << YAML::Value << ctx.tool->teeth;
    campaign << YAML::Key << "radius_mm" << YAML::Value << ctx.tool->radius_mm;
    if (ctx.tool->helix_deg) {
      campaign << YAML::Key << "helix_deg" << YAML::Value << *ctx.tool->helix_deg;
    }
    campaign << YAML::EndMap;
  }
  if (text.workpiece) campaign << YAML::Key << "workpiece" << YAML::Value << *text.workpiece;
  if (text.machine) campaign << YAML::Key << "machine" << YAML::Value << *text.machine;
  campaign << YAML::EndMap;
  write_synth_yaml(ctx.out / "campaign.yaml", campaign);
}

void write_truth_yaml(const SynthContext& ctx) {
  YAML::Emitter t;
  configure_synth_emitter(t);
  t << YAML::Comment("Values used by chatterlab synth to write this campaign.");
  t << YAML::BeginMap;
  for (const auto& kv : ctx.truth.top) t << YAML::Key << kv.first << YAML::Value << kv.second;
  t << YAML::Key << "tests" << YAML::Value << ctx.truth.tests << YAML::EndMap;
  write_synth_yaml(ctx.out / "truth.yaml", t);
}

}  // namespace

SynthSummary synthesize_campaign(const std::filesystem::path& spec_yaml,
                                 const std::filesystem::path& out_dir,
                                 const std::function<void()>& before_writing) {
  const std::string label = spec_yaml.filename().string();
  const YAML::Node root = load_yaml_file_or_throw(spec_yaml, label);
  YamlReader r(label);
  std::set<std::string> keys = {"format", "name",      "description", "seed",
                                "tool",   "workpiece", "machine"};
  const KindRegistry& kinds = builtin_kinds();
  for (const auto& k : kinds.kinds()) {
    if (!k->synth_section().empty()) keys.insert(k->synth_section());
  }
  r.check_keys(root, keys);
  const auto format = r.required_string(root, "format");
  if (!format.empty() && format != "chatterlab-synth/1") {
    r.error("format", "'" + format + "': must be 'chatterlab-synth/1'");
  }
  SynthSummary summary;
  summary.campaign_name = r.required_string(root, "name");
  SynthContext ctx;
  ctx.spec_label = label;
  // A whole number (a fraction, 1e300 or a negative seed is refused, never converted).
  ctx.seed =
      static_cast<std::uint64_t>(r.optional_int(root, "seed", "", 0, kMaxSynthSeed).value_or(1));
  CampaignText text;
  text.description = r.optional_string(root, "description");
  text.workpiece = r.optional_string(root, "workpiece");
  text.machine = r.optional_string(root, "machine");
  ctx.out = out_dir;
  if (root["tool"]) {
    ctx.tool_given = true;
    ctx.tool = read_tool(root["tool"], r);
  }
  // Each kind's section, in the registry's order (tap, dyno, cut).
  std::vector<std::pair<const TestKind*, std::shared_ptr<const KindSpec>>> sections;
  for (const auto& k : kinds.kinds()) {
    const std::string section = k->synth_section();
    if (section.empty() || !root[section]) continue;
    auto parsed = k->parse_synth(root[section], ctx, r);
    if (parsed) sections.emplace_back(k.get(), std::move(parsed));
  }
  r.throw_if_errors();

  if (before_writing) before_writing();
  std::filesystem::create_directories(out_dir);
  write_campaign_yaml(text, ctx, summary.campaign_name);
  for (const auto& [kind, section] : sections) {
    summary.tests_written += kind->write_synth(*section, ctx);
  }
  write_truth_yaml(ctx);
  summary.warnings = r.warnings();
  return summary;
}

}  // namespace chatterlab::app
