// `validate` and `report` run the same checks before computing (issue 16: "validate runs
// exactly the checks report runs ... so that a campaign validate calls usable never fails in
// report for an input reason"). One campaign holds two good tap tests and, beside them, one
// copy of the x tap test per bad input of the issue's classes (YAML structure, numbers, files,
// records, names). For every test the verdicts must agree: validate's UNUSABLE exactly when the
// pipeline skips the test for an input reason, with the same message; a test validate calls
// usable is never skipped for one. The good tests are analysed whatever their neighbours hold,
// nothing throws, and the campaign folder is unchanged.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <complex>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli/validate.h"
#include "app/core/campaign.h"
#include "app/core/hashing.h"
#include "app/core/input_boundary.h"
#include "app/core/utf8.h"
#include "app/pipeline/pipeline.h"
#include "app/report/report.h"
#include "app/synth/synth.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::TempDir;

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

void replace_in(const fs::path& p, const std::string& from, const std::string& to) {
  std::string s = read_text(p);
  const auto at = s.find(from);
  ASSERT_NE(at, std::string::npos) << p << ": no '" << from << "'";
  s.replace(at, from.size(), to);
  write_text(p, s);
}

// Every entry below `root`, symlinks not followed: type, and a regular file's size and hash
// (a file above the input limit: its size only).
std::map<std::string, std::string> snapshot(const fs::path& root) {
  std::map<std::string, std::string> out;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator();
       ++it) {
    const fs::file_status st = fs::symlink_status(it->path());
    std::string what = std::to_string(static_cast<int>(st.type()));
    if (st.type() == fs::file_type::regular) {
      const auto bytes = fs::file_size(it->path());
      what += " " + std::to_string(bytes);
      if (bytes <= kMaxInputFileBytes) what += " " + sha256_file(it->path());
    }
    out[it->path().lexically_relative(root).string()] = what;
  }
  return out;
}

const char* kSynthSpec = R"(format: chatterlab-synth/1
name: agree
seed: 7
tool: {teeth: 2, radius_mm: 6.35, helix_deg: 30}
tap:
  sample_rate_hz: 25600
  hits: 3
  hit_spacing_s: 1.0
  response: acceleration
  noise_pct: 1.0
  force_peak_N: 150
  pulse_width_s: 0.0003
  axes:
    x:
      modes:
        - {m_kg: 0.03211, c_kg_s: 13.39, k_N_m: 1.023e6}
    y:
      modes:
        - {m_kg: 0.03211, c_kg_s: 13.39, k_N_m: 1.023e6}
)";

// A measured receptance of one mode (the hammer mode of x) from 20 Hz to 2 kHz as
// frequency,real,imaginary rows; with `bad_cell` one cell of the middle row is text.
std::string frf_table(bool bad_cell) {
  const double m = 0.03211, c = 13.39, k = 1.023e6;
  std::ostringstream s;
  s.precision(10);
  s << "f_hz,re_m_N,im_m_N\n";
  for (int i = 0; i <= 990; ++i) {
    const double f = 20.0 + 2.0 * i, w = 2.0 * 3.141592653589793 * f;
    const std::complex<double> h = 1.0 / std::complex<double>(k - m * w * w, c * w);
    if (bad_cell && i == 500) {
      s << f << ",abc," << h.imag() << "\n";
    } else {
      s << f << "," << h.real() << "," << h.imag() << "\n";
    }
  }
  return s.str();
}

// A bad input: applied to a copy of tap/x in bad/<id>/ (test.yaml and hits.csv).
struct Mutation {
  std::string id;
  bool usable;  // what both must find: usable (perhaps with a warning) or not
  std::function<void(const fs::path& dir)> apply;
};

std::vector<Mutation> mutations() {
  auto append = [](const std::string& text) {
    return [text](const fs::path& d) {
      std::ofstream(d / "test.yaml", std::ios::app | std::ios::binary) << text;
    };
  };
  auto yaml = [](const std::string& from, const std::string& to) {
    return [from, to](const fs::path& d) { replace_in(d / "test.yaml", from, to); };
  };
  auto csv = [](const std::string& text) {
    return [text](const fs::path& d) { write_text(d / "hits.csv", text); };
  };
  auto data_file = [](const std::string& name, const std::function<void(const fs::path&)>& make) {
    return [name, make](const fs::path& d) {
      replace_in(d / "test.yaml", "hits.csv", name);
      make(d);
    };
  };
  auto frf_test = [](const std::string& table) {
    return [table](const fs::path& d) {
      fs::remove(d / "hits.csv");
      write_text(d / "test.yaml",
                 "kind: tap\naxis: x\nresponse: displacement\nfrf: {file: frf.csv}\n");
      write_text(d / "frf.csv", table);
    };
  };
  std::string deep =
      "kind: tap\naxis: x\nsample_rate_hz: 25600\ndata: {file: hits.csv}\n"
      "response: acceleration\nnote: ";
  for (int i = 0; i < 200; ++i) deep += "[";
  for (int i = 0; i < 200; ++i) deep += "]";
  deep += "\n";
  return {
      // YAML structure
      {"nonscalar-key", false, append("channels: {[a]: {scale: 2}}\n")},
      {"nonscalar-key-in-data", false,
       yaml("data: {file: hits.csv}", "data: {file: hits.csv, [x]: 1}")},
      {"tagged-empty-key", false, append("channels: {!y2 : {scale: 200}}\n")},
      {"duplicate-key", false, append("axis: y\n")},
      {"misspelt-key", true, append("respnse: acceleration\n")},
      {"misspelt-calibration", false, append("channels: {forse: {scale: 2}}\n")},
      {"not-a-mapping", false,
       [](const fs::path& d) { write_text(d / "test.yaml", "- a\n- b\n"); }},
      {"not-yaml", false,
       [](const fs::path& d) { write_text(d / "test.yaml", "kind: tap\naxis: [x\n"); }},
      {"too-deep", false, [deep](const fs::path& d) { write_text(d / "test.yaml", deep); }},
      {"unknown-kind", false, yaml("kind: tap", "kind: tapp")},
      {"bad-axis", false, yaml("axis: x", "axis: q")},
      {"response-list", false, yaml("response: acceleration", "response: [acceleration]")},
      // numbers
      {"rate-inf", false, yaml("sample_rate_hz: 25600", "sample_rate_hz: .inf")},
      {"rate-nan", false, yaml("sample_rate_hz: 25600", "sample_rate_hz: .nan")},
      {"rate-overflow", false, yaml("sample_rate_hz: 25600", "sample_rate_hz: 1e400")},
      {"rate-zero", false, yaml("sample_rate_hz: 25600", "sample_rate_hz: 0")},
      {"rate-negative", false, yaml("sample_rate_hz: 25600", "sample_rate_hz: -25600")},
      {"rate-text", false, yaml("sample_rate_hz: 25600", "sample_rate_hz: fast")},
      {"hits-huge", false, yaml("hits: auto", "hits: 1e300")},
      {"hits-negative", false, yaml("hits: auto", "hits: -3")},
      {"hits-fraction", false, yaml("hits: auto", "hits: 2.5")},
      {"hit-window-inf", false, yaml("hits: auto", "hits: [[0.1, .inf]]")},
      {"hit-window-past-the-end", false, yaml("hits: auto", "hits: [[0.5, 30.0]]")},
      {"hit-window-before-the-start", false, yaml("hits: auto", "hits: [[-0.5, 0.5]]")},
      {"hit-windows-inside", true, yaml("hits: auto", "hits: [[0.9, 1.6], [1.9, 2.6]]")},
      // a tap test from a measured FRF (no record): the file is read before computing
      {"frf-not-a-table", false, frf_test("hello\nworld\n")},
      {"frf-text-cell", false, frf_test(frf_table(true))},
      {"frf-good", true, frf_test(frf_table(false))},
      // files the test names
      {"data-outside", false, yaml("hits.csv", "../../../x.csv")},
      {"data-absolute", false, yaml("hits.csv", "/x.csv")},
      {"data-missing", false, yaml("hits.csv", "gone.csv")},
      {"data-folder", false,
       data_file("f.csv", [](const fs::path& d) { fs::create_directory(d / "f.csv"); })},
      {"data-fifo", false,
       data_file("p.csv", [](const fs::path& d) { ::mkfifo((d / "p.csv").c_str(), 0600); })},
      {"data-loop", false,
       data_file("l.csv",
                 [](const fs::path& d) {
                   fs::create_symlink("m.csv", d / "l.csv");
                   fs::create_symlink("l.csv", d / "m.csv");
                 })},
      {"data-long-name", false, yaml("hits.csv", std::string(300, 'n') + ".csv")},
      {"data-huge", false,
       data_file("h.csv",
                 [](const fs::path& d) {
                   write_text(d / "h.csv", "force,response\n");
                   fs::resize_file(d / "h.csv", kMaxInputFileBytes + 1);
                 })},
      // records
      {"csv-empty", false, csv("")},
      {"csv-header-only", false, csv("force,response\n")},
      {"csv-one-row", false, csv("force,response\n1,2\n")},
      {"csv-no-response", false, csv("force,other\n1,2\n3,4\n")},
      {"csv-latin1-header", false, csv("force,r\xE9ponse\n1,2\n3,4\n")},
      {"csv-text-cell", false,
       [](const fs::path& d) {
         std::string s = read_text(d / "hits.csv");
         s.insert(s.find('\n') + 1, "abc,1\n");
         write_text(d / "hits.csv", s);
       }},
  };
}

TEST(ValidateReportAgree, EveryBadInputGetsTheSameVerdictFromBoth) {
  TempDir d;
  d.write("spec.yaml", kSynthSpec);
  const fs::path root = d.path() / "campaign";
  synthesize_campaign(d.path() / "spec.yaml", root);
  const auto list = mutations();
  for (const auto& m : list) {
    const fs::path dir = root / "bad" / m.id;
    fs::create_directories(dir);
    fs::copy_file(root / "tap/x/test.yaml", dir / "test.yaml");
    fs::copy_file(root / "tap/x/hits.csv", dir / "hits.csv");
    m.apply(dir);
  }
  // A folder whose name is not UTF-8 (Latin-1 a-umlaut), holding a good test.
  const fs::path latin1 = root / "bad" / "latin1-\xE4";
  fs::create_directories(latin1);
  fs::copy_file(root / "tap/x/test.yaml", latin1 / "test.yaml");
  fs::copy_file(root / "tap/x/hits.csv", latin1 / "hits.csv");
  const auto before = snapshot(root);

  // validate, as the command runs it.
  CampaignSpec for_validate = load_campaign(root);
  std::ostringstream said;
  validate_campaign(for_validate, said);
  std::map<std::string, std::string> validate_status;  // id -> ok / UNUSABLE
  {
    std::istringstream lines(said.str());
    std::string line;
    const std::regex row(R"(^  (ok|UNUSABLE|-)\s+(\S+)\s)");
    std::smatch m;
    while (std::getline(lines, line)) {
      if (std::regex_search(line, m, row)) validate_status[m[2]] = m[1];
    }
  }
  std::map<std::string, std::vector<std::string>> validate_errors;
  for (const auto& t : for_validate.tests) validate_errors[t.id] = t.errors;
  // The pipeline report runs (the same load, then every usable test analysed).
  PipelineOptions o;
  o.jobs = 2;
  const CampaignResults r = run_campaign(load_campaign(root), o);
  ASSERT_EQ(r.tests.size(), list.size() + 3);  // tap/x, tap/y, the latin1 folder, the copies

  std::map<std::string, const TestOutcome*> by_id;
  for (const auto& t : r.tests) by_id[t.spec->id] = &t;
  for (const auto& t : r.tests) {
    const std::string& id = t.spec->id;
    SCOPED_TRACE(id);
    ASSERT_EQ(validate_status.count(id), 1u) << said.str();
    const bool validate_usable = validate_status[id] == "ok";
    const bool skipped_for_input = t.failure == Failure::kInput;
    EXPECT_EQ(validate_usable, !skipped_for_input)
        << "validate: " << validate_status[id] << "; report: " << t.status.message;
    EXPECT_NE(t.failure, Failure::kInternal) << t.status.message;
    if (skipped_for_input) {
      // The same message: each of validate's error lines is in the skip reason.
      for (const auto& e : validate_errors[id]) {
        EXPECT_NE(t.status.message.find(e), std::string::npos) << e;
      }
    }
  }
  for (const auto& m : list) {
    SCOPED_TRACE(m.id);
    const auto it = by_id.find("bad/" + m.id);
    ASSERT_NE(it, by_id.end());
    EXPECT_EQ(it->second->failure != Failure::kInput, m.usable) << it->second->status.message;
  }
  for (const char* good : {"tap/x", "tap/y"}) {
    ASSERT_TRUE(by_id.count(good));
    EXPECT_TRUE(by_id[good]->status.ok()) << good << ": " << by_id[good]->status.message;
  }
  EXPECT_EQ(snapshot(root), before);
}

// A folder whose name is not UTF-8 once ended the whole run (results.json could not be
// written: "invalid UTF-8 byte"). Now its test is skipped with the reason, the other tests are
// analysed and results.json, results.csv and index.html are written, in UTF-8.
TEST(ValidateReportAgree, AFolderNameThatIsNotUtf8SkipsItsTestOnly) {
  TempDir d;
  d.write("spec.yaml", kSynthSpec);
  const fs::path root = d.path() / "campaign";
  synthesize_campaign(d.path() / "spec.yaml", root);
  const fs::path latin1 = root / "tap" / "Fr\xE4sen";
  fs::create_directories(latin1);
  fs::copy_file(root / "tap/x/test.yaml", latin1 / "test.yaml");
  fs::copy_file(root / "tap/x/hits.csv", latin1 / "hits.csv");
  const auto before = snapshot(root);
  ReportOptions o;
  o.pdf = false;
  o.jobs = 2;
  std::ostringstream log;
  EXPECT_EQ(run_report(root, d.path() / "out", o, log), 0) << log.str();
  const nlohmann::json r = nlohmann::json::parse(read_text(d.path() / "out/results.json"));
  std::map<std::string, std::string> status;
  for (const auto& [id, t] : r.at("tests").items()) status[id] = t.at("status");
  const std::string shown = "tap/Fr\xEF\xBF\xBDsen";  // U+FFFD for the byte 0xE4
  EXPECT_EQ(status, (std::map<std::string, std::string>{
                        {"tap/x", "ok"}, {"tap/y", "ok"}, {shown, "skipped"}}));
  if (r.at("tests").contains(shown)) {
    EXPECT_EQ(r.at("tests").at(shown).at("skip_reason"),
              shown +
                  "/test.yaml: the folder's name is not valid UTF-8 (shown with U+FFFD for "
                  "each bad byte); rename the folder in UTF-8");
  }
  for (const char* f : {"results.json", "results.csv", "index.html"}) {
    EXPECT_TRUE(valid_utf8(read_text(d.path() / "out" / f))) << f;
  }
  EXPECT_EQ(snapshot(root), before);
}

}  // namespace
}  // namespace chatterlab::app
