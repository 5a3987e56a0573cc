// A cut test's bifurcation keys in results.json (EXPERIMENT_FORMAT.md section 2:
// bifurcation_depth_mm null when the run shows no bifurcation, absent when its depth does not
// vary): a ramped cut always carries the key, null beside bifurcation_status and its reason when
// the detector could not run (docs/format/results-json.md, "kind: cut").
#include <gtest/gtest.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "app/kinds/cut/cut_kind.h"

namespace chatterlab::app {
namespace {

using nlohmann::json;

json results_of(std::unique_ptr<CutOutcome> c) {
  TestSpec spec;
  spec.id = "cuts/incline";
  spec.kind = "cut";
  TestOutcome t;
  t.spec = &spec;
  t.status.succeed();
  t.result = std::move(c);
  return CutKind().results(t);
}

TEST(CutResultsJson, RampedCutWhoseDetectorCouldNotRunHasANullDepthWithTheReason) {
  auto c = std::make_unique<CutOutcome>();
  c->summary.succeed();
  c->ramped = true;
  c->bifurcation_status.fail(
      "the cut window holds 12 revolutions: too few for the bifurcation detector (more than 61)");
  const json j = results_of(std::move(c));
  ASSERT_TRUE(j.contains("bifurcation_depth_mm")) << j.dump();
  EXPECT_TRUE(j["bifurcation_depth_mm"].is_null());
  EXPECT_EQ(j["bifurcation_status"], "skipped");
  EXPECT_EQ(j["bifurcation_skip_reason"],
            "the cut window holds 12 revolutions: too few for the bifurcation detector (more "
            "than 61)");
  for (const char* k : {"bifurcation_verdict", "bifurcation_noise_floor_m", "chatter_islands"}) {
    EXPECT_FALSE(j.contains(k)) << k;
  }
}

TEST(CutResultsJson, RampedCutWhoseDetectorDidNotRunSaysSo) {
  auto c = std::make_unique<CutOutcome>();
  c->summary.succeed();
  c->ramped = true;  // bifurcation_status left "not run"
  const json j = results_of(std::move(c));
  EXPECT_TRUE(j.at("bifurcation_depth_mm").is_null());
  EXPECT_EQ(j["bifurcation_status"], "skipped");
  EXPECT_EQ(j["bifurcation_skip_reason"], "the bifurcation detector did not run");
}

TEST(CutResultsJson, RampedCutWithoutBifurcationHasANullDepthAndNoStatus) {
  auto c = std::make_unique<CutOutcome>();
  c->summary.succeed();
  c->ramped = true;
  c->bifurcation_status.succeed();
  c->bifurcation.noise_floor_m = 1e-7;  // no bifurcation_depth_m: the run never changes state
  const json j = results_of(std::move(c));
  EXPECT_TRUE(j.at("bifurcation_depth_mm").is_null());
  EXPECT_FALSE(j.contains("bifurcation_status"));
  EXPECT_TRUE(j.contains("bifurcation_verdict"));
  EXPECT_EQ(j["bifurcation_noise_floor_m"], 1e-7);
  EXPECT_EQ(j["chatter_islands"], json::array());
}

TEST(CutResultsJson, ConstantDepthCutHasNoBifurcationKeys) {
  auto c = std::make_unique<CutOutcome>();
  c->summary.succeed();
  const json j = results_of(std::move(c));
  EXPECT_FALSE(j.contains("bifurcation_depth_mm"));
  EXPECT_FALSE(j.contains("bifurcation_status"));
}

}  // namespace
}  // namespace chatterlab::app
