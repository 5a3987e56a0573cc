// Kinds sifs-static, sifs-tap, sifs-cut (EXPERIMENT_FORMAT section 6, app/kinds/sifs): each
// test.yaml problem names the file and key; a cut whose `taps` name a missing test, a test of
// another kind or a tap of the other axis is refused at loading; the order of the pipeline is
// static -> calibration -> taps -> cuts -> Q map.
#include "app/kinds/sifs/sifs_kinds.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "app/core/campaign.h"
#include "app/pipeline/pipeline.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::TempDir;

const char* kWasherCsv = "x1,x2,y1,y2,z1,z2\n0,0,0,0,0,0\n0,0,0,0,0,0\n";
const char* kTapCsv = "hammer,x1,x2,y1,y2,z1,z2\n0,0,0,0,0,0,0\n0,0,0,0,0,0,0\n";

std::string static_yaml(const std::string& loads =
                            "[[0.0, 0.001, 0], [0.0005, 0.001, 44.5], "
                            "[0.001, 0.0015, 0]]",
                        const std::string& axis = "x") {
  return "kind: sifs-static\naxis: " + axis + "\nsample_rate_hz: 1024\ndata: {file: s.csv}\n" +
         "loads: " + loads + "\n";
}

std::string tap_yaml(const std::string& axis = "x", const std::string& extra = "") {
  return "kind: sifs-tap\naxis: " + axis +
         "\nsample_rate_hz: 12800\ndata: {file: t.csv}\nhits: auto\nband_hz: [100, 4000]\n" + extra;
}

std::string cut_yaml(const std::string& extra = "",
                     const std::string& taps = "{x: tap/x, y: tap/y}") {
  return "kind: sifs-cut\nspindle_rpm: 9000\nsample_rate_hz: 12800\ndata: {file: c.csv}\n"
         "air_window_s: [0.0, 0.0001]\ncut_window_s: [0.0001, 0.00015]\ntaps: " +
         taps + "\n" + extra;
}

// Loads a campaign of the given tests (id -> test.yaml) and returns the errors of `which`.
std::vector<std::string> errors_of(const std::vector<std::pair<std::string, std::string>>& tests,
                                   const std::string& which) {
  TempDir d;
  d.write("campaign.yaml", chatterlab::testing::kCampaignYaml);
  for (const auto& [id, yaml] : tests) {
    d.write(id + "/test.yaml", yaml);
    d.write(id + "/s.csv", kWasherCsv);
    d.write(id + "/t.csv", kTapCsv);
    d.write(id + "/c.csv", kWasherCsv);
  }
  CampaignSpec c = load_campaign(d.path());
  for (auto& t : c.tests) {
    if (t.id != which) continue;
    if (t.usable()) check_signals(t);
    return t.errors;
  }
  ADD_FAILURE() << "no test " << which;
  return {};
}

bool any_contains(const std::vector<std::string>& v, const std::string& what) {
  for (const auto& s : v) {
    if (s.find(what) != std::string::npos) return true;
  }
  return false;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& e : v) s += e + "\n";
  return s;
}

TEST(SifsStaticKind, LoadErrorsNameTheirKey) {
  auto e = errors_of({{"st", static_yaml("[[0, 1, 0], [1, 2], [2, 3, 0]]")}}, "st");
  EXPECT_TRUE(any_contains(e, "loads[1]")) << joined(e);
  e = errors_of({{"st", static_yaml("[[0, 1, 0]]")}}, "st");
  EXPECT_TRUE(any_contains(e, "loads")) << joined(e);
  e = errors_of({{"st", static_yaml("[[0, 0.001, 0], [0.001, 0.0005, 1], [0.001, 0.0015, 0]]")}},
                "st");
  EXPECT_TRUE(any_contains(e, "loads[1]")) << joined(e);
  // The record is two samples at 1024 Hz: a window ending at 9 s lies beyond it.
  e = errors_of({{"st", static_yaml("[[0, 0.001, 0], [0.001, 0.0015, 1], [0.0015, 9, 0]]")}}, "st");
  EXPECT_TRUE(any_contains(e, "loads[2]' ends at 9 s, after the record")) << joined(e);
  e = errors_of(
      {{"st", static_yaml("[[0.0, 0.001, 0], [0.0005, 0.001, 44.5], [0.001, 0.0015, 0]]", "w")}},
      "st");
  EXPECT_TRUE(any_contains(e, "axis")) << joined(e);
  e = errors_of({{"st", static_yaml()}}, "st");
  EXPECT_TRUE(e.empty()) << joined(e);
}

TEST(SifsTapKind, LoadErrorsNameTheirKey) {
  auto e = errors_of({{"tap/x", tap_yaml("z")}}, "tap/x");
  EXPECT_TRUE(any_contains(e, "axis")) << joined(e);
  e = errors_of({{"tap/x", tap_yaml("x", "modes: 2.5\n")}}, "tap/x");
  EXPECT_TRUE(any_contains(e, "modes")) << joined(e);
  e = errors_of({{"tap/x",
                  "kind: sifs-tap\naxis: x\nsample_rate_hz: 12800\ndata: {file: t.csv}\n"
                  "hits: [[0.1, 0.05]]\nband_hz: [100, 4000]\n"}},
                "tap/x");
  EXPECT_TRUE(any_contains(e, "hits[0]")) << joined(e);
  e = errors_of({{"tap/x",
                  "kind: sifs-tap\naxis: x\nsample_rate_hz: 12800\ndata: {file: t.csv}\n"
                  "hits: auto\n"}},
                "tap/x");
  EXPECT_TRUE(any_contains(e, "band_hz")) << joined(e);
  e = errors_of({{"tap/x", tap_yaml()}}, "tap/x");
  EXPECT_TRUE(e.empty()) << joined(e);
}

TEST(SifsCutKind, LoadErrorsNameTheirKey) {
  const std::vector<std::pair<std::string, std::string>> taps{{"tap/x", tap_yaml("x")},
                                                              {"tap/y", tap_yaml("y")}};
  auto with = [&](const std::string& yaml) {
    auto t = taps;
    t.emplace_back("cut", yaml);
    return errors_of(t, "cut");
  };
  EXPECT_TRUE(with(cut_yaml()).empty()) << joined(with(cut_yaml()));
  auto e = with(cut_yaml("", "{x: tap/x, y: tap/z}"));
  EXPECT_TRUE(any_contains(e, "taps.y")) << joined(e);
  EXPECT_TRUE(any_contains(e, "not a test of the campaign")) << joined(e);
  e = with(cut_yaml("", "{x: tap/y, y: tap/y}"));
  EXPECT_TRUE(any_contains(e, "whose axis is y")) << joined(e);
  e = with(cut_yaml("gain: optimal\n"));
  EXPECT_TRUE(any_contains(e, "gain")) << joined(e);
  e = with(cut_yaml("dynamometer: {channels: [dx, dy], angle_deg: 30}\n"));
  EXPECT_TRUE(any_contains(e, "dynamometer.channels")) << joined(e);
  e = with(
      "kind: sifs-cut\nspindle_rpm: 9000\nsample_rate_hz: 12800\ndata: {file: c.csv}\n"
      "air_window_s: [0.0, 0.0001]\ncut_window_s: [0.00005, 0.00015]\ntaps: {x: tap/x, y: "
      "tap/y}\n");
  EXPECT_TRUE(any_contains(e, "air_window_s")) << joined(e);
  // The dynamometer's channels are required of the record.
  e = with(cut_yaml("dynamometer: {channels: [dx, dy, dz], angle_deg: 30}\n"));
  EXPECT_TRUE(any_contains(e, "dx")) << joined(e);
}

TEST(SifsCutKind, NeedsTheCampaignTool) {
  TempDir d;
  d.write("campaign.yaml", "format: chatterlab-campaign/1\nname: no-tool\n");
  d.write("tap/x/test.yaml", tap_yaml("x"));
  d.write("tap/x/t.csv", kTapCsv);
  d.write("tap/y/test.yaml", tap_yaml("y"));
  d.write("tap/y/t.csv", kTapCsv);
  d.write("cut/test.yaml", cut_yaml());
  d.write("cut/c.csv", kWasherCsv);
  CampaignSpec c = load_campaign(d.path());
  for (const auto& t : c.tests) {
    if (t.id != "cut") continue;
    EXPECT_TRUE(any_contains(t.errors, "tool")) << joined(t.errors);
  }
}

TEST(SifsMapGrid, HoldsTheDefaultGridAndTheCutSpeeds) {
  const auto g = sifs_map_grid({9000, 11600});
  EXPECT_EQ(g.front(), 1000);
  EXPECT_EQ(g.back(), 24000);
  EXPECT_EQ(g.size(), 48u);  // 47 grid speeds + 11600 (9000 is on the grid)
}

}  // namespace
}  // namespace chatterlab::app
