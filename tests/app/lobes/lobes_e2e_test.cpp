// `chatterlab lobes` end to end on the specs of experiments/lobes/ (docs/format/lobes.md).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>

#include "analysis/common/summary.h"
#include "app/lobes/lobes_run.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::TempDir;
using nlohmann::json;

json read_json(const std::filesystem::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

std::filesystem::path example(const char* name) {
  return std::filesystem::path(CHATTERLAB_SOURCE_DIR) / "experiments/lobes" / name;
}

// The unequal teeth of 000 table 5.2 at 10,000-26,000 rpm: both methods, every key of the
// format, and the limit at 15,000 rpm against the simulator's incline 1.
TEST(LobesEndToEnd, UnequalTeethOfTheSourceTable) {
  TempDir d;
  std::ostringstream log;
  LobesRunOptions o;
  o.pdf = false;
  o.jobs = 2;
  ASSERT_EQ(run_lobes(example("incline1-unequal-teeth.yaml"), d.path(), o, log), 0) << log.str();
  const json r = read_json(d.path() / "results.json");
  EXPECT_EQ(r["format"], "chatterlab-lobes-results/1");
  const json& sd = r["methods"]["semi-discretization"];
  const json& zoa = r["methods"]["zoa"];
  ASSERT_EQ(sd["spindle_rpm"].size(), 200u);
  ASSERT_EQ(sd["limit_depth_mm"].size(), 200u);
  ASSERT_EQ(sd["type"].size(), 200u);
  ASSERT_EQ(sd["chatter_hz"].size(), 200u);
  ASSERT_EQ(zoa["limit_depth_mm"].size(), 200u);
  EXPECT_EQ(sd["period"], "revolution");  // unequal teeth
  EXPECT_FALSE(zoa.contains("type"));     // ZOA gives no boundary type
  int flips = 0, hopfs = 0;
  double lowest = 1e9;
  for (std::size_t i = 0; i < 200; ++i) {
    const json& b = sd["limit_depth_mm"][i];
    if (b.is_null()) continue;
    lowest = std::min(lowest, b.get<double>());
    const std::string t = sd["type"][i];
    EXPECT_TRUE(t == "flip" || t == "hopf") << t;
    flips += t == "flip";
    hopfs += t == "hopf";
    // A flip's multiplier is real; a Hopf's is complex.
    EXPECT_EQ(t == "flip", sd["critical_multiplier_im"][i].get<double>() == 0.0) << i;
    EXPECT_GE(std::hypot(sd["critical_multiplier_re"][i].get<double>(),
                         sd["critical_multiplier_im"][i].get<double>()),
              1.0);
  }
  EXPECT_GT(hopfs, 0);
  EXPECT_GT(flips, 0);  // at this low immersion the flip lobes reach down between Hopf lobes
  EXPECT_DOUBLE_EQ(sd["minimum_limit_depth_mm"].get<double>(), lowest);
  EXPECT_TRUE(std::filesystem::exists(d.path() / "figures/lobes.svg"));
  EXPECT_TRUE(std::filesystem::exists(d.path() / "figures/lobes.png"));
  std::ifstream in(d.path() / "index.html");
  const std::string html((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(html.find("figures/lobes.svg"), std::string::npos);
  EXPECT_NE(html.find("incline1-unequal-teeth.yaml"), std::string::npos);
}

// --results-only writes results.json alone; a bad spec writes nothing and names file and key.
TEST(LobesEndToEnd, ResultsOnlyAndBadSpec) {
  TempDir d;
  std::ostringstream log;
  LobesRunOptions o;
  o.report = false;
  o.jobs = 1;
  ASSERT_EQ(run_lobes(example("insperger-stepan-1dof.yaml"), d.path() / "out", o, log), 0);
  EXPECT_TRUE(std::filesystem::exists(d.path() / "out/results.json"));
  EXPECT_FALSE(std::filesystem::exists(d.path() / "out/index.html"));
  EXPECT_FALSE(std::filesystem::exists(d.path() / "out/figures"));
  const json r = read_json(d.path() / "out/results.json");
  EXPECT_EQ(r["methods"]["semi-discretization"]["period"], "tooth");
  const auto bad = d.write("bad.yaml", "format: chatterlab-lobes/1\ntool: {teeth: 2}\n");
  try {
    run_lobes(bad, d.path() / "bad-out", o, log);
    FAIL() << "a spec without radius_mm was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml: key 'tool.radius_mm'"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(d.path() / "bad-out"));
}

}  // namespace
}  // namespace chatterlab::app
