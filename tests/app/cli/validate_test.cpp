// `validate` reports every problem that would skip work in `report`, campaign.yaml blocks
// owned by kinds included, and exits non-zero for it.
#include "app/cli/validate.h"

#include <gtest/gtest.h>

#include <sstream>

#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::kCampaignYaml;
using chatterlab::testing::TempDir;

void write_tap(const TempDir& d) {
  d.write("t/test.yaml",
          "kind: tap\naxis: x\nsample_rate_hz: 1000\ndata: {file: h.csv}\nresponse: velocity\n");
  // 16 rows: the shortest record a tap test takes (analysis/frf/hits.h).
  std::string rows = "force,response\n";
  for (int i = 0; i < 16; ++i) rows += "1,2\n";
  d.write("t/h.csv", rows);
}

TEST(Validate, CleanCampaignPasses) {
  TempDir d;
  d.write("campaign.yaml", std::string(kCampaignYaml) + "estimation: {window_s: 0.1}\n");
  write_tap(d);
  CampaignSpec c = load_campaign(d.path());
  std::ostringstream out;
  EXPECT_EQ(validate_campaign(c, out), 0) << out.str();
  EXPECT_NE(out.str().find("1 tests found, 1 usable, 0 unusable"), std::string::npos);
}

// A bad `estimation:` block would skip every cut test's identification in `report`.
TEST(Validate, BadEstimationBlockFails) {
  TempDir d;
  d.write("campaign.yaml",
          std::string(kCampaignYaml) + "estimation: {window_s: -0.2, repeat_runs: 1}\n");
  write_tap(d);
  CampaignSpec c = load_campaign(d.path());
  std::ostringstream out;
  EXPECT_EQ(validate_campaign(c, out), 1);
  EXPECT_NE(out.str().find("error: campaign.yaml: key 'estimation.window_s' must be > 0 (the "
                           "steps that use campaign.yaml 'estimation' would be skipped)"),
            std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("campaign.yaml: key 'estimation.repeat_runs' must be 0 (no "
                           "repeatability runs) or a whole number >= 2"),
            std::string::npos)
      << out.str();
}

TEST(Validate, EstimationBlockThatIsNotAMappingFails) {
  TempDir d;
  d.write("campaign.yaml", std::string(kCampaignYaml) + "estimation: 3\n");
  write_tap(d);
  CampaignSpec c = load_campaign(d.path());
  std::ostringstream out;
  EXPECT_EQ(validate_campaign(c, out), 1);
  EXPECT_NE(out.str().find("campaign.yaml: key 'estimation' must be a mapping"), std::string::npos)
      << out.str();
}

// Every kind of the format is analysed: a force-record test's own keys bring no warning, and a
// misspelt kind is an error naming the known kinds.
TEST(Validate, EveryFormatKindIsKnownAndAMisspeltKindFails) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  write_tap(d);
  d.write("dynamometer/x/test.yaml",
          "kind: force-record\nsample_rate_hz: 10240\ndata: {file: f.csv}\nspindle_rpm: 15345\n"
          "noise_var_N2: {x: 0.01, y: 0.01}\nrd_alpha: gcv\nsmo: {rho_N_s: 2.0e8}\n");
  // 0.1 s of record: the format's evaluation window (0.05 s to the end less 0.01 s) holds some.
  std::string record = "Fx,Fy\n";
  for (int k = 0; k < 1024; ++k) record += std::to_string(k % 7) + ",0.5\n";
  d.write("dynamometer/x/f.csv", record);
  CampaignSpec c = load_campaign(d.path());
  std::ostringstream out;
  EXPECT_EQ(validate_campaign(c, out), 0) << out.str();
  const std::string s = out.str();
  EXPECT_NE(s.find("ok       dynamometer/x               force-record\n"), std::string::npos) << s;
  EXPECT_EQ(s.find("warning"), std::string::npos) << s;
  EXPECT_NE(s.find("2 tests found, 2 usable, 0 unusable"), std::string::npos) << s;

  d.write("dynamometer/y/test.yaml",
          "kind: force-recrod\nsample_rate_hz: 10240\ndata: {file: f.csv}\n");
  d.write("dynamometer/y/f.csv", "Fx,Fy\n0,0\n");
  CampaignSpec c2 = load_campaign(d.path());
  std::ostringstream out2;
  EXPECT_EQ(validate_campaign(c2, out2), 1) << out2.str();
  EXPECT_NE(out2.str().find("UNUSABLE dynamometer/y               force-recrod"), std::string::npos)
      << out2.str();
  EXPECT_NE(out2.str().find("key 'kind' 'force-recrod' is not a known test kind"),
            std::string::npos)
      << out2.str();
}

}  // namespace
}  // namespace chatterlab::app
