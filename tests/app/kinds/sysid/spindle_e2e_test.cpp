// Kinds sweep-frf and spindle-current end to end (format section 5, source 001): `synth` writes a
// spindle campaign from the simulated drive (analysis/sysid/spindle_drive.h) -- a speed-loop
// sweep and cuts at 3000, 5000 and 7000 rpm with a dynamometer -- plus a cut whose model names
// no test; `report` realizes the torque-to-current model from the sweep and runs the torque
// observer on each cut. References: truth.yaml (the drive's exact FRF, static gain and
// closed-loop torsional mode; the true torque held over each sample) with the tolerances below.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "app/core/signals.h"
#include "app/report/report.h"
#include "app/synth/synth.h"
#include "tests/support/results_schema.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::TempDir;
using nlohmann::json;

const char* kSpec =
    "format: chatterlab-synth/1\n"
    "name: spindle-e2e\n"
    "seed: 11\n"
    "tool: {teeth: 2, radius_mm: 6.0, helix_deg: 30}\n"
    "spindle:\n"
    "  cuts: {rpm: [3000, 5000, 7000], feed_per_tooth_mm: 0.2}\n"
    "era:\n"
    "  systems:\n"
    "    - {name: sys1-clean, order: 16, snr_db: .inf}\n"
    "    - {name: sys2-10db, order: 12, snr_db: 10}\n";

constexpr double kDcGainTol = 0.02;    // relative, model static gain against 1/Kt
constexpr double kModeFnTol = 0.01;    // relative, torsional mode frequency
constexpr double kModeZetaTol = 0.10;  // relative, its damping ratio
constexpr double kMinFitPct = 90.0;    // model fit to the measured FRF
// Torque against the true torque, % of its range: measured 3.5, 4.9, 6.1 % at 3000, 5000 and
// 7000 rpm (current noise 0.003 A and quantization 0.01 A).
constexpr double kTruthNrmsePct = 8.0;
constexpr double kDynoNrmsePct = 8.0;   // torque against the dynamometer (001 eq. 4.20)
constexpr double kMeanTol = 0.02;       // relative, mean torque over the cut window
constexpr double kToothPassTol = 0.05;  // relative, tooth-passing amplitude

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

Eigen::VectorXd csv_column(const fs::path& file, const std::string& name) {
  DataSpec d;
  d.file = file;
  d.relative_file = file.filename().string();
  return SignalTable::open(d, d.relative_file).channel(name);
}

class SpindleE2E : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    campaign_ = dir_->path() / "campaign";
    report_ = dir_->path() / "report";
    synthesize_campaign(dir_->write("spec.yaml", kSpec), campaign_);
    // A cut whose model names no test of the campaign.
    std::string yaml = read_text(campaign_ / "spindle/cut-n05000/test.yaml");
    const auto at = yaml.find("model: spindle/sweep");
    yaml.replace(at, 20, "model: spindle/none");
    dir_->write("campaign/spindle/orphan/test.yaml", yaml);
    fs::copy_file(campaign_ / "spindle/cut-n05000/current.f32",
                  campaign_ / "spindle/orphan/current.f32");
    fs::copy_file(campaign_ / "spindle/cut-n05000/dyno.csv", campaign_ / "spindle/orphan/dyno.csv");
    ReportOptions o;
    o.pdf = false;
    o.jobs = 2;
    std::ostringstream log;
    rc_ = run_report(campaign_, report_, o, log);
    log_ = log.str();
    results_ = new json(json::parse(read_text(report_ / "results.json")));
    truth_ = new YAML::Node(YAML::LoadFile((campaign_ / "truth.yaml").string()));
  }
  static void TearDownTestSuite() {
    delete results_;
    delete truth_;
    delete dir_;
    results_ = nullptr;
    truth_ = nullptr;
    dir_ = nullptr;
  }
  static const json& test(const std::string& id) { return results_->at("tests").at(id); }
  static TempDir* dir_;
  static fs::path campaign_, report_;
  static int rc_;
  static std::string log_;
  static json* results_;
  static YAML::Node* truth_;
};
TempDir* SpindleE2E::dir_ = nullptr;
fs::path SpindleE2E::campaign_;
fs::path SpindleE2E::report_;
int SpindleE2E::rc_ = -1;
std::string SpindleE2E::log_;
json* SpindleE2E::results_ = nullptr;
YAML::Node* SpindleE2E::truth_ = nullptr;

TEST_F(SpindleE2E, SweepRecoversTheDrive) {
  const json& t = test("spindle/sweep");
  ASSERT_EQ(t.at("status"), "ok") << t.dump(2) << log_;
  const json& m = t.at("model");
  const YAML::Node tr = (*truth_)["tests"]["spindle/sweep"];
  const double dc = tr["dc_gain_A_per_Nm"].as<double>();
  EXPECT_NEAR(m.at("dc_gain").get<double>() / dc, 1.0, kDcGainTol);
  EXPECT_GT(m.at("fit_pct").get<double>(), kMinFitPct);
  EXPECT_GE(m.at("order").get<int>(), 2);
  EXPECT_LE(m.at("order").get<int>(), 40);
  EXPECT_EQ(t.at("frf").at("segment_samples"), 4096);
  // The closed-loop torsional mode: the identified mode nearest the true one.
  const double fn = tr["modes"][0]["fn_hz"].as<double>();
  const double zeta = tr["modes"][0]["zeta"].as<double>();
  double best = 1e300, best_zeta = 0.0;
  for (const auto& md : m.at("modes")) {
    const double f = md.at("fn_hz").get<double>();
    if (std::abs(f - fn) < std::abs(best - fn)) {
      best = f;
      best_zeta = md.at("zeta").get<double>();
    }
  }
  EXPECT_NEAR(best / fn, 1.0, kModeFnTol) << best;
  EXPECT_NEAR(best_zeta / zeta, 1.0, kModeZetaTol) << best_zeta;
}

TEST_F(SpindleE2E, CutsRecoverTheTorqueAtThreeSpeeds) {
  for (const char* id : {"spindle/cut-n03000", "spindle/cut-n05000", "spindle/cut-n07000"}) {
    const json& t = test(id);
    ASSERT_EQ(t.at("status"), "ok") << id << t.dump(2);
    const YAML::Node tr = (*truth_)["tests"][id];
    EXPECT_EQ(t.at("model"), "spindle/sweep");
    EXPECT_NEAR(t.at("observer").at("R_A2").get<double>(), 0.01 * 0.01 / 12.0, 1e-18);
    EXPECT_NEAR(t.at("observer").at("Q_Nm2").get<double>() / tr["Q_Nm2"].as<double>(), 1.0, 1e-8);
    EXPECT_NEAR(t.at("torque_mean_Nm").get<double>() / tr["torque_mean_Nm"].as<double>(), 1.0,
                kMeanTol)
        << id;
    EXPECT_LT(t.at("reference").at("nrmse_pct").get<double>(), kDynoNrmsePct) << id;
    EXPECT_EQ(t.at("observer").at("gain").size(),
              test("spindle/sweep").at("model").at("order").get<std::size_t>() + 1);
    // The torque file against the true torque over the cut window.
    const Eigen::VectorXd est =
        csv_column(report_ / t.at("torque_file").get<std::string>(), "torque");
    const Eigen::VectorXd truth =
        csv_column(campaign_ / tr["torque_file"].as<std::string>(), "torque");
    ASSERT_EQ(est.size(), truth.size());
    const auto c0 = static_cast<Eigen::Index>(tr["cut_window_s"][0].as<double>() * 10000);
    const auto c1 = static_cast<Eigen::Index>(tr["cut_window_s"][1].as<double>() * 10000);
    const Eigen::VectorXd e = est.segment(c0, c1 - c0) - truth.segment(c0, c1 - c0);
    const double range =
        truth.segment(c0, c1 - c0).maxCoeff() - truth.segment(c0, c1 - c0).minCoeff();
    const double nrmse = 100.0 * std::sqrt(e.squaredNorm() / static_cast<double>(c1 - c0)) / range;
    EXPECT_LT(nrmse, kTruthNrmsePct) << id;
    // Tooth-passing amplitude of the true torque, as the kind computes it.
    const double f_tp = tr["tooth_pass_hz"].as<double>();
    std::complex<double> acc = 0.0;
    const Eigen::VectorXd tw = truth.segment(c0, c1 - c0);
    const double mean = tw.mean();
    for (Eigen::Index k = 0; k < tw.size(); ++k) {
      acc += (tw[k] - mean) * std::polar(1.0, -2.0 * 3.141592653589793 * f_tp *
                                                  static_cast<double>(c0 + k) / 10000.0);
    }
    const double amp = 2.0 * std::abs(acc) / static_cast<double>(tw.size());
    EXPECT_NEAR(t.at("tooth_pass_amplitude_Nm").get<double>() / amp, 1.0, kToothPassTol) << id;
    RecordProperty(std::string(id).substr(8) + "_nrmse_truth_pct", std::to_string(nrmse));
  }
}

// Kind frf on the synth section `era` (001 sec. 3.3's validation case): without noise the
// realization is exact (order, fit to the truth FRF 100 % to 1e-4); at 10 dB the model keeps
// the modes that stand above the noise and fits the noise-free FRF better than 60 % (measured
// 0.0 and 77.5 % here; the study of docs/sysid.md gives the spread over 50 systems).
TEST_F(SpindleE2E, EraSectionFrfTests) {
  const auto truth_row = [&](const std::string& id, const std::string& q) {
    for (const auto& r : results_->at("truth_comparison")) {
      if (r.at("source") == id && r.at("quantity") == q) return r.at("estimate").get<double>();
    }
    ADD_FAILURE() << "no truth row " << q << " of " << id;
    return std::nan("");
  };
  const json& clean = test("era/sys1-clean");
  ASSERT_EQ(clean.at("status"), "ok") << clean.dump(2);
  EXPECT_EQ(clean.at("model").at("order").get<int>(), 16);
  EXPECT_NEAR(truth_row("era/sys1-clean", "frf_fit_vs_truth_pct"), 100.0, 1e-4);
  const json& noisy = test("era/sys2-10db");
  ASSERT_EQ(noisy.at("status"), "ok") << noisy.dump(2);
  EXPECT_GE(noisy.at("model").at("order").get<int>(), 2);
  EXPECT_GT(truth_row("era/sys2-10db", "frf_fit_vs_truth_pct"), 60.0);
  RecordProperty("era_10db_fit_vs_truth_pct",
                 std::to_string(truth_row("era/sys2-10db", "frf_fit_vs_truth_pct")));
}

TEST_F(SpindleE2E, ACutWithoutItsModelIsSkippedNamingTheKey) {
  const json& t = test("spindle/orphan");
  EXPECT_NE(t.at("status"), "ok");
  const std::string why = t.at("skip_reason");
  EXPECT_NE(why.find("'model'"), std::string::npos) << why;
  EXPECT_NE(why.find("spindle/none"), std::string::npos) << why;
}

TEST_F(SpindleE2E, ReportAndResultsValidate) {
  const std::string html = read_text(report_ / "index.html");
  EXPECT_NE(html.find("Spindle drive models from sweeps (ERA)"), std::string::npos);
  EXPECT_NE(html.find("Cutting torque from spindle current"), std::string::npos);
  const auto check = chatterlab::testing::check_results_schema(report_ / "results.json");
  EXPECT_TRUE(check.valid) << check.output;
}

}  // namespace
}  // namespace chatterlab::app
