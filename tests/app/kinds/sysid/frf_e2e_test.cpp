// Kind frf end to end (format section 5): a campaign with an FRF file of a known 12-state
// discrete system (written in mA per N*m, calibrated to A by `channels: {re: {scale}, im:
// {scale}}`) and a second test whose frequency column is not uniform. The first realizes the
// system exactly (order, poles, static gain; reference: the system written, tolerance: rounding
// of the CSV's 17 digits and of the realization), the second is skipped with a message naming
// its file and freq_hz, and the campaign's report is written with results.json valid against
// docs/results.schema.json.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "analysis/sysid/random_system.h"
#include "app/report/report.h"
#include "tests/support/results_schema.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::TempDir;
using nlohmann::json;

constexpr double kRate = 10000.0;

sysid::DiscreteStateSpace truth_system() {
  sysid::RandomSystemOptions o;
  o.order = 12;
  o.max_radius = 0.97;  // 0.97^2000 ~ 1e-27: no time aliasing on the 5 Hz grid (N = 2000)
  return sysid::random_stable_system(o, kRate, 42);
}

std::string frf_csv(const sysid::DiscreteStateSpace& s, bool break_grid) {
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(1001, 0.0, 5000.0);
  const Eigen::VectorXcd G = sysid::frequency_response(s, f);
  std::string text = "freq_hz,re,im,coherence\n";
  char buf[160];
  for (Eigen::Index i = 0; i < f.size(); ++i) {
    const double fi = (break_grid && i == 500) ? f[i] + 1.0 : f[i];
    std::snprintf(buf, sizeof buf, "%.10g,%.17g,%.17g,1\n", fi, 1e3 * G[i].real(),
                  1e3 * G[i].imag());
    text += buf;
  }
  return text;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class FrfCampaign : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const fs::path campaign = dir_->path() / "campaign";
    report_ = dir_->path() / "report";
    dir_->write("campaign/campaign.yaml",
                "format: chatterlab-campaign/1\nname: frf-e2e\ndescription: ERA on FRF files\n");
    const std::string yaml =
        "kind: frf\nsample_rate_hz: 10000\ndata: {file: frf.csv}\n"
        "channels: {re: {scale: 1.0e-3}, im: {scale: 1.0e-3}}\n"
        "input_unit: N*m\noutput_unit: A\nera_max_order: 40\n";
    dir_->write("campaign/spindle/model/test.yaml", yaml);
    dir_->write("campaign/spindle/model/frf.csv", frf_csv(truth_system(), false));
    dir_->write("campaign/spindle/broken/test.yaml", yaml);
    dir_->write("campaign/spindle/broken/frf.csv", frf_csv(truth_system(), true));
    ReportOptions o;
    o.pdf = false;
    o.jobs = 2;
    std::ostringstream log;
    rc_ = run_report(campaign, report_, o, log);
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
  static fs::path report_;
  static int rc_;
  static std::string log_;
  static json* results_;
};
TempDir* FrfCampaign::dir_ = nullptr;
fs::path FrfCampaign::report_;
int FrfCampaign::rc_ = -1;
std::string FrfCampaign::log_;
json* FrfCampaign::results_ = nullptr;

TEST_F(FrfCampaign, RealizesTheWrittenSystem) {
  ASSERT_NE(results_, nullptr) << log_;
  const json& t = results_->at("tests").at("spindle/model");
  ASSERT_EQ(t.at("status"), "ok") << t.dump(2);
  EXPECT_EQ(t.at("input_unit"), "N*m");
  EXPECT_EQ(t.at("output_unit"), "A");
  const json& m = t.at("model");
  EXPECT_EQ(m.at("method"), "era-gavish-donoho-schur");
  EXPECT_EQ(m.at("order").get<int>(), 12);
  EXPECT_EQ(m.at("unstable_removed").get<int>(), 0);
  EXPECT_EQ(m.at("hankel_rows").get<int>(), 500);  // N = 2 * 1000, alpha = N / 4
  EXPECT_NEAR(m.at("sample_time_s").get<double>(), 1e-4, 1e-18);
  EXPECT_GT(m.at("fit_pct").get<double>(), 99.999);
  const sysid::DiscreteStateSpace s = truth_system();
  EXPECT_NEAR(m.at("dc_gain").get<double>(), sysid::dc_gain(s), 1e-8);
  EXPECT_NEAR(m.at("D").get<double>(), s.D, 1e-9);
  ASSERT_EQ(m.at("A").size(), 12u);
  ASSERT_EQ(m.at("B").size(), 12u);
  ASSERT_EQ(m.at("C").size(), 12u);
  // Every true pole has a reported one within 1e-7 (poles_z as [re, im]).
  const Eigen::VectorXcd p = sysid::poles(s);
  ASSERT_EQ(m.at("poles_z").size(), 12u);
  for (Eigen::Index i = 0; i < p.size(); ++i) {
    double best = 1e300;
    for (const auto& z : m.at("poles_z")) {
      best = std::min(
          best, std::abs(p[i] - std::complex<double>(z[0].get<double>(), z[1].get<double>())));
    }
    EXPECT_LT(best, 1e-7) << p[i];
  }
  EXPECT_EQ(m.at("modes").size(), sysid::modes_of(p, kRate).size());
}

TEST_F(FrfCampaign, ANonUniformGridIsSkippedNamingTheFileAndKey) {
  ASSERT_NE(results_, nullptr) << log_;
  const json& t = results_->at("tests").at("spindle/broken");
  EXPECT_NE(t.at("status"), "ok");
  const std::string why = t.at("skip_reason");
  EXPECT_NE(why.find("spindle/broken/frf.csv"), std::string::npos) << why;
  EXPECT_NE(why.find("freq_hz = 2501"), std::string::npos) << why;
  EXPECT_FALSE(t.contains("model"));
}

TEST_F(FrfCampaign, ReportHasTheSectionAndResultsValidate) {
  ASSERT_NE(results_, nullptr) << log_;
  const std::string html = read_text(report_ / "index.html");
  EXPECT_NE(html.find("Drive models from FRFs (ERA)"), std::string::npos);
  EXPECT_NE(html.find("spindle/model"), std::string::npos);
  const json& figs = results_->at("tests").at("spindle/model").at("figures");
  EXPECT_FALSE(figs.empty()) << figs.dump();
  const auto check = chatterlab::testing::check_results_schema(report_ / "results.json");
  EXPECT_TRUE(check.valid) << check.output;
}

}  // namespace
}  // namespace chatterlab::app
