#include "app/core/campaign.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "app/core/yaml_reader.h"
#include "app/kinds/cut/cut_spec.h"
#include "app/kinds/tap/tap_step.h"
#include "app/pipeline/pipeline.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::kCampaignYaml;
using chatterlab::testing::TempDir;

bool any_contains(const std::vector<std::string>& v, const std::string& s) {
  return std::any_of(v.begin(), v.end(),
                     [&](const std::string& e) { return e.find(s) != std::string::npos; });
}

const char* kTapYaml =
    "kind: tap\naxis: x\nsample_rate_hz: 1000\ndata: {file: hits.csv}\n"
    "response: acceleration\nhits: auto\n";

TEST(Campaign, FindsTestsRecursivelyWithSlashIds) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write("tap/x/test.yaml", kTapYaml);
  d.write("tap/x/hits.csv", "force,response\n1,2\n");
  d.write("deep/er/still/test.yaml", kTapYaml);
  d.write("deep/er/still/hits.csv", "force,response\n1,2\n");
  d.write("structure/only/readme.txt", "no test here");
  const CampaignSpec c = load_campaign(d.path());
  EXPECT_TRUE(c.errors.empty());
  ASSERT_EQ(c.tests.size(), 2u);
  EXPECT_EQ(c.tests[0].id, "deep/er/still");
  EXPECT_EQ(c.tests[1].id, "tap/x");
  EXPECT_TRUE(c.tests[1].usable());
  EXPECT_EQ(c.tests[1].kind_spec<TapSpec>().axis, "x");
  ASSERT_TRUE(c.tool.has_value());
  EXPECT_DOUBLE_EQ(c.tool->radius_m, 6.35e-3);
}

TEST(Campaign, MissingCampaignYamlIsACampaignError) {
  TempDir d;
  const CampaignSpec c = load_campaign(d.path());
  ASSERT_EQ(c.errors.size(), 1u);
  EXPECT_NE(c.errors[0].find("campaign.yaml: file not found"), std::string::npos);
}

TEST(Campaign, WrongFormatStringAndBadName) {
  TempDir d;
  d.write("campaign.yaml", "format: chatterlab-campaign/2\nname: bad name!\n");
  const CampaignSpec c = load_campaign(d.path());
  EXPECT_TRUE(
      any_contains(c.errors, "campaign.yaml: key 'format' 'chatterlab-campaign/2': must be"));
  EXPECT_TRUE(any_contains(c.errors, "campaign.yaml: key 'name' 'bad name!': must match"));
}

TEST(Campaign, MissingAndMisspeltRequiredKey) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write("t/test.yaml",
          "kind: tap\naxis: x\nsample_rte_hz: 1000\ndata: {file: hits.csv}\nresponse: velocity\n");
  d.write("t/hits.csv", "force,response\n1,2\n");
  const CampaignSpec c = load_campaign(d.path());
  ASSERT_EQ(c.tests.size(), 1u);
  EXPECT_FALSE(c.tests[0].usable());
  EXPECT_TRUE(any_contains(c.tests[0].errors,
                           "t/test.yaml: key 'sample_rate_hz' is missing (found 'sample_rte_hz': "
                           "misspelt?)"));
  EXPECT_TRUE(any_contains(c.tests[0].warnings,
                           "key 'sample_rte_hz' is not part of the format and is ignored (did you "
                           "mean 'sample_rate_hz'?)"));
}

TEST(Campaign, KeyWithoutItsUnitSuffixIsAMisspelling) {
  EXPECT_TRUE(looks_like("sample_rate", "sample_rate_hz"));
  EXPECT_TRUE(looks_like("feed_per_tooth", "feed_per_tooth_mm"));
  EXPECT_TRUE(looks_like("smaple_rate_hz", "sample_rate_hz"));
  EXPECT_TRUE(looks_like("data", "data_rate"));  // prefix up to a unit suffix
  EXPECT_FALSE(looks_like("dat", "data_rate"));  // too short to say
  EXPECT_FALSE(looks_like("kind", "axis"));
  EXPECT_FALSE(looks_like("axis", "axis"));
}

TEST(Campaign, WithinEditsComparesLengthsFirst) {
  EXPECT_TRUE(within_edits("smaple_rate_hz", "sample_rate_hz", 2));
  EXPECT_TRUE(within_edits("sample_rate", "sample_rate_hz", 3));
  EXPECT_FALSE(within_edits("sample_rate", "sample_rate_hz", 2));  // 3 characters apart
  EXPECT_FALSE(within_edits(std::string(100000, 'a'), "axis", 2));
  EXPECT_TRUE(within_edits("", "ab", 2));
}

TEST(Campaign, WrongTypeNamesFileKeyAndValue) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write("t/test.yaml",
          "kind: tap\naxis: x\nsample_rate_hz: fast\ndata: {file: hits.csv}\nresponse: velocity\n");
  d.write("t/hits.csv", "force,response\n1,2\n");
  const CampaignSpec c = load_campaign(d.path());
  EXPECT_TRUE(any_contains(c.tests[0].errors,
                           "t/test.yaml: key 'sample_rate_hz' must be a number, got 'fast'"));
}

TEST(Campaign, SampleRateMustBePositive) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write("t/test.yaml",
          "kind: tap\naxis: x\nsample_rate_hz: 0\ndata: {file: hits.csv}\nresponse: velocity\n");
  d.write("t/hits.csv", "force,response\n1,2\n");
  const CampaignSpec c = load_campaign(d.path());
  EXPECT_TRUE(any_contains(c.tests[0].errors, "t/test.yaml: key 'sample_rate_hz' = 0"));
  EXPECT_TRUE(any_contains(c.tests[0].errors, "must be > 0"));
}

TEST(Campaign, UnknownKindAndMissingFile) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write("a/test.yaml", "kind: grinding-wheel\nsample_rate_hz: 10\ndata: {file: s.csv}\n");
  d.write("a/s.csv", "v\n1\n");
  d.write("b/test.yaml", kTapYaml);  // hits.csv absent
  const CampaignSpec c = load_campaign(d.path());
  ASSERT_EQ(c.tests.size(), 2u);
  EXPECT_TRUE(any_contains(c.tests[0].errors,
                           "a/test.yaml: key 'kind' 'grinding-wheel' is not a known test kind"));
  EXPECT_TRUE(
      any_contains(c.tests[1].errors, "b/test.yaml: key 'data.file' 'hits.csv': file not found"));
}

TEST(Campaign, RawFileNeedsChannelList) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write("c/test.yaml",
          "kind: cut\noperation: up-milling\nspindle_rpm: 15000\nfeed_per_tooth_mm: 0.0635\n"
          "radial_immersion_mm: 0.382\naxial_depth_mm: [0, 6]\ncut_window_s: [1, 2]\n"
          "sample_rate_hz: 100000\ndata: {file: s.f32}\n");
  d.write("c/s.f32", std::string(24, '\0'));
  const CampaignSpec c = load_campaign(d.path());
  EXPECT_TRUE(any_contains(c.tests[0].errors,
                           "c/test.yaml: key 'data.channels' is required for a raw binary file"));
  ASSERT_NE(dynamic_cast<const CutSpec*>(c.tests[0].params.get()), nullptr);
  EXPECT_DOUBLE_EQ(c.tests[0].kind_spec<CutSpec>().axial_depth_m.second, 6e-3);
}

TEST(Campaign, CutWithoutToolIsUnusable) {
  TempDir d;
  d.write("campaign.yaml", "format: chatterlab-campaign/1\nname: x\n");
  d.write("d/test.yaml",
          "kind: dyno-slot\nspindle_rpm: 200\nfeed_per_tooth_mm: 0.05\naxial_depth_mm: 1\n"
          "sample_rate_hz: 1000\ndata: {file: f.csv}\n");
  d.write("d/f.csv", "Fx,Fy,zero\n0,0,0\n");
  const CampaignSpec c = load_campaign(d.path());
  EXPECT_TRUE(any_contains(c.tests[0].errors, "needs campaign.yaml key 'tool'"));
}

TEST(Campaign, InvalidYamlIsReported) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write("t/test.yaml", "kind: [tap\n");
  const CampaignSpec c = load_campaign(d.path());
  EXPECT_TRUE(any_contains(c.tests[0].errors, "t/test.yaml: not valid YAML"));
}

TEST(Campaign, ChannelCalibrationParsed) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write("t/test.yaml", std::string(kTapYaml) + "channels:\n  force: {scale: 2.5, offset: -1}\n");
  d.write("t/hits.csv", "force,response\n1,2\n");
  const CampaignSpec c = load_campaign(d.path());
  EXPECT_DOUBLE_EQ(c.tests[0].channel("force").scale, 2.5);
  EXPECT_DOUBLE_EQ(c.tests[0].channel("force").offset, -1.0);
  EXPECT_DOUBLE_EQ(c.tests[0].channel("response").scale, 1.0);
}

// ---- CSV dialect and column keys (EXPERIMENT_FORMAT.md section 1) ----

CampaignSpec tap_with(TempDir& d, const std::string& data_and_channels,
                      const std::string& file = "hits.txt") {
  d.write("campaign.yaml", kCampaignYaml);
  d.write("t/test.yaml",
          "kind: tap\naxis: x\nsample_rate_hz: 1000\nresponse: acceleration\n" + data_and_channels);
  d.write("t/" + file, "force;response\n1,5;2\n");
  return load_campaign(d.path());
}

TEST(CampaignDialect, DataKeysParsed) {
  TempDir d;
  const CampaignSpec c =
      tap_with(d, "data: {file: hits.txt, delimiter: \";\", decimal: \",\", skip_lines: 22}\n");
  const TestSpec& t = c.tests[0];
  EXPECT_TRUE(t.errors.empty()) << t.errors[0];
  EXPECT_TRUE(t.warnings.empty()) << t.warnings[0];
  EXPECT_EQ(t.data.delimiter, ';');
  EXPECT_EQ(t.data.decimal, ',');
  EXPECT_EQ(t.data.skip_lines, 22);
}

TEST(CampaignDialect, DefaultsAndTheWaysToWriteTab) {
  TempDir d;
  EXPECT_EQ(tap_with(d, "data: {file: hits.txt}\n").tests[0].data.delimiter, 0);  // detected
  EXPECT_EQ(tap_with(d, "data: {file: hits.txt}\n").tests[0].data.decimal, '.');
  EXPECT_EQ(tap_with(d, "data: {file: hits.txt}\n").tests[0].data.skip_lines, 0);
  for (const char* tab : {"tab", "\"\\t\"", "'\\t'"}) {
    const CampaignSpec c =
        tap_with(d, std::string("data:\n  file: hits.txt\n  delimiter: ") + tab + "\n");
    EXPECT_EQ(c.tests[0].data.delimiter, '\t') << tab;
    EXPECT_TRUE(c.tests[0].errors.empty()) << tab;
  }
  EXPECT_EQ(tap_with(d, "data: {file: hits.txt, delimiter: \",\"}\n").tests[0].data.delimiter, ',');
}

TEST(CampaignDialect, BadValuesNameFileAndKey) {
  TempDir d;
  EXPECT_EQ(tap_with(d, "data: {file: hits.txt, delimiter: \"|\"}\n").tests[0].errors,
            std::vector<std::string>{
                "t/test.yaml: key 'data.delimiter' must be \",\", \";\" or tab, got '|'"});
  EXPECT_EQ(
      tap_with(d, "data: {file: hits.txt, decimal: \";\"}\n").tests[0].errors,
      std::vector<std::string>{"t/test.yaml: key 'data.decimal' must be \".\" or \",\", got ';'"});
  EXPECT_EQ(
      tap_with(d, "data: {file: hits.txt, delimiter: \",\", decimal: \",\"}\n").tests[0].errors,
      std::vector<std::string>{"t/test.yaml: key 'data.decimal' \",\" needs data.delimiter "
                               "\";\" or tab (the cells are split at \",\")"});
  for (const char* n : {"-1", "2.5"}) {
    EXPECT_EQ(
        tap_with(d, std::string("data: {file: hits.txt, skip_lines: ") + n + "}\n").tests[0].errors,
        std::vector<std::string>{"t/test.yaml: key 'data.skip_lines' must be a whole number "
                                 ">= 0 (lines before the header row)"})
        << n;
  }
  EXPECT_TRUE(
      any_contains(tap_with(d, "data: {file: hits.txt, skip_lines: many}\n").tests[0].errors,
                   "t/test.yaml: key 'data.skip_lines'"));
}

TEST(CampaignDialect, TextExtensionsAcceptedOthersRefused) {
  TempDir d;
  for (const char* f : {"hits.csv", "hits.txt", "hits.tsv", "hits.lvm", "HITS.CSV"}) {
    const CampaignSpec c = tap_with(d, std::string("data: {file: ") + f + "}\n", f);
    EXPECT_TRUE(c.tests[0].errors.empty()) << f << ": " << c.tests[0].errors[0];
  }
  const CampaignSpec c = tap_with(d, "data: {file: hits.xlsx}\n", "hits.xlsx");
  EXPECT_TRUE(any_contains(c.tests[0].errors,
                           "t/test.yaml: key 'data.file' 'hits.xlsx': unsupported signal format "
                           "(use text .csv, .txt, .tsv, .lvm, raw .f32, .f64, UFF .uff, .unv or "
                           "MATLAB .mat)"));
}

TEST(CampaignDialect, DialectKeysOnARawFileAreIgnoredWithAWarning) {
  TempDir d;
  const CampaignSpec c =
      tap_with(d, "data: {file: s.f32, channels: [force, response], delimiter: \";\"}\n", "s.f32");
  EXPECT_TRUE(any_contains(c.tests[0].warnings,
                           "t/test.yaml: key 'data.delimiter' applies to text files and is "
                           "ignored for a raw binary file"));
}

TEST(CampaignDialect, ColumnByHeaderTextOrIndex) {
  TempDir d;
  const CampaignSpec c = tap_with(d,
                                  "data: {file: hits.txt}\n"
                                  "channels:\n"
                                  "  force: {column: \"Force (N)\"}\n"
                                  "  response: {column: 2, scale: 9.81}\n"
                                  "  a: {column: Hammer}\n"
                                  "  b: {column: \"2\"}\n");
  const TestSpec& t = c.tests[0];
  EXPECT_TRUE(t.errors.empty()) << t.errors[0];
  EXPECT_TRUE(t.warnings.empty()) << t.warnings[0];
  ASSERT_TRUE(t.channel("force").column.has_value());
  EXPECT_EQ(t.channel("force").column->header, "Force (N)");
  EXPECT_FALSE(t.channel("force").column->by_index());
  ASSERT_TRUE(t.channel("response").column.has_value());
  EXPECT_EQ(t.channel("response").column->index, 2);
  EXPECT_DOUBLE_EQ(t.channel("response").scale, 9.81);
  EXPECT_EQ(t.channel("a").column->header, "Hammer");
  EXPECT_EQ(t.channel("b").column->header, "2");  // quoted: a header text
  EXPECT_FALSE(t.channel("x").column.has_value());
}

TEST(CampaignDialect, BadColumnValues) {
  TempDir d;
  for (const char* v : {"-1", "1.5", "[1, 2]", "\"\""}) {
    const CampaignSpec c = tap_with(
        d, std::string("data: {file: hits.txt}\nchannels:\n  force: {column: ") + v + "}\n");
    EXPECT_TRUE(any_contains(c.tests[0].errors,
                             "t/test.yaml: key 'channels.force.column' must be the header text "
                             "of a column or its 0-based index"))
        << v << ": " << (c.tests[0].errors.empty() ? "no error" : c.tests[0].errors[0]);
  }
}

TEST(CampaignDialect, ValidateReportsABadColumnWithFileAndKey) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write(
      "t/test.yaml",
      "kind: tap\naxis: x\nsample_rate_hz: 1000\nresponse: acceleration\n"
      "data: {file: hits.csv}\nchannels:\n  force: {column: Hammer}\n  response: {column: 5}\n");
  std::string rows = "t,Force (N),Accel\n";
  for (int i = 0; i < 16; ++i) rows += "0,1,2\n";  // a tap record's shortest length
  d.write("t/hits.csv", rows);
  CampaignSpec c = load_campaign(d.path());
  check_signals(c.tests[0]);
  EXPECT_EQ(c.tests[0].errors,
            (std::vector<std::string>{
                "t/hits.csv: channels.force.column 'Hammer' is not a column of the header "
                "(columns: 't', 'Force (N)', 'Accel')",
                "t/hits.csv: channels.response.column is 5, out of range: the file has 3 "
                "columns, 0 to 2 (t, Force (N), Accel)"}));
}

}  // namespace
}  // namespace chatterlab::app
