// chatterlab compare (app/nightly/compare.h): which numbers count as moved, the tolerance
// families, the flags, the tolerances file's messages and the command's exit status and forms.
#include "app/nightly/compare.h"

#include <gtest/gtest.h>

#include <fstream>

#include "analysis/common/summary.h"
#include "render/temp_dir.h"
#include "tests/app/cli/run_binary.h"

namespace chatterlab::app {
namespace {

using nlohmann::json;

json sample() {
  return json::parse(R"({
    "format": "chatterlab-results/1",
    "runtime_s": 12.5,
    "tests": {
      "tap/x": {"status": "ok", "runtime_s": 0.25, "modes": [{"fn_hz": 912.4, "zeta": 0.031}]},
      "cuts/incline": {"status": "ok", "message": "",
                       "identification": {"c_kg_s": 22.22, "c_kg_s_ci95": [22.16, 22.28]}}
    },
    "identified": {"Kt1_N_m2": 2.491e8}
  })");
}

const Change* find(const Comparison& c, const std::string& key) {
  for (const auto& ch : c.changes) {
    if (ch.key == key) return &ch;
  }
  return nullptr;
}

TEST(Compare, IdenticalDocumentsHaveNoChangeAndTimingsAreNotCompared) {
  json b = sample();
  b["runtime_s"] = 99.0;
  b["tests"]["tap/x"]["runtime_s"] = 3.0;
  const Comparison c = compare_results(sample(), b);
  EXPECT_TRUE(c.changes.empty());
  EXPECT_EQ(c.flags(), 0);
  // fn, zeta, c, the two interval ends, Kt1: the two timings are not counted.
  EXPECT_EQ(c.numbers_compared, 6);
  EXPECT_EQ(c.numbers_equal, 6);
}

TEST(Compare, TheWorkerThreadsAreNotComparedUnlessAUserRuleSaysSo) {
  json a = sample();
  a["settings"] = {{"pipeline", {{"jobs", 2}}}, {"cut", {{"window_s", 0.02}}}};
  json b = a;
  b["settings"]["pipeline"]["jobs"] = 8;
  Comparison c = compare_results(a, b);
  EXPECT_TRUE(c.changes.empty());
  EXPECT_EQ(c.numbers_compared, 7);  // the six of sample() and window_s
  // Under a campaign's name, as compare --site gives them.
  c = compare_results(json{{"demo", a}}, json{{"demo", b}});
  EXPECT_TRUE(c.changes.empty());
  // Another setting is compared; a user's rule comes first.
  b["settings"]["cut"]["window_s"] = 0.05;
  CompareOptions o;
  o.rules.push_back({"settings.pipeline.jobs", 0, 0, false});
  c = compare_results(a, b, o);
  ASSERT_EQ(c.flags(), 2);
  EXPECT_EQ(c.changes[0].key, "settings.cut.window_s");
  EXPECT_EQ(c.changes[1].key, "settings.pipeline.jobs");
  EXPECT_EQ(c.changes[1].rule, "settings.pipeline.jobs");
}

TEST(Compare, ANumberBeyondTheDefaultToleranceIsFlaggedWithItsChange) {
  json b = sample();
  b["tests"]["tap/x"]["modes"][0]["fn_hz"] = 912.4 * (1 + 1e-6);  // beyond rel 1e-9
  b["identified"]["Kt1_N_m2"] = 2.491e8 * (1 + 1e-12);            // within
  const Comparison c = compare_results(sample(), b);
  ASSERT_EQ(c.changes.size(), 1u);
  const Change& ch = c.changes[0];
  EXPECT_EQ(ch.key, "tests.tap/x.modes[0].fn_hz");
  EXPECT_EQ(ch.kind, Change::Kind::kMoved);
  EXPECT_TRUE(ch.flag);
  EXPECT_NEAR(ch.abs_change, 912.4e-6, 1e-12);
  EXPECT_NEAR(ch.rel_change, 1e-6 / (1 + 1e-6), 1e-12);
  EXPECT_EQ(ch.rule, "default");
  EXPECT_EQ(c.flags(), 1);
}

TEST(Compare, TheFirstMatchingRuleDecidesAndAnIgnoredFamilyIsNotCompared) {
  json b = sample();
  b["tests"]["cuts/incline"]["identification"]["c_kg_s_ci95"] = {22.10, 22.34};  // ~0.3 %
  b["tests"]["tap/x"]["modes"][0]["zeta"] = 0.035;                               // 13 %
  CompareOptions o;
  o.rules.push_back({"*_ci95*", 0.01, 0, false});
  o.rules.push_back({"*.zeta", 0.2, 0, false});
  o.rules.push_back({"*", 0, 0, true});  // never reached for the two above
  Comparison c = compare_results(sample(), b, o);
  EXPECT_TRUE(c.changes.empty());
  // A tighter family flags the interval's both ends; the absolute bound adds to the relative.
  o.rules = {{"*_ci95*", 1e-3, 0, false}};
  c = compare_results(sample(), b, o);
  ASSERT_EQ(c.flags(), 3);  // both ends and zeta (default)
  EXPECT_EQ(find(c, "tests.cuts/incline.identification.c_kg_s_ci95[0]")->rule, "*_ci95*");
  o.rules = {{"*_ci95*", 1e-3, 0.1, false}, {"*.zeta", 0, 0.005, false}};
  c = compare_results(sample(), b, o);
  EXPECT_EQ(c.flags(), 0);
  // A user's rule overrides the built-in one for timings.
  json t = sample();
  t["runtime_s"] = 13.0;
  o.rules = {{"runtime_s", 0.01, 0, false}};
  c = compare_results(sample(), t, o);
  ASSERT_EQ(c.flags(), 1);
  EXPECT_EQ(c.changes[0].key, "runtime_s");
}

TEST(Compare, AVanishedNumberAndAFailedStatusAreFlaggedAddedNumbersAndTextAreListed) {
  json b = sample();
  b["tests"]["cuts/incline"] = {{"status", "skipped"}, {"message", "needs the hammer mode"}};
  b["tests"]["tap/y"] = {{"status", "ok"}, {"modes", {{{"fn_hz", 950.0}}}}};
  const Comparison c = compare_results(sample(), b);
  EXPECT_EQ(find(c, "tests.cuts/incline.identification.c_kg_s")->kind, Change::Kind::kRemoved);
  EXPECT_TRUE(find(c, "tests.cuts/incline.identification.c_kg_s")->flag);
  EXPECT_TRUE(find(c, "tests.cuts/incline.status")->flag);
  EXPECT_EQ(find(c, "tests.cuts/incline.message")->kind, Change::Kind::kText);
  EXPECT_FALSE(find(c, "tests.cuts/incline.message")->flag);
  EXPECT_EQ(find(c, "tests.tap/y.modes[0].fn_hz")->kind, Change::Kind::kAdded);
  EXPECT_FALSE(find(c, "tests.tap/y.modes[0].fn_hz")->flag);
  // c, its two interval ends and the status.
  EXPECT_EQ(c.flags(), 4);
  EXPECT_TRUE(c.changes.front().flag);  // flags first
  // The way back: a status that becomes ok is not a regression.
  const Comparison back = compare_results(b, sample());
  EXPECT_FALSE(find(back, "tests.cuts/incline.status")->flag);
  // A number that became null (not finite) has vanished.
  json n = sample();
  n["identified"]["Kt1_N_m2"] = nullptr;
  EXPECT_TRUE(find(compare_results(sample(), n), "identified.Kt1_N_m2")->flag);
}

class CompareFiles : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto p = dir_.path() / name;
    std::ofstream(p) << text;
    return p;
  }
  render::TempDir dir_{"compare"};
};

TEST_F(CompareFiles, TheTolerancesFileIsReadAndItsMistakesNameTheFileAndKey) {
  const CompareOptions o = load_tolerances(write("tol.yaml", R"(
default: {rel: 1.0e-6, abs: 1.0e-12}
rules:
  - {keys: "*_ci95*", rel: 0.05}
  - {keys: "tests.*.variants*", ignore: true}
)"));
  EXPECT_DOUBLE_EQ(o.fallback.rel, 1e-6);
  EXPECT_DOUBLE_EQ(o.fallback.abs, 1e-12);
  ASSERT_EQ(o.rules.size(), 2u);
  EXPECT_EQ(o.rules[0].keys, "*_ci95*");
  EXPECT_DOUBLE_EQ(o.rules[0].rel, 0.05);
  EXPECT_TRUE(o.rules[1].ignore);
  const auto bad = write("bad.yaml", "rules:\n  - {rel: -1}\n  - {keys: x, ignore: maybe}\n");
  try {
    load_tolerances(bad);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("bad.yaml"), std::string::npos) << m;
    EXPECT_NE(m.find("rules[0].keys"), std::string::npos) << m;
    EXPECT_NE(m.find("rules[0].rel"), std::string::npos) << m;
    EXPECT_NE(m.find("rules[1].ignore"), std::string::npos) << m;
  }
  EXPECT_THROW(read_json_file(write("no.json", "{\"a\": ")), InputError);
  EXPECT_THROW(read_json_file(dir_.path() / "absent.json"), InputError);
}

TEST_F(CompareFiles, TheCommandExitsOneOnAFlagAndZeroOtherwiseInItsThreeForms) {
  using chatterlab::testing::quoted;
  using chatterlab::testing::run_chatterlab;
  const auto a = write("a.json", sample().dump());
  json changed = sample();
  changed["identified"]["Kt1_N_m2"] = 2.6e8;
  const auto b = write("b.json", changed.dump());
  json timed = sample();
  timed["runtime_s"] = 40.0;
  const auto same = write("same.json", timed.dump());

  auto r = run_chatterlab("compare " + quoted(a) + " " + quoted(same), dir_.path());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("6 numbers compared, 6 within tolerance; 0 changes, 0 flagged"),
            std::string::npos)
      << r.out;

  const auto html = dir_.path() / "diff.html";
  r = run_chatterlab("compare " + quoted(a) + " " + quoted(b) + " --json --html " + quoted(html),
                     dir_.path());
  EXPECT_EQ(r.status, 1) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["format"], "chatterlab-compare/1");
  EXPECT_EQ(j["flags"], 1);
  ASSERT_EQ(j["changes"].size(), 1u);
  EXPECT_EQ(j["changes"][0]["key"], "identified.Kt1_N_m2");
  EXPECT_NEAR(j["changes"][0]["rel_change"].get<double>(), (2.6e8 - 2.491e8) / 2.6e8, 1e-12);
  const std::string page = chatterlab::testing::file_text(html);
  EXPECT_NE(page.find("<code>identified.Kt1_N_m2</code>"), std::string::npos);
  EXPECT_NE(page.find("1 flagged"), std::string::npos);

  // A loose enough family passes the same pair.
  const auto tol = write("tol.yaml", "rules:\n  - {keys: \"identified.*\", rel: 0.05}\n");
  r = run_chatterlab("compare " + quoted(a) + " " + quoted(b) + " --tolerances " + quoted(tol),
                     dir_.path());
  EXPECT_EQ(r.status, 0) << r.out << r.err;

  r = run_chatterlab("compare " + quoted(a) + " " + quoted(dir_.path() / "absent.json"),
                     dir_.path());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("absent.json: cannot be read"), std::string::npos) << r.err;
  r = run_chatterlab("compare " + quoted(a), dir_.path());
  EXPECT_EQ(r.status, 2);
}

}  // namespace
}  // namespace chatterlab::app
