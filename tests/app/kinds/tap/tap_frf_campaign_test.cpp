// A tap test from a measured FRF end to end: a campaign folder whose one tap test names
// `frf: {file: ...}` (no data, no sample_rate_hz) loads without errors, runs through run_report
// (pdf off) with status ok, fits the two modes of the written receptance within 0.5 %, hashes
// the FRF file into inputs_sha256, writes a results.json valid against
// docs/results.schema.json (frf_source file, no hit keys) and says in the report where the FRF
// was read from.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "app/core/campaign.h"
#include "app/report/report.h"
#include "tests/support/results_schema.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::TempDir;
using nlohmann::json;

struct TrueMode {
  double fn_hz, zeta, k_N_m;
};
const TrueMode kModes[] = {{612.0, 0.025, 2.0e7}, {1430.0, 0.018, 5.0e7}};

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The receptance (m/N) of the two modes on 1..2000 Hz, 1 Hz steps, as f_hz,re,im.
std::string frf_csv() {
  std::string text = "f_hz,re,im\n";
  char buf[128];
  for (int i = 1; i <= 2000; ++i) {
    const double f = i;
    std::complex<double> h = 0.0;
    for (const auto& m : kModes) {
      const double r = f / m.fn_hz;
      h += 1.0 / (m.k_N_m * std::complex<double>(1.0 - r * r, 2.0 * m.zeta * r));
    }
    std::snprintf(buf, sizeof buf, "%.1f,%.17g,%.17g\n", f, h.real(), h.imag());
    text += buf;
  }
  return text;
}

class TapFrfCampaign : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    campaign_ = dir_->path() / "campaign";
    report_ = dir_->path() / "report";
    dir_->write("campaign/campaign.yaml",
                "format: chatterlab-campaign/1\nname: tap-frf-e2e\n"
                "description: one tap test from a measured FRF file\n");
    dir_->write("campaign/tap/x/test.yaml",
                "kind: tap\naxis: x\nresponse: displacement\nfrf: {file: measured.csv}\n");
    dir_->write("campaign/tap/x/measured.csv", frf_csv());
    ReportOptions o;
    o.pdf = false;
    o.jobs = 2;
    std::ostringstream log;
    rc_ = run_report(campaign_, report_, o, log);
    log_ = log.str();
    if (fs::exists(report_ / "results.json")) {
      results_ = new json(json::parse(read_text(report_ / "results.json")));
    }
  }
  static void TearDownTestSuite() {
    delete results_;
    delete dir_;
    results_ = nullptr;
    dir_ = nullptr;
  }
  static TempDir* dir_;
  static fs::path campaign_, report_;
  static int rc_;
  static std::string log_;
  static json* results_;
};
TempDir* TapFrfCampaign::dir_ = nullptr;
fs::path TapFrfCampaign::campaign_;
fs::path TapFrfCampaign::report_;
int TapFrfCampaign::rc_ = -1;
std::string TapFrfCampaign::log_;
json* TapFrfCampaign::results_ = nullptr;

TEST_F(TapFrfCampaign, LoadsWithoutDataOrSampleRate) {
  const CampaignSpec c = load_campaign(campaign_, builtin_kinds());
  ASSERT_EQ(c.tests.size(), 1u);
  const TestSpec& t = c.tests.front();
  EXPECT_TRUE(t.usable()) << (t.errors.empty() ? "" : t.errors.front());
  EXPECT_TRUE(t.errors.empty());
  EXPECT_TRUE(t.data.relative_file.empty());
}

TEST_F(TapFrfCampaign, ReportFitsTheModesAndValidates) {
  EXPECT_EQ(rc_, 0) << log_;
  ASSERT_NE(results_, nullptr) << log_;
  const json& j = *results_;
  const json& t = j.at("tests").at("tap/x");
  ASSERT_EQ(t.at("status"), "ok") << t.dump(2);
  EXPECT_EQ(t.at("frf_source"), "file");
  EXPECT_EQ(t.at("frf_input"), "tap/x/measured.csv");
  EXPECT_FALSE(t.at("frf_columns").get<std::string>().empty());
  EXPECT_FALSE(t.contains("hits"));
  EXPECT_FALSE(t.contains("hits_used"));
  EXPECT_NEAR(t.at("frequency_resolution_hz").get<double>(), 1.0, 1e-9);

  ASSERT_TRUE(t.contains("modes")) << t.dump(2);
  const json& modes = t.at("modes");
  ASSERT_EQ(modes.size(), 2u) << modes.dump(2);
  for (std::size_t i = 0; i < 2; ++i) {
    const TrueMode& m = kModes[i];
    EXPECT_NEAR(modes[i].at("fn_hz").get<double>() / m.fn_hz, 1.0, 0.005) << "mode " << i + 1;
    EXPECT_NEAR(modes[i].at("zeta").get<double>() / m.zeta, 1.0, 0.005) << "mode " << i + 1;
    EXPECT_NEAR(modes[i].at("k_N_m").get<double>() / m.k_N_m, 1.0, 0.005) << "mode " << i + 1;
  }

  // The FRF file is an input like a data file: hashed beside test.yaml.
  const json& inputs = j.at("inputs_sha256");
  EXPECT_TRUE(inputs.contains("tap/x/measured.csv")) << inputs.dump(2);
  EXPECT_TRUE(inputs.contains("tap/x/test.yaml")) << inputs.dump(2);

  const auto check = chatterlab::testing::check_results_schema(report_ / "results.json");
  EXPECT_TRUE(check.valid) << check.output;
}

TEST_F(TapFrfCampaign, ReportSaysWhereTheFrfCameFrom) {
  const std::string html = read_text(report_ / "index.html");
  ASSERT_FALSE(html.empty()) << log_;
  EXPECT_NE(html.find("FRF read from measured.csv"), std::string::npos);
  EXPECT_EQ(html.find("hits used"), std::string::npos);
}

}  // namespace
}  // namespace chatterlab::app
