// The chatterlab binary as a lab's script runs it (issue 15, CLI): --quiet leaves stdout empty
// and errors on stderr, `report` prints a progress line per test or group, the exit status
// tells "nothing analysed" (4) apart, a re-run into an earlier output folder leaves none of its
// files behind while a folder that is not chatterlab's is refused, and results.json names a
// campaign whose campaign.yaml has no valid name after its folder.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/cli/exit_codes.h"
#include "app/cli/output_folder.h"
#include "tests/app/cli/run_binary.h"
#include "tests/support/results_schema.h"
#include "tests/support/synth_spec.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::BinaryRun;
using chatterlab::testing::file_text;
using chatterlab::testing::quoted;
using chatterlab::testing::TempDir;
using nlohmann::json;

BinaryRun run(const std::string& args, const TempDir& d) {
  return chatterlab::testing::run_chatterlab(args, d.path());
}

std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string line = text.substr(at, end - at);
    if (line.rfind(prefix, 0) == 0) out.push_back(line);
    at = end + 1;
  }
  return out;
}

// One synth campaign for the suite (2 tap tests, 3 dyno-slot tests, the dyno-slot group).
class CliRuns : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    chatterlab::testing::SynthSpecText spec;
    spec.tap_hits = 2;
    spec.dyno_duration_s = 0.5;
    dir_->write("spec.yaml", spec.text());
    const BinaryRun s = chatterlab::testing::run_chatterlab(
        "synth " + quoted(dir_->path() / "spec.yaml") + " --out " + quoted(campaign()) + " --quiet",
        dir_->path());
    ASSERT_EQ(s.status, 0) << s.err;
    EXPECT_EQ(s.out, "");  // synth --quiet
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path campaign() { return dir_->path() / "campaign"; }

  static TempDir* dir_;
};
TempDir* CliRuns::dir_ = nullptr;

TEST_F(CliRuns, QuietPrintsNothingAndProgressPrintsALinePerTestOrGroup) {
  TempDir d;
  const BinaryRun q = run(
      "report " + quoted(campaign()) + " --out " + quoted(d.path() / "q") + " --no-pdf --quiet", d);
  EXPECT_EQ(q.status, kExitOk) << q.err;
  EXPECT_EQ(q.out, "");
  EXPECT_EQ(q.err, "");
  EXPECT_TRUE(fs::exists(d.path() / "q/results.json"));

  const BinaryRun r =
      run("report " + quoted(campaign()) + " --out " + quoted(d.path() / "r") + " --no-pdf", d);
  EXPECT_EQ(r.status, kExitOk) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(r.out.rfind("report: 5 tests found in synth-test\n", 0), 0u) << r.out;
  // 5 tests, the dyno-slot group and the lobes group (tap and dyno tests: docs/lobes.md),
  // counted as they finish: [1/7] .. [7/7].
  const auto progress = lines_starting(r.out, "[");
  ASSERT_EQ(progress.size(), 7u) << r.out;
  for (std::size_t k = 0; k < progress.size(); ++k) {
    EXPECT_EQ(progress[k].rfind("[" + std::to_string(k + 1) + "/7] ", 0), 0u) << progress[k];
    EXPECT_NE(progress[k].find(" ok "), std::string::npos) << progress[k];
    EXPECT_NE(progress[k].find(" s elapsed"), std::string::npos) << progress[k];
  }
  EXPECT_EQ(progress[5].rfind("[6/7] group dyno-slot ok ", 0), 0u) << progress[5];
  EXPECT_EQ(progress.back().rfind("[7/7] group lobes ok ", 0), 0u) << progress.back();
  EXPECT_NE(r.out.find("report: 5 tests, 5 analysed, 0 skipped"), std::string::npos) << r.out;
}

TEST(CliExit, EveryTestSkippedExitsWithFour) {
  TempDir d;
  d.write("c/campaign.yaml", chatterlab::testing::kCampaignYaml);
  d.write("c/t/test.yaml",
          "kind: tap\naxis: x\nsample_rate_hz: 1000\ndata: {file: none.csv}\nresponse: velocity\n");
  const BinaryRun r =
      run("report " + quoted(d.path() / "c") + " --out " + quoted(d.path() / "o") + " --no-pdf", d);
  EXPECT_EQ(r.status, kExitNothingAnalysed) << r.out << r.err;
  EXPECT_NE(r.err.find("chatterlab report: no test was analysed (every one of the 1 tests was "
                       "skipped); exit status 4"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("\n[1/1] t skipped 0.0 s, "), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(d.path() / "o/results.json"));  // the report is still written

  // --quiet: the error alone, on stderr.
  const BinaryRun q = run(
      "report " + quoted(d.path() / "c") + " --out " + quoted(d.path() / "o") + " --no-pdf --quiet",
      d);
  EXPECT_EQ(q.status, kExitNothingAnalysed);
  EXPECT_EQ(q.out, "");
  EXPECT_NE(q.err.find("no test was analysed"), std::string::npos) << q.err;

  // No test at all: nothing analysed either.
  d.write("empty/campaign.yaml", chatterlab::testing::kCampaignYaml);
  const BinaryRun e = run("report " + quoted(d.path() / "empty") + " --out " +
                              quoted(d.path() / "oe") + " --no-pdf --quiet",
                          d);
  EXPECT_EQ(e.status, kExitNothingAnalysed);
  EXPECT_NE(e.err.find("no test.yaml found below the campaign folder"), std::string::npos) << e.err;
}

TEST(CliExit, UsageTextsNameTheExitStatuses) {
  TempDir d;
  const BinaryRun h = run("report --help", d);
  EXPECT_EQ(h.status, 0);
  EXPECT_NE(h.out.find("--quiet"), std::string::npos) << h.out;
  EXPECT_NE(h.out.find("exit status:"), std::string::npos) << h.out;
  EXPECT_NE(h.out.find("  4  report: the report was written but no test was analysed"),
            std::string::npos)
      << h.out;
  const BinaryRun bad = run("report --quiett", d);
  EXPECT_EQ(bad.status, kExitUsage);
  EXPECT_NE(bad.err.find("unknown option '--quiett'"), std::string::npos) << bad.err;
}

// A campaign.yaml without a valid name: results.json `campaign` is the folder's name, made to
// fit the schema's pattern [A-Za-z0-9._-]+, and the file validates.
TEST(CliCampaignErrors, ResultsNameTheCampaignAfterItsFolder) {
  TempDir d;
  d.write("lab run 7/campaign.yaml",
          "format: chatterlab-campaign/1\ntool: {teeth: 2, radius_mm: 6}\n");
  const BinaryRun r = run("report " + quoted(d.path() / "lab run 7") + " --out " +
                              quoted(d.path() / "o") + " --no-pdf --quiet",
                          d);
  EXPECT_EQ(r.status, kExitNothingAnalysed) << r.err;
  std::ifstream in(d.path() / "o/results.json");
  const json j = json::parse(in);
  EXPECT_EQ(j["campaign"], "lab-run-7");
  const auto check = chatterlab::testing::check_results_schema(d.path() / "o/results.json");
  EXPECT_TRUE(check.valid) << check.output;

  // campaign.yaml that is not YAML at all.
  d.write("broken_one/campaign.yaml", "name: [unclosed\n");
  const BinaryRun b = run("report " + quoted(d.path() / "broken_one") + " --out " +
                              quoted(d.path() / "ob") + " --no-pdf --quiet",
                          d);
  EXPECT_EQ(b.status, kExitNothingAnalysed) << b.err;
  std::ifstream inb(d.path() / "ob/results.json");
  EXPECT_EQ(json::parse(inb)["campaign"], "broken_one");

  // No campaign.yaml: nothing is written, exit 1.
  fs::create_directories(d.path() / "nothing");
  const BinaryRun n = run("report " + quoted(d.path() / "nothing") + " --out " +
                              quoted(d.path() / "on") + " --no-pdf --quiet",
                          d);
  EXPECT_EQ(n.status, kExitInputError);
  EXPECT_EQ(n.out, "");
  EXPECT_NE(n.err.find("campaign.yaml"), std::string::npos) << n.err;
  EXPECT_FALSE(fs::exists(d.path() / "on/results.json"));
}

TEST(CliOutputFolder, RefusesAFolderThatIsNotChatterlabs) {
  TempDir d;
  d.write("c/campaign.yaml", chatterlab::testing::kCampaignYaml);
  d.write("thesis/chapter1.tex", "keep me\n");
  const BinaryRun r = run("report " + quoted(d.path() / "c") + " --out " +
                              quoted(d.path() / "thesis") + " --no-pdf --quiet",
                          d);
  EXPECT_EQ(r.status, kExitInputError);
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find("the folder is not empty and is not a chatterlab output folder"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(files_below(d.path() / "thesis"), std::vector<std::string>{"chapter1.tex"});

  d.write("a-file", "x");
  const BinaryRun f = run("report " + quoted(d.path() / "c") + " --out " +
                              quoted(d.path() / "a-file") + " --no-pdf --quiet",
                          d);
  EXPECT_EQ(f.status, kExitInputError);
  EXPECT_NE(f.err.find("exists and is not a folder"), std::string::npos) << f.err;
}

TEST(CliOutputFolder, SimulateAndSynthQuiet) {
  TempDir d;
  d.write("thesis/chapter1.tex", "keep me\n");
  d.write("spec.yaml", "format: chatterlab-simulation/1\n");
  const BinaryRun r = run("simulate " + quoted(d.path() / "spec.yaml") + " --out " +
                              quoted(d.path() / "thesis") + " --quiet",
                          d);
  EXPECT_EQ(r.status, kExitInputError);
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find("chatterlab simulate: --out "), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(d.path() / "thesis/chapter1.tex"));
  // A spec error under --quiet: on stderr only.
  const BinaryRun b = run("simulate " + quoted(d.path() / "spec.yaml") + " --out " +
                              quoted(d.path() / "sim") + " --quiet",
                          d);
  EXPECT_EQ(b.status, kExitInputError);
  EXPECT_EQ(b.out, "");
  EXPECT_NE(b.err.find("chatterlab simulate: "), std::string::npos) << b.err;
}

// A misspelt key of a simulation spec is a warning on stderr, with or without --quiet (stdout
// holds the summary only), and the run goes on.
TEST(CliOutputFolder, SimulateWarnsOnStderrEvenWhenQuiet) {
  TempDir d;
  d.write("spec.yaml",
          "format: chatterlab-simulation/1\n"
          "tool: {teeth: 2, radius_mm: 6.35}\n"
          "modal: {m_kg: 0.03134, c_kg_s: 22.21, k_N_m: 9.84e5}\n"
          "coefficients: {Kt_N_m2: 6.0e8, Kr_N_m2: 2.0e8}\n"
          "cut: {operation: up-milling, spindle_rpm: 15000, feed_per_tooth_mm: 0.0635,\n"
          "      radial_immersion_mm: 0.382, axial_depth_mm: [0.0, 0.1], revolutions_per_mm: 100}\n"
          "steps_per_toth: 100\n");
  const std::string warning =
      "chatterlab simulate: warning: spec.yaml: key 'steps_per_toth' is not part of the format "
      "and is ignored (did you mean 'steps_per_tooth'?)";
  for (const char* quiet : {"", " --quiet"}) {
    SCOPED_TRACE(quiet);
    const BinaryRun r = run("simulate " + quoted(d.path() / "spec.yaml") + " --out " +
                                quoted(d.path() / "sim") + " --results-only" + quiet,
                            d);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find(warning), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("warning"), std::string::npos) << r.out;
    EXPECT_TRUE(fs::exists(d.path() / "sim/results.json"));
  }
}

// `chatterlab lobes` through the binary: quiet prints nothing and writes results.json; a
// misspelt key is a warning on stderr; a spec error exits 1 naming file and key and leaves --out
// as it was; a folder that is not chatterlab's is refused.
TEST(CliOutputFolder, LobesQuietWarningsAndErrors) {
  TempDir d;
  const std::string spec =
      "format: chatterlab-lobes/1\n"
      "tool: {teeth: 2, radius_mm: 6.35}\n"
      "modal: {m_kg: 0.03134, c_kg_s: 22.21, k_N_m: 9.84e5}\n"
      "coefficients: {Kt_N_m2: 6.0e8, Kr_N_m2: 2.0e8}\n"
      "cut: {operation: up-milling, radial_immersion_mm: 6.35}\n"
      "spindle_rpm: [10000, 20000]\n"
      "speeds: 11\n";
  d.write("spec.yaml", spec + "max_depht_mm: 5\n");
  const BinaryRun r = run("lobes " + quoted(d.path() / "spec.yaml") + " --out " +
                              quoted(d.path() / "lobes") + " --no-pdf --quiet --jobs 1",
                          d);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find("chatterlab lobes: warning: spec.yaml: key 'max_depht_mm' is not part of "
                       "the format and is ignored (did you mean 'max_depth_mm'?)"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::exists(d.path() / "lobes/results.json"));
  EXPECT_TRUE(fs::exists(d.path() / "lobes/figures/lobes.svg"));
  d.write("bad.yaml", spec + "max_depth_mm: 0\n");
  const BinaryRun b =
      run("lobes " + quoted(d.path() / "bad.yaml") + " --out " + quoted(d.path() / "lobes"), d);
  EXPECT_EQ(b.status, kExitInputError);
  EXPECT_NE(b.err.find("chatterlab lobes: bad.yaml: key 'max_depth_mm' must be > 0"),
            std::string::npos)
      << b.err;
  EXPECT_TRUE(fs::exists(d.path() / "lobes/figures/lobes.svg"));  // the previous output stays
  d.write("thesis/chapter1.tex", "keep me\n");
  const BinaryRun t =
      run("lobes " + quoted(d.path() / "spec.yaml") + " --out " + quoted(d.path() / "thesis"), d);
  EXPECT_EQ(t.status, kExitInputError);
  EXPECT_NE(t.err.find("chatterlab lobes: --out "), std::string::npos) << t.err;
  EXPECT_TRUE(fs::exists(d.path() / "thesis/chapter1.tex"));
}

// A second run of a smaller campaign into the first run's folder holds exactly the files of a
// run into a fresh folder (tap figures and per-test files of the first run gone, an old PDF
// too), plus a file the user put there.
TEST_F(CliRuns, ReRunLeavesNoStaleFile) {
  TempDir d;
  const fs::path o = d.path() / "o";
  const BinaryRun first =
      run("report " + quoted(campaign()) + " --out " + quoted(o) + " --no-pdf --quiet", d);
  ASSERT_EQ(first.status, 0) << first.err;
  const auto first_files = files_below(o);
  ASSERT_TRUE(std::any_of(first_files.begin(), first_files.end(), [](const std::string& f) {
    return f.rfind("figures/", 0) == 0 && f.find("tap") != std::string::npos;
  })) << "the first run draws tap figures";
  // As if the first run had written a PDF: listed in the manifest like any file it wrote.
  d.write("o/report.pdf", "%PDF-1.7 old\n");
  std::ofstream(o / kManifestName, std::ios::app) << "report.pdf\n";
  d.write("o/notes.txt", "the user's\n");

  const fs::path sparse = d.path() / "sparse";
  fs::copy(campaign(), sparse, fs::copy_options::recursive);
  fs::remove_all(sparse / "tap");
  const BinaryRun second =
      run("report " + quoted(sparse) + " --out " + quoted(o) + " --no-pdf --quiet", d);
  ASSERT_EQ(second.status, 0) << second.err;
  const BinaryRun fresh = run(
      "report " + quoted(sparse) + " --out " + quoted(d.path() / "fresh") + " --no-pdf --quiet", d);
  ASSERT_EQ(fresh.status, 0) << fresh.err;

  auto rerun_files = files_below(o);
  EXPECT_NE(std::find(rerun_files.begin(), rerun_files.end(), "notes.txt"), rerun_files.end());
  rerun_files.erase(std::remove(rerun_files.begin(), rerun_files.end(), "notes.txt"),
                    rerun_files.end());
  EXPECT_EQ(rerun_files, files_below(d.path() / "fresh"));
  EXPECT_FALSE(fs::exists(o / "report.pdf"));
  // The manifest lists what the second run wrote, not the user's file.
  const std::string manifest = file_text(o / kManifestName);
  EXPECT_NE(manifest.find("\nresults.json\n"), std::string::npos) << manifest;
  EXPECT_EQ(manifest.find("notes.txt"), std::string::npos) << manifest;
}

}  // namespace
}  // namespace chatterlab::app
