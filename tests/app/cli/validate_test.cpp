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
  d.write("t/h.csv", "force,response\n1,2\n");
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

}  // namespace
}  // namespace chatterlab::app
