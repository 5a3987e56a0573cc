// The campaign's stability-lobes section (app/kinds/lobes, docs/lobes.md "Campaign section"):
// measured points and hysteresis, and the group run on hand-made campaign values.
#include "app/kinds/lobes/lobes_group.h"

#include <gtest/gtest.h>

#include "analysis/frf/mode.h"
#include "app/kinds/cut/cut_summary.h"
#include "app/kinds/dyno_slot/dyno_slot_kind.h"
#include "app/kinds/tap/tap_kind.h"

namespace chatterlab::app {
namespace {

CutSummary ramp(const std::string& id, double rpm, double from_m, double to_m,
                std::optional<double> bifurcation_m, dynamics::RunVerdict verdict) {
  CutSummary c;
  c.id = id;
  c.spindle_rpm = rpm;
  c.radial_immersion_m = 0.382e-3;
  c.depth_start_m = from_m;
  c.depth_end_m = to_m;
  c.ramped = true;
  c.bifurcation_ok = true;
  c.profile = to_m > from_m ? dynamics::DepthProfile::kIncline : dynamics::DepthProfile::kDecline;
  c.verdict = verdict;
  c.bifurcation_depth_m = bifurcation_m;
  return c;
}

CutSummary constant(const std::string& id, double rpm, double depth_m,
                    std::optional<bool> chatter) {
  CutSummary c;
  c.id = id;
  c.spindle_rpm = rpm;
  c.radial_immersion_m = 0.382e-3;
  c.depth_start_m = c.depth_end_m = depth_m;
  c.chatter = chatter;
  return c;
}

// 000 table 5.1's pattern: an incline and a decline at one speed give a hysteresis band; a ramp
// that never changes state is all one colour; a constant cut is a point.
TEST(LobesGroup, MeasuredPointsAndTheHysteresisBand) {
  const auto changes = dynamics::RunVerdict::kChanges;
  const CutSummary up = ramp("cuts/incline", 15000, 0.0, 4e-3, 2.5e-3, changes);
  const CutSummary down = ramp("cuts/decline", 15000.5, 4e-3, 0.0, 1.9e-3, changes);
  const CutSummary calm =
      ramp("cuts/calm", 12000, 0.0, 1e-3, std::nullopt, dynamics::RunVerdict::kAllStable);
  const CutSummary c1 = constant("cuts/c1", 12000, 1e-3, true);
  const CutSummary c2 = constant("cuts/c2", 15000, 0.5e-3, std::nullopt);  // not determined
  LobeDiagram d;
  add_measured_points({&up, &down, &calm, &c1, &c2}, d);
  ASSERT_EQ(d.measured.size(), 5u);
  const MeasuredPoint& pu = d.measured[0];
  EXPECT_TRUE(pu.ramp);
  ASSERT_EQ(pu.stable_m.size(), 1u);
  ASSERT_EQ(pu.chatter_m.size(), 1u);
  EXPECT_EQ(pu.stable_m[0], std::make_pair(0.0, 2.5e-3));
  EXPECT_EQ(pu.chatter_m[0], std::make_pair(2.5e-3, 4e-3));
  // The decline runs from 4 to 0 mm: the same picture, stable below its depth.
  EXPECT_EQ(d.measured[1].stable_m[0], std::make_pair(0.0, 1.9e-3));
  EXPECT_EQ(d.measured[1].chatter_m[0], std::make_pair(1.9e-3, 4e-3));
  EXPECT_EQ(d.measured[2].stable_m[0], std::make_pair(0.0, 1e-3));  // all stable
  EXPECT_TRUE(d.measured[2].chatter_m.empty());
  EXPECT_FALSE(d.measured[3].ramp);
  EXPECT_EQ(d.measured[3].chatter, std::optional<bool>(true));
  EXPECT_FALSE(d.measured[4].chatter.has_value());
  // 15,000 and 15,000.5 rpm are one speed (within 0.1 %): chatter begins at 2.5 mm going up and
  // ends at 1.9 mm going down.
  ASSERT_EQ(d.hysteresis.size(), 1u);
  EXPECT_EQ(d.hysteresis[0].incline, "cuts/incline");
  EXPECT_EQ(d.hysteresis[0].decline, "cuts/decline");
  EXPECT_DOUBLE_EQ(d.hysteresis[0].onset_m, 2.5e-3);
  EXPECT_DOUBLE_EQ(d.hysteresis[0].end_m, 1.9e-3);
  EXPECT_EQ(d.measured_rpm, (std::vector<double>{12000, 15000, 15000.5}));
}

CampaignSpec campaign_with_tool() {
  CampaignSpec c;
  c.tool = ToolSpec{2, 6.35e-3, std::nullopt};
  TestSpec tap;
  tap.kind = "tap";
  TestSpec dyno;
  dyno.kind = "dyno-slot";
  c.tests = {tap, dyno};
  return c;
}

// Tap and dyno tests without cuts: one diagram, a slot; hammer modes of x used on y too and
// said so. Without the dyno fit: the reason, and the group fails (nothing to draw).
TEST(LobesGroup, WithoutCutsASlotAndTheReasonsForWhatIsMissing) {
  const CampaignSpec c = campaign_with_tool();
  LobesGroup g;
  ASSERT_TRUE(g.applies(c));
  CampaignValues values;
  values.put(value::kHammerModesX, "tap/x",
             std::vector<frf::Mode>{frf::mode_from_mck(0.03211, 13.39, 1.023e6)});
  milling::CuttingCoefficients k;
  k.Kt_N_m2 = 5.89e8;
  k.Kr_N_m2 = 3.19e8;
  values.put(value::kCuttingCoefficients, "group:dyno-slot", k);
  RunContext ctx;
  ctx.campaign = &c;
  ctx.jobs = 1;
  GroupOutcome out;
  g.run(values, ctx, out);
  ASSERT_TRUE(out.status.ok()) << out.status.message;
  const nlohmann::json j = g.results(out);
  ASSERT_EQ(j["diagrams"].size(), 1u);
  const nlohmann::json& d = j["diagrams"][0];
  EXPECT_DOUBLE_EQ(d["radial_immersion_mm"].get<double>(), 12.7);  // a slot
  const nlohmann::json& s = d["sources"]["hammer-dyno"];
  EXPECT_NE(s["note"].get<std::string>().find("the same on y (no tap test of y)"),
            std::string::npos);
  EXPECT_EQ(s["Kt_N_m2"], (std::vector<double>{5.89e8, 5.89e8}));
  // Slot, one mode on x and y: SD's lowest limit within 3 % of ZOA's closed-form-like minimum
  // (docs/lobes.md: slot minima of SD and ZOA agree within 1.4 % for N = 2).
  const double sd_min = s["methods"]["semi-discretization"]["minimum_limit_depth_mm"];
  const double zoa_min = s["methods"]["zoa"]["minimum_limit_depth_mm"];
  EXPECT_NEAR(sd_min / zoa_min, 1.0, 0.05);

  CampaignValues no_dyno;
  no_dyno.put(value::kHammerModesX, "tap/x",
              std::vector<frf::Mode>{frf::mode_from_mck(0.03211, 13.39, 1.023e6)});
  no_dyno.fail(value::kCuttingCoefficients, "group:dyno-slot", "fewer than two records");
  GroupOutcome failed;
  g.run(no_dyno, ctx, failed);
  EXPECT_FALSE(failed.status.ok());
  EXPECT_NE(failed.status.message.find("fewer than two records"), std::string::npos)
      << failed.status.message;
}

}  // namespace
}  // namespace chatterlab::app
