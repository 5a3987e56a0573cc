// The input boundary (issue 16): every file a test.yaml names is resolved inside the campaign
// and must be a regular file, checked before it is opened. A test naming a file outside (`..`,
// an absolute path, a symlink leading out) or a folder, FIFO or symlink loop is skipped with a
// message naming its test.yaml and key; the rest of the campaign is analysed; nothing outside
// is read or hashed; nothing hangs; the campaign folder is not changed.
#include "app/core/input_boundary.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/cutting/slot_synth.h"
#include "app/cli/validate.h"
#include "app/core/campaign.h"
#include "app/core/hashing.h"
#include "app/core/signals.h"
#include "app/report/report.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::kCampaignYaml;
using chatterlab::testing::TempDir;
using nlohmann::json;

// What a line of the outside file holds: never to be seen in a report.
const char* kSecret = "outside-secret-7f3a";

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every entry below `root` (symlinks not followed): its type and, for a regular file, its
// SHA-256, for a symlink its target (a FIFO is never opened).
std::map<std::string, std::string> snapshot(const fs::path& root) {
  std::map<std::string, std::string> out;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator();
       ++it) {
    const std::string rel = it->path().lexically_relative(root).generic_string();
    const fs::file_status st = fs::symlink_status(it->path());
    std::string what = std::to_string(static_cast<int>(st.type()));
    if (st.type() == fs::file_type::regular) {
      // The sparse file above the size limit: its size stands for its bytes (all zero).
      const auto bytes = fs::file_size(it->path());
      what += " " + (bytes > kMaxInputFileBytes ? std::to_string(bytes) : sha256_file(it->path()));
    }
    if (st.type() == fs::file_type::symlink) what += " -> " + fs::read_symlink(it->path()).string();
    out[rel] = what;
  }
  return out;
}

void write_dyno(const fs::path& file, double feed_mm, std::uint64_t seed) {
  cutting::SlotRecordSpec s;
  s.spindle_rpm = 500;
  s.feed_per_tooth_m = feed_mm * 1e-3;
  s.depth_m = 2e-3;
  s.coefficients = {6.61e8, 3.17e8, 9740, 7620};
  s.theta_dyn_rad = -0.41;
  s.noise_std_N = 1.0;
  s.fs_hz = 10000;
  s.duration_s = 1.5;
  s.seed = seed;
  const auto rec = cutting::generate_slot_record(s);
  fs::create_directories(file.parent_path());
  write_signals(file, {"zero", "Fy", "Fx"}, {&rec.zero_V, &rec.Fy_N, &rec.Fx_N});
}

std::string dyno_yaml(double feed_mm, const std::string& file) {
  std::ostringstream y;
  y << "kind: dyno-slot\nspindle_rpm: 500\nfeed_per_tooth_mm: " << feed_mm
    << "\naxial_depth_mm: 2\nsample_rate_hz: 10000\n"
    << "data: {file: '" << file << "', channels: [zero, Fy, Fx]}\n";
  return y.str();
}

std::string csv_yaml(const std::string& file) {
  return "kind: dyno-slot\nspindle_rpm: 500\nfeed_per_tooth_mm: 0.1\naxial_depth_mm: 2\n"
         "sample_rate_hz: 10000\ndata: {file: '" +
         file + "'}\n";
}

// A campaign in d/campaign with three good dyno tests (one through `..` inside the campaign,
// one through a symlink inside it) and a test for each way out or each non-regular file;
// d/outside.csv is a real file beside the campaign.
struct Fixture {
  TempDir d;
  fs::path campaign = d.path() / "campaign";
  fs::path outside = d.path() / "outside.csv";
  // id -> the exact skip reason.
  std::map<std::string, std::string> bad;

  Fixture() {
    d.write("outside.csv", std::string("Fx,Fy,zero\n1,2,") + kSecret + "\n");
    d.write("campaign/campaign.yaml", kCampaignYaml);
    write_dyno(campaign / "good/a/rec.f64", 0.05, 1);
    d.write("campaign/good/a/test.yaml", dyno_yaml(0.05, "rec.f64"));
    // A file shared one level up (as `chatterlab init` writes): `..` that stays inside.
    write_dyno(campaign / "good/b.f64", 0.10, 2);
    d.write("campaign/good/b/test.yaml", dyno_yaml(0.10, "../b.f64"));
    // A symlink whose target stays inside the campaign.
    write_dyno(campaign / "good/c-real.f64", 0.15, 3);
    fs::create_directories(campaign / "good/c");
    fs::create_symlink("../c-real.f64", campaign / "good/c/rec.f64");
    d.write("campaign/good/c/test.yaml", dyno_yaml(0.15, "rec.f64"));

    auto add = [&](const std::string& id, const std::string& file, const std::string& why) {
      d.write("campaign/" + id + "/test.yaml", csv_yaml(file));
      bad[id] = id + "/test.yaml: key 'data.file' '" + file + "': " + why;
    };
    add("up", "../../outside.csv", "must lie inside the campaign folder");
    add("abs", outside.string(),
        "is an absolute path: must be relative to the test folder and lie inside the campaign "
        "folder");
    fs::create_directories(campaign / "linkout");
    fs::create_symlink(outside, campaign / "linkout/rec.csv");
    add("linkout", "rec.csv", "must lie inside the campaign folder (a symlink leads outside)");
    fs::create_directories(campaign / "dirlink");
    fs::create_directory_symlink(d.path(), campaign / "dirlink/shared");
    add("dirlink", "shared/outside.csv",
        "must lie inside the campaign folder (a symlink leads outside)");
    fs::create_directories(campaign / "folder/rec.csv");
    add("folder", "rec.csv", "is a folder, not a regular file");
    fs::create_directories(campaign / "fifo");
    EXPECT_EQ(::mkfifo((campaign / "fifo/rec.csv").c_str(), 0600), 0);
    add("fifo", "rec.csv", "is a FIFO, not a regular file");
    fs::create_directories(campaign / "loop");
    fs::create_symlink("loop.csv", campaign / "loop/rec.csv");
    fs::create_symlink("rec.csv", campaign / "loop/loop.csv");
    add("loop", "rec.csv", "is a symlink loop, not a regular file");
    // A file above the size limit (sparse: nothing is written, nothing may read it), and a
    // name longer than the file system allows.
    fs::resize_file(d.write("campaign/huge/rec.csv", "Fx,Fy,zero\n"), kMaxInputFileBytes + 1);
    add("huge", "rec.csv", "is 4.29 GB, above the 4 GiB limit of an input file");
    const std::string long_name(300, 'n');
    add("longname", long_name + ".csv",
        "cannot be resolved (" + std::make_error_code(std::errc::filename_too_long).message() +
            ")");
    // Another file key (a tap test's measured FRF) through the same boundary.
    d.write("campaign/frf/test.yaml",
            "kind: tap\naxis: x\nresponse: displacement\nfrf: {file: ../../outside.csv}\n");
    bad["frf"] =
        "frf/test.yaml: key 'frf.file' '../../outside.csv': must lie inside the campaign folder";
    fs::create_directories(campaign / "frflink");
    fs::create_symlink(outside, campaign / "frflink/frf.csv");
    d.write("campaign/frflink/test.yaml",
            "kind: tap\naxis: y\nresponse: displacement\nfrf: {file: frf.csv}\n");
    bad["frflink"] =
        "frflink/test.yaml: key 'frf.file' 'frf.csv': must lie inside the campaign folder (a "
        "symlink leads outside)";
  }
};

TEST(InputBoundary, ReportSkipsEachBadFileAndAnalysesTheRest) {
  Fixture f;
  const auto before = snapshot(f.campaign);
  const auto around = snapshot(f.d.path());  // the campaign, the outside files and folders
  const fs::path out = f.d.path() / "out";
  std::ostringstream log;
  ReportOptions opt;
  opt.pdf = false;
  opt.jobs = 2;
  // The FIFO must never be opened: the whole report finishes quickly.
  auto run = std::async(std::launch::async, [&] { return run_report(f.campaign, out, opt, log); });
  if (run.wait_for(std::chrono::seconds(120)) != std::future_status::ready) {
    ADD_FAILURE() << "report did not finish within 120 s (a FIFO opened?)";
    std::_Exit(1);
  }
  ASSERT_EQ(run.get(), 0) << log.str();

  const std::string results = read_text(out / "results.json");
  const json r = json::parse(results);
  const json& t = r["tests"];
  for (const char* id : {"good/a", "good/b", "good/c"}) {
    EXPECT_EQ(t[id]["status"], "ok") << id << t[id].dump();
  }
  EXPECT_TRUE(r["groups"].contains("dyno-slot"));
  for (const auto& [id, why] : f.bad) {
    ASSERT_TRUE(t.contains(id)) << id;
    EXPECT_EQ(t[id]["status"], "skipped") << id;
    EXPECT_EQ(t[id]["skip_reason"], why) << id;
  }
  // Nothing outside was read: no line of the outside file, and it is not hashed.
  const std::string html = read_text(out / "index.html");
  EXPECT_EQ(results.find(kSecret), std::string::npos);
  EXPECT_EQ(html.find(kSecret), std::string::npos);
  EXPECT_EQ(log.str().find(kSecret), std::string::npos);
  const json& inputs = r["inputs_sha256"];
  EXPECT_TRUE(inputs.contains("good/b.f64")) << inputs.dump();
  EXPECT_TRUE(inputs.contains("good/c-real.f64")) << inputs.dump();
  for (const auto& [name, hash] : inputs.items()) {
    EXPECT_EQ(name.find("outside"), std::string::npos) << name;
    EXPECT_EQ(name.find(".."), std::string::npos) << name;
    EXPECT_NE(name, "fifo/rec.csv");
    EXPECT_NE(name, "folder/rec.csv");
  }
  // The reasons are on the page (the quoted file names are HTML-escaped there).
  for (const auto& [id, why] : f.bad) {
    const std::string reason = why.substr(why.rfind("': ") + 3);
    EXPECT_NE(html.find(reason), std::string::npos) << reason;
  }
  // The campaign folder is unchanged, file by file, and nothing was written beside it or to the
  // files outside that its keys name: everything new is under --out.
  EXPECT_EQ(snapshot(f.campaign), before);
  auto after = snapshot(f.d.path());
  for (auto it = after.begin(); it != after.end();) {
    it = (it->first == "out" || it->first.rfind("out/", 0) == 0) ? after.erase(it) : ++it;
  }
  EXPECT_EQ(after, around);
}

TEST(InputBoundary, ValidateReportsTheSameProblems) {
  Fixture f;
  const auto before = snapshot(f.campaign);
  auto run = std::async(std::launch::async, [&] {
    CampaignSpec c = load_campaign(f.campaign);
    std::ostringstream out;
    const int code = validate_campaign(c, out);
    return std::make_pair(code, out.str());
  });
  if (run.wait_for(std::chrono::seconds(60)) != std::future_status::ready) {
    ADD_FAILURE() << "validate did not finish within 60 s (a FIFO opened?)";
    std::_Exit(1);
  }
  const auto [code, text] = run.get();
  EXPECT_EQ(code, 1);
  for (const auto& [id, why] : f.bad) EXPECT_NE(text.find(why), std::string::npos) << why << text;
  EXPECT_EQ(text.find(kSecret), std::string::npos);
  EXPECT_NE(text.find("3 usable"), std::string::npos) << text;
  EXPECT_EQ(snapshot(f.campaign), before);
}

TEST(InputBoundary, CheckInputFile) {
  TempDir d;
  d.write("c/campaign.yaml", kCampaignYaml);
  d.write("c/t/a.csv", "x\n1\n");
  d.write("c/shared.csv", "x\n1\n");
  d.write("out.csv", "x\n1\n");
  const fs::path root = d.path() / "c", folder = root / "t";
  auto problem = [&](const std::string& v) { return check_input_file(root, folder, v).problem; };
  EXPECT_EQ(problem("a.csv"), "");
  EXPECT_EQ(check_input_file(root, folder, "a.csv").path, folder / "a.csv");
  EXPECT_EQ(problem("../shared.csv"), "");
  EXPECT_EQ(problem("./../t/a.csv"), "");
  EXPECT_EQ(problem("../../out.csv"), "'../../out.csv': must lie inside the campaign folder");
  EXPECT_EQ(problem("../../c/shared.csv"), "");  // out and back in: lexically inside
  EXPECT_EQ(problem(".."), "'..': must lie inside the campaign folder");  // the root itself
  EXPECT_EQ(problem("../.."), "'../..': must lie inside the campaign folder");
  EXPECT_EQ(problem("gone.csv"), "'gone.csv': file not found");
  EXPECT_EQ(problem(""), "'': names no file");
  EXPECT_NE(problem((d.path() / "out.csv").string()).find("is an absolute path"),
            std::string::npos);
  // A dangling symlink (nothing to read, wherever it points), and one that stays inside.
  fs::create_symlink(d.path() / "nothing.csv", folder / "dangling-out.csv");
  EXPECT_EQ(problem("dangling-out.csv"), "'dangling-out.csv': file not found");
  fs::create_symlink("nothing.csv", folder / "dangling-in.csv");
  EXPECT_EQ(problem("dangling-in.csv"), "'dangling-in.csv': file not found");
  // A symlink to a device leads outside; the device itself is no regular file either.
  fs::create_symlink("/dev/null", folder / "null.csv");
  EXPECT_EQ(problem("null.csv"),
            "'null.csv': must lie inside the campaign folder (a symlink leads outside)");
  EXPECT_EQ(regular_file_problem("/dev/null"), "is a device, not a regular file");
  // Without a campaign root, the test folder is the boundary.
  EXPECT_EQ(check_input_file("", folder, "a.csv").problem, "");
  EXPECT_EQ(check_input_file("", folder, "../shared.csv").problem,
            "'../shared.csv': must lie inside the campaign folder");

  // The throwing form names the test.yaml and the key.
  try {
    resolve_input_file(root, folder, "t/test.yaml", "data.file", "../../out.csv");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "t/test.yaml: key 'data.file' '../../out.csv': must lie inside the campaign "
                 "folder");
  }
  // Provenance hashing reads only regular files inside.
  EXPECT_TRUE(regular_file_inside(root, folder / "a.csv"));
  EXPECT_FALSE(regular_file_inside(root, d.path() / "out.csv"));
  EXPECT_FALSE(regular_file_inside(root, folder / "null.csv"));
  EXPECT_FALSE(regular_file_inside(root, folder));
}

// The loader itself: a symlink loop anywhere in the campaign does not end the run; a test.yaml
// that is a symlink leading out is not read and is a test with that error.
TEST(InputBoundary, LoaderSurvivesLoopsAndRefusesTestYamlLeadingOut) {
  TempDir d;
  d.write("c/campaign.yaml", kCampaignYaml);
  d.write("secret.yaml", std::string("kind: tap\nnote: ") + kSecret + "\n");
  fs::create_directories(d.path() / "c/x");
  fs::create_symlink("b", d.path() / "c/x/a");
  fs::create_symlink("a", d.path() / "c/x/b");
  fs::create_symlink("test.yaml", d.path() / "c/x/test.yaml");  // a loop of its own
  fs::create_directories(d.path() / "c/out");
  fs::create_symlink(d.path() / "secret.yaml", d.path() / "c/out/test.yaml");
  const CampaignSpec c = load_campaign(d.path() / "c");
  EXPECT_TRUE(c.errors.empty());
  ASSERT_EQ(c.tests.size(), 2u);
  EXPECT_EQ(c.tests[0].id, "out");
  ASSERT_EQ(c.tests[0].errors.size(), 1u);
  EXPECT_EQ(c.tests[0].errors[0],
            "out/test.yaml: must lie inside the campaign folder (a symlink leads outside)");
  EXPECT_TRUE(c.tests[0].kind.empty());
  EXPECT_EQ(c.tests[1].id, "x");
  ASSERT_EQ(c.tests[1].errors.size(), 1u);
  EXPECT_EQ(c.tests[1].errors[0], "x/test.yaml: is a symlink loop, not a regular file");
}

// campaign.yaml, truth.yaml and each test.yaml are inside the boundary too: a campaign.yaml
// leading out or of the wrong type is a campaign error (nothing of it read), a truth.yaml
// leading out a warning (no comparison with the truth, its values never read), a test.yaml that
// is a FIFO, a folder or a dangling link a test skipped with the reason (before, such a test
// silently vanished from the campaign). Nothing hangs on the FIFOs.
TEST(InputBoundary, CampaignTruthAndTestYamlsAreInsideTheBoundary) {
  TempDir d;
  d.write("secret/campaign.yaml", kCampaignYaml);
  d.write("secret/truth.yaml", std::string("note: ") + kSecret + "\n");
  auto load = std::async(std::launch::async, [&] {
    std::vector<CampaignSpec> out;
    // campaign.yaml a symlink leading out, then a FIFO.
    fs::create_directories(d.path() / "a");
    fs::create_symlink(d.path() / "secret/campaign.yaml", d.path() / "a/campaign.yaml");
    out.push_back(load_campaign(d.path() / "a"));
    fs::create_directories(d.path() / "b");
    EXPECT_EQ(::mkfifo((d.path() / "b/campaign.yaml").c_str(), 0600), 0);
    out.push_back(load_campaign(d.path() / "b"));
    fs::create_directories(d.path() / "e");  // a symlink loop: no exception
    fs::create_symlink("campaign.yaml", d.path() / "e/campaign.yaml");
    out.push_back(load_campaign(d.path() / "e"));
    // A good campaign.yaml; truth.yaml leading out; test.yaml a FIFO, a folder, a dangling link.
    d.write("c/campaign.yaml", kCampaignYaml);
    fs::create_symlink(d.path() / "secret/truth.yaml", d.path() / "c/truth.yaml");
    fs::create_directories(d.path() / "c/fifo");
    EXPECT_EQ(::mkfifo((d.path() / "c/fifo/test.yaml").c_str(), 0600), 0);
    fs::create_directories(d.path() / "c/folder/test.yaml");
    fs::create_directories(d.path() / "c/gone");
    fs::create_symlink("nothing.yaml", d.path() / "c/gone/test.yaml");
    out.push_back(load_campaign(d.path() / "c"));
    return out;
  });
  if (load.wait_for(std::chrono::seconds(60)) != std::future_status::ready) {
    ADD_FAILURE() << "load_campaign did not finish within 60 s (a FIFO opened?)";
    std::_Exit(1);
  }
  std::vector<CampaignSpec> c = load.get();  // validate_campaign takes it to change
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c[0].errors, std::vector<std::string>{"campaign.yaml: must lie inside the campaign "
                                                  "folder (a symlink leads outside)"});
  EXPECT_TRUE(c[0].tests.empty());
  EXPECT_EQ(c[1].errors, std::vector<std::string>{"campaign.yaml: is a FIFO, not a regular file"});
  EXPECT_EQ(c[2].errors,
            std::vector<std::string>{"campaign.yaml: is a symlink loop, not a regular file"});
  for (int k = 0; k < 3; ++k) EXPECT_FALSE(c[static_cast<std::size_t>(k)].campaign_yaml_found);
  // report stops at once with the reason, as for a missing campaign.yaml (before, it went on
  // with no test and said "no test.yaml found"), and writes nothing.
  std::ostringstream log;
  ReportOptions opt;
  opt.pdf = false;
  EXPECT_EQ(run_report(d.path() / "a", d.path() / "out-a", opt, log), 1);
  EXPECT_EQ(log.str(),
            "chatterlab report: campaign.yaml: must lie inside the campaign folder (a symlink "
            "leads outside)\n");
  EXPECT_FALSE(fs::exists(d.path() / "out-a"));

  EXPECT_TRUE(c[3].errors.empty());
  EXPECT_FALSE(c[3].has_truth);
  EXPECT_NE(std::find(c[3].warnings.begin(), c[3].warnings.end(),
                      "truth.yaml: must lie inside the campaign folder (a symlink leads outside); "
                      "not read (no comparison with the truth)"),
            c[3].warnings.end());
  ASSERT_EQ(c[3].tests.size(), 3u);
  const std::map<std::string, std::string> want = {
      {"fifo", "fifo/test.yaml: is a FIFO, not a regular file"},
      {"folder", "folder/test.yaml: is a folder, not a regular file"},
      {"gone", "gone/test.yaml: file not found"}};
  for (const TestSpec& t : c[3].tests) {
    ASSERT_EQ(want.count(t.id), 1u) << t.id;
    EXPECT_EQ(t.errors, std::vector<std::string>{want.at(t.id)}) << t.id;
  }
  // validate counts them as tests found and not usable, and says why.
  std::ostringstream text;
  EXPECT_EQ(validate_campaign(c[3], text), 1);
  EXPECT_NE(text.str().find("3 tests found, 0 usable"), std::string::npos) << text.str();
  for (const auto& [id, why] : want) EXPECT_NE(text.str().find(why), std::string::npos) << why;
  EXPECT_EQ(text.str().find(kSecret), std::string::npos);
}

}  // namespace
}  // namespace chatterlab::app
