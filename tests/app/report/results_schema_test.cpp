// results.json against its published schema (docs/results.schema.json,
// docs/format/results-json.md): the chatterlab binary writes a small synthetic campaign holding
// every implemented kind (tap, dyno-slot, constant and ramped cut) and a test of a contract kind
// the program does not analyse yet, reports it, and the report's results.json must validate with
// Debian's python3-jsonschema (tests/support/validate_json_schema.py). A second run of the same
// campaign without its tap tests and with one dyno-slot record covers the skipped branches (offset,
// identification, group). A copy whose ramped cut's bifurcation detector could not run (null
// depth with its reason) is valid too. Then the schema must have teeth: copies of the file with a
// required key removed, a wrong type, a value outside an enum, a number under a key without a
// unit or a figure file outside figures/ must each fail.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/record_property.h"
#include "tests/support/synth_spec.h"
#include "tests/support/temp_campaign.h"

namespace {

namespace fs = std::filesystem;
using chatterlab::testing::TempDir;
using nlohmann::json;

// Tap tests on x (with a bounced hit) and y, a three-feed dyno-slot group, a constant-depth cut
// and a short incline that crosses the bifurcation (measured near 2.3 mm): the demo campaign
// (experiments/demo.synth.yaml) cut down to what runs in a few seconds.
std::string spec_text() {
  chatterlab::testing::SynthSpecText t;
  t.name = "schema-check";
  t.seed = 7;
  t.tap_sample_rate_hz = 12800;
  t.tap_hit_spacing_s = 0.5;
  t.tap_double_hit_x = 2;
  t.dyno_duration_s = 0.5;
  t.cut_air_revolutions = 10;
  t.cut_tests =
      "    - {name: constant, axial_depth_mm: 1.0, duration_s: 0.1, offset_angle_deg: 147.0}\n"
      "    - {name: incline, axial_depth_mm: [1.5, 3.0], revolutions_per_mm: 300,\n"
      "       offset_angle_deg: 212.5}\n";
  return t.text();
}

// One identification pass over 0.02 s and two repeatability runs: every results.json block of
// a cut test, at a fraction of the default cost (docs/format/campaign.md, estimation).
const char* kEstimation =
    "estimation: {window_s: 0.02, max_passes: 1, repeat_runs: 2, settle_revolutions: 5}\n";

// A misspelt kind, which the report skips as unknown.
const char* kForceRecordTest =
    "kind: force-recrod\nsample_rate_hz: 10240\ndata: {file: forces.csv}\nspindle_rpm: 15345\n";

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs `command` with stdout and stderr into `log`; returns its exit status.
int run(const std::string& command, const fs::path& log) {
  const int rc = std::system((command + " > " + quoted(log) + " 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

struct Validation {
  int exit_status = -1;
  std::string output;
  // "valid" or "invalid" per instance file, and the error lines that follow an invalid one.
  std::map<std::string, std::string> verdict;
  std::map<std::string, std::string> errors;
};

Validation validate(const std::vector<fs::path>& instances) {
  const fs::path source(CHATTERLAB_SOURCE_DIR);
  std::string cmd = "/usr/bin/python3 " + quoted(source / "tests/support/validate_json_schema.py") +
                    " " + quoted(source / "docs/results.schema.json");
  for (const auto& p : instances) cmd += " " + quoted(p);
  Validation v;
  FILE* pipe = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!pipe) return v;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, pipe)) v.output += buf;
  const int rc = ::pclose(pipe);
  v.exit_status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  std::istringstream lines(v.output);
  std::string line, current;
  while (std::getline(lines, line)) {
    if (line.rfind("  at ", 0) == 0) {
      v.errors[current] += line + "\n";
      continue;
    }
    const auto colon = line.rfind(": ");
    if (colon == std::string::npos) continue;
    current = line.substr(0, colon);
    v.verdict[current] = line.substr(colon + 2);
  }
  return v;
}

void write_json(const fs::path& p, const json& j) { std::ofstream(p) << j.dump(2) << "\n"; }

TEST(ResultsSchema, ReportOfASynthCampaignValidatesAndBrokenCopiesFail) {
  const auto t0 = std::chrono::steady_clock::now();
  TempDir d;
  const fs::path bin(CHATTERLAB_BINARY);
  const fs::path spec = d.write("spec.yaml", spec_text());
  const fs::path campaign = d.path() / "campaign";
  const fs::path out = d.path() / "report";
  const fs::path log = d.path() / "log.txt";
  ASSERT_EQ(run(quoted(bin) + " synth " + quoted(spec) + " --out " + quoted(campaign), log), 0)
      << read_text(log);
  std::ofstream(campaign / "campaign.yaml", std::ios::app) << kEstimation;
  d.write("campaign/dynamometer/x/test.yaml", kForceRecordTest);
  d.write("campaign/dynamometer/x/forces.csv", "Fx,Fy\n0,0\n1,0.5\n");
  ASSERT_EQ(
      run(quoted(bin) + " report " + quoted(campaign) + " --out " + quoted(out) + " --no-pdf", log),
      0)
      << read_text(log);

  // The same campaign without tap tests and with one dyno-slot record: the cut tests' offset
  // and identification steps and the dyno-slot group are skipped with their reasons.
  const fs::path sparse = d.path() / "sparse";
  const fs::path sparse_out = d.path() / "sparse-report";
  fs::copy(campaign, sparse, fs::copy_options::recursive);
  fs::remove_all(sparse / "tap");
  fs::remove_all(sparse / "dyno/f100");
  fs::remove_all(sparse / "dyno/f150");
  ASSERT_EQ(
      run(quoted(bin) + " report " + quoted(sparse) + " --out " + quoted(sparse_out) + " --no-pdf",
          log),
      0)
      << read_text(log);

  const fs::path results = out / "results.json";
  const fs::path sparse_results = sparse_out / "results.json";
  json r;
  json s;
  {
    std::ifstream in(results);
    r = json::parse(in);
    std::ifstream in2(sparse_results);
    s = json::parse(in2);
  }

  // The runs cover what the schema describes; otherwise "valid" would say little.
  const json& tests = r["tests"];
  for (const char* id : {"tap/x", "tap/y", "dyno/f050", "cuts/constant", "cuts/incline"}) {
    ASSERT_TRUE(tests.contains(id)) << id;
    EXPECT_EQ(tests[id]["status"], "ok") << id << ": " << tests[id].dump();
  }
  EXPECT_EQ(tests["dynamometer/x"]["status"], "skipped");
  EXPECT_NE(tests["dynamometer/x"]["skip_reason"].get<std::string>().find(
                "'force-recrod' is not a known test kind"),
            std::string::npos);
  EXPECT_TRUE(r["groups"]["dyno-slot"].contains("Ktc_N_m2"));
  EXPECT_EQ(r["identified_from"], "cuts/constant");
  EXPECT_FALSE(r["truth_comparison"].empty());
  EXPECT_EQ(tests["cuts/constant"]["estimators"].size(), 13u);
  EXPECT_TRUE(tests["cuts/incline"]["bifurcation_depth_mm"].is_number());
  EXPECT_EQ(tests["cuts/incline"]["figures"]["bifurcation"]["csv"],
            "figures/cut-cuts-incline-bifurcation.csv");
  EXPECT_EQ(r["groups"]["dyno-slot"]["figures"]["force"]["svg"], "figures/dyno-force-vs-feed.svg");
  EXPECT_FALSE(s["groups"]["dyno-slot"].contains("figures"));
  EXPECT_TRUE(tests["cuts/incline"].contains("simulated_identified"));
  EXPECT_TRUE(tests["cuts/constant"]["estimators"]["ekf-modal-x"].contains("repeatability"));
  EXPECT_EQ(s["groups"]["dyno-slot"]["status"], "skipped");
  EXPECT_EQ(s["tests"]["cuts/constant"]["offset_status"], "skipped");
  EXPECT_EQ(s["tests"]["cuts/constant"]["identification_status"], "skipped");
  EXPECT_TRUE(s["identified"].empty());

  // Broken copies, each of which the schema must reject, with the JSON pointer it names.
  struct Breakage {
    const char* name;
    const char* pointer;  // where the validator must report it
    std::function<void(json&)> apply;
  };
  // A ramped cut whose detector could not run: the depth is null beside the reason (format: the
  // key is absent only for a constant depth), without the detector's keys.
  const auto bifurcation_skipped = [](json& j) {
    json& c = j["tests"]["cuts/incline"];
    for (const char* k : {"bifurcation_verdict", "bifurcation_noise_floor_m", "chatter_islands"}) {
      c.erase(k);
    }
    c["bifurcation_depth_mm"] = nullptr;
    c["bifurcation_status"] = "skipped";
    c["bifurcation_skip_reason"] = "too few revolutions for the bifurcation detector";
  };
  const std::vector<Breakage> breakages = {
      {"required key removed", "at /: 'format' is a required property",
       [](json& j) { j.erase("format"); }},
      {"group key removed", "at /groups/dyno-slot: 'Ktc_N_m2' is a required property",
       [](json& j) { j["groups"]["dyno-slot"].erase("Ktc_N_m2"); }},
      {"estimate key removed", "at /tests/cuts~1constant/estimators/ekf-modal-x/estimates:",
       [](json& j) {
         j["tests"]["cuts/constant"]["estimators"]["ekf-modal-x"]["estimates"].erase("k_N_m");
       }},
      {"unscented estimate key unknown",
       "at /tests/cuts~1constant/estimators/ukf-coeff-xy-per-tooth/estimates:",
       [](json& j) {
         j["tests"]["cuts/constant"]["estimators"]["ukf-coeff-xy-per-tooth"]["estimates"]["m_kg"] =
             1.0;
       }},
      {"filter outside its enum", "at /tests/cuts~1constant/estimators/ukf-modal-x/filter:",
       [](json& j) { j["tests"]["cuts/constant"]["estimators"]["ukf-modal-x"]["filter"] = "ukf"; }},
      {"number as text", "at /tests/tap~1x/modes/0/fn_hz:",
       [](json& j) { j["tests"]["tap/x"]["modes"][0]["fn_hz"] = "898.3"; }},
      {"depth as text", "at /tests/cuts~1incline/bifurcation_depth_mm:",
       [](json& j) { j["tests"]["cuts/incline"]["bifurcation_depth_mm"] = "2.3"; }},
      {"status outside its enum", "at /tests/cuts~1constant/status:",
       [](json& j) { j["tests"]["cuts/constant"]["status"] = "done"; }},
      {"number under a key without a unit", "at /tests/dyno~1f050/duration:",
       [](json& j) { j["tests"]["dyno/f050"]["duration"] = 0.5; }},
      {"unit dropped from a key", "at /tests/tap~1x/modes/0: 'fn_hz' is a required property",
       [](json& j) {
         json& m = j["tests"]["tap/x"]["modes"][0];
         m["fn"] = m["fn_hz"];
         m.erase("fn_hz");
       }},
      {"skipped test without its reason", "at /tests/dynamometer~1x: 'skip_reason'",
       [](json& j) { j["tests"]["dynamometer/x"].erase("skip_reason"); }},
      {"hash that is not one", "at /inputs_sha256/campaign.yaml:",
       [](json& j) { j["inputs_sha256"]["campaign.yaml"] = "abc"; }},
      {"analysed test without figures", "at /tests/tap~1x: 'figures' is a required property",
       [](json& j) { j["tests"]["tap/x"].erase("figures"); }},
      {"figure file outside figures/", "at /tests/tap~1x/figures/frf/csv:",
       [](json& j) { j["tests"]["tap/x"]["figures"]["frf"]["csv"] = "tap/x/frf.csv"; }},
      {"bifurcation skipped without the depth key",
       "at /tests/cuts~1incline: 'bifurcation_depth_mm' is a required property",
       [&](json& j) {
         bifurcation_skipped(j);
         j["tests"]["cuts/incline"].erase("bifurcation_depth_mm");
       }},
      {"joint value without its interval",
       "at /tests/cuts~1constant/identification/joint/identified: 'c_kg_s_ci95' is a required",
       [](json& j) {
         j["tests"]["cuts/constant"]["identification"]["joint"]["identified"].erase("c_kg_s_ci95");
       }},
      {"joint interval of one end",
       "at /tests/cuts~1constant/identification/joint/identified/zeta_ci95:",
       [](json& j) {
         j["tests"]["cuts/constant"]["identification"]["joint"]["identified"]["zeta_ci95"] =
             json::array({0.05});
       }},
      {"joint method mislabelled", "at /tests/cuts~1constant/identification/joint/method:",
       [](json& j) {
         j["tests"]["cuts/constant"]["identification"]["joint"]["method"] = "sequence";
       }},
      {"bifurcation skipped with a depth", "at /tests/cuts~1incline/bifurcation_depth_mm:",
       [&](json& j) {
         bifurcation_skipped(j);
         j["tests"]["cuts/incline"]["bifurcation_depth_mm"] = 2.3;
       }},
  };
  std::vector<fs::path> files = {results, sparse_results};
  for (std::size_t i = 0; i < breakages.size(); ++i) {
    json broken = r;
    breakages[i].apply(broken);
    files.push_back(d.path() / ("broken-" + std::to_string(i) + ".json"));
    write_json(files.back(), broken);
  }

  const fs::path skipped_copy = d.path() / "bifurcation-skipped.json";
  {
    json copy = r;
    bifurcation_skipped(copy);
    write_json(skipped_copy, copy);
  }
  files.push_back(skipped_copy);

  Validation v = validate(files);
  ASSERT_NE(v.exit_status, 3) << v.output;  // python3-jsonschema missing
  ASSERT_NE(v.exit_status, 2) << v.output;  // schema not valid under its draft's meta-schema
  EXPECT_EQ(v.exit_status, 1) << v.output;  // the broken copies
  EXPECT_EQ(v.verdict.at(results.string()), "valid") << v.errors[results.string()];
  EXPECT_EQ(v.verdict.at(sparse_results.string()), "valid") << v.errors[sparse_results.string()];
  EXPECT_EQ(v.verdict.at(skipped_copy.string()), "valid") << v.errors[skipped_copy.string()];
  for (std::size_t i = 0; i < breakages.size(); ++i) {
    const std::string f = files[i + 2].string();
    EXPECT_EQ(v.verdict.at(f), "invalid") << breakages[i].name;
    EXPECT_NE(v.errors[f].find(breakages[i].pointer), std::string::npos)
        << breakages[i].name << ": expected '" << breakages[i].pointer << "' in\n"
        << v.errors[f];
  }
  chatterlab::testing::record_and_print(
      "runtime_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

}  // namespace
