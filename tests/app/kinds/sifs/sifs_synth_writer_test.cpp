// The `sifs` section of a synth spec (app/kinds/sifs/sifs_synth.h): a small campaign written
// through parse_sifs_synth / write_sifs_synth into a temporary folder; its files, test.yaml keys
// (EXPERIMENT_FORMAT section 6), truth entries, determinism and the errors of a bad section.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/common/constants.h"
#include "app/kinds/sifs/sifs_synth.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::TempDir;

// Short records: two weights, two hits, a 1 s cut at 9000 rpm.
const char* kSection =
    "static: {steps: 2, unloaded_s: 2, hold_s: 1.5, transition_s: 0.5}\n"
    "taps: {hits: 2}\n"
    "cuts: {rpm: [9000], duration_s: 1.0, air_s: 0.3, entry_s: 0.05, exit_s: 0.05, "
    "tail_s: 0.05}\n";

SynthContext context(const fs::path& out, std::uint64_t seed = 1) {
  SynthContext ctx;
  ctx.spec_label = "spec.yaml";
  ctx.seed = seed;
  ctx.out = out;
  ctx.tool_given = true;
  SynthTool t;
  t.teeth = 4;
  t.radius_mm = 9.525;
  t.helix_deg = 30.0;
  ctx.tool = t;
  return ctx;
}

// Writes the section into `out`; returns the context (its truth) and the test count.
int write(const std::string& section, SynthContext& ctx) {
  YamlReader r("spec.yaml");
  const auto spec = parse_sifs_synth(YAML::Load(section), ctx, r);
  EXPECT_TRUE(r.errors().empty()) << r.errors().front();
  return write_sifs_synth(*spec, ctx);
}

std::vector<std::string> errors_of(const std::string& section, const SynthContext& ctx) {
  YamlReader r("spec.yaml");
  parse_sifs_synth(YAML::Load(section), ctx, r);
  return r.errors();
}

std::string bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class SifsSynthWriter : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    ctx_ = new SynthContext(context(dir_->path()));
    written_ = write(kSection, *ctx_);
  }
  static void TearDownTestSuite() {
    delete ctx_;
    delete dir_;
  }
  static TempDir* dir_;
  static SynthContext* ctx_;
  static int written_;
};
TempDir* SifsSynthWriter::dir_ = nullptr;
SynthContext* SifsSynthWriter::ctx_ = nullptr;
int SifsSynthWriter::written_ = 0;

TEST_F(SifsSynthWriter, WritesTheTestsOfFormatSection6) {
  EXPECT_EQ(written_, 6);
  const fs::path out = dir_->path();
  for (const char* a : {"x", "y", "z"}) {
    const YAML::Node t =
        YAML::LoadFile((out / "sifs" / (std::string("static-") + a) / "test.yaml").string());
    EXPECT_EQ(t["kind"].as<std::string>(), "sifs-static");
    EXPECT_EQ(t["axis"].as<std::string>(), a);
    EXPECT_EQ(t["sample_rate_hz"].as<double>(), 1024.0);
    EXPECT_EQ(t["data"]["file"].as<std::string>(), "static.f32");
    ASSERT_EQ(t["data"]["channels"].size(), 6u);
    EXPECT_EQ(t["channels"]["z2"]["scale"].as<double>(), 200.0);
    ASSERT_EQ(t["loads"].size(), 5u);  // 0, 1, 2, 1, 0 weights
    EXPECT_EQ(t["loads"][2].size(), 3u);
    const double peak = t["loads"][2][2].as<double>();
    EXPECT_DOUBLE_EQ(peak, std::string(a) == "z" ? -2 * 44.482 : 2 * 44.482);
    EXPECT_EQ(t["loads"][0][2].as<std::string>(), "0");
    // 2 x 2 s unloaded + 3 x 1.5 s loaded + 4 x 0.5 s ramps at 1024 Hz, 6 float32 channels.
    EXPECT_EQ(fs::file_size(out / "sifs" / (std::string("static-") + a) / "static.f32"),
              10752u * 6u * 4u);
  }
  for (const char* a : {"x", "y"}) {
    const fs::path d = out / "sifs" / (std::string("tap-") + a);
    const YAML::Node t = YAML::LoadFile((d / "test.yaml").string());
    EXPECT_EQ(t["kind"].as<std::string>(), "sifs-tap");
    EXPECT_EQ(t["axis"].as<std::string>(), a);
    EXPECT_EQ(t["sample_rate_hz"].as<double>(), 12800.0);
    ASSERT_EQ(t["data"]["channels"].size(), 7u);
    EXPECT_EQ(t["data"]["channels"][0].as<std::string>(), "hammer");
    EXPECT_EQ(t["channels"]["hammer"]["scale"].as<double>(), 444.8);
    ASSERT_EQ(t["hits"].size(), 2u);
    for (const auto& h : t["hits"]) {
      EXPECT_NEAR(h[1].as<double>() - h[0].as<double>(), 0.2, 1e-9);  // equal windows
    }
    EXPECT_EQ(t["band_hz"][1].as<double>(), 4000.0);
    EXPECT_EQ(t["modes"].as<int>(), 3);
    EXPECT_EQ(fs::file_size(d / "taps.f32") % (7 * 4), 0u);
  }
  const fs::path d = out / "sifs" / "cut-n09000";
  const YAML::Node t = YAML::LoadFile((d / "test.yaml").string());
  EXPECT_EQ(t["kind"].as<std::string>(), "sifs-cut");
  EXPECT_EQ(t["spindle_rpm"].as<double>(), 9000.0);
  ASSERT_EQ(t["data"]["channels"].size(), 9u);
  EXPECT_EQ(t["data"]["channels"][6].as<std::string>(), "dx");
  EXPECT_EQ(t["channels"]["dz"]["scale"].as<double>(), 500.0);
  EXPECT_EQ(t["air_window_s"][1].as<double>(), 0.25);
  EXPECT_EQ(t["cut_window_s"][0].as<double>(), 0.4);
  EXPECT_EQ(t["cut_window_s"][1].as<double>(), 0.85);
  EXPECT_EQ(t["taps"]["x"].as<std::string>(), "sifs/tap-x");
  EXPECT_EQ(t["taps"]["y"].as<std::string>(), "sifs/tap-y");
  EXPECT_EQ(t["dynamometer"]["channels"].size(), 3u);
  EXPECT_EQ(t["dynamometer"]["angle_deg"].as<double>(), 30.0);
  EXPECT_EQ(t["filter_rate_hz"].as<double>(), 10000.0);
  EXPECT_EQ(t["unbalance_harmonics"].as<int>(), 2);
  EXPECT_EQ(t["band_hz"].size(), 2u);
  EXPECT_EQ(fs::file_size(d / "cut.f32"), 12800u * 9u * 4u);
  EXPECT_TRUE(fs::exists(out / "truth" / "sifs-cut-n09000.csv"));
  EXPECT_FALSE(fs::exists(out / "campaign.yaml"));  // synth.cpp's
}

TEST_F(SifsSynthWriter, TruthHasTheFormatKeys) {
  const SynthTruth& truth = ctx_->truth;
  Eigen::Matrix3d C, S;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      C(i, j) = truth.top["calibration_matrix"][i][j].as<double>();
      S(i, j) = truth.top["sensitivity_matrix"][i][j].as<double>();
    }
  }
  EXPECT_DOUBLE_EQ(C(0, 1), -19.0);  // the format's truth example
  EXPECT_LT((C * S - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-8);  // 10 digits
  const YAML::Node tap = truth.tests["sifs/tap-x"];
  ASSERT_EQ(tap["modes"].size(), 3u);
  for (const char* k : {"fn_hz", "zeta", "alpha", "residue_phase_deg"}) {
    EXPECT_TRUE(tap["modes"][0][k]) << k;
  }
  EXPECT_EQ(tap["modes"][0]["fn_hz"].as<double>(), 420.0);
  EXPECT_EQ(truth.tests["sifs/tap-y"]["modes"][0]["fn_hz"].as<double>(), 441.0);
  EXPECT_EQ(tap["antiresonances_hz"].size(), 2u);
  EXPECT_EQ(tap["bandwidth_before_hz"].as<double>(), 158.0);
  EXPECT_NEAR(tap["noise_var_N2"].as<double>(), 0.0225, 1e-12);
  const YAML::Node cut = truth.tests["sifs/cut-n09000"];
  EXPECT_EQ(cut["spindle_rpm"].as<double>(), 9000.0);
  EXPECT_EQ(cut["teeth"].as<int>(), 4);
  EXPECT_EQ(cut["force_file"].as<std::string>(), "truth/sifs-cut-n09000.csv");
  ASSERT_EQ(cut["window_s"].size(), 2u);
  const double revs = (cut["window_s"][1].as<double>() - cut["window_s"][0].as<double>()) * 150.0;
  EXPECT_NEAR(revs, std::round(revs), 1e-6);  // whole revolutions
  EXPECT_EQ(cut["noise_var_N2"].size(), 2u);
  ASSERT_EQ(cut["unbalance"]["x"].size(), 2u);
  EXPECT_EQ(cut["unbalance"]["y"][1]["h"].as<int>(), 2);
  const double omega = 9000 * kRpmToRadPerS;
  EXPECT_NEAR(cut["unbalance"]["x"][0]["amp_N"].as<double>(), 7.5e-6 * omega * omega, 1e-8);
  const YAML::Node h = cut["harmonics"];
  ASSERT_EQ(h["h"].size(), 30u);  // 30 x 150 Hz = 0.45 x 10 kHz
  for (const char* k : {"x_re_N", "x_im_N", "x_meas_re_N", "x_meas_im_N", "y_re_N", "y_im_N",
                        "y_meas_re_N", "y_meas_im_N"}) {
    EXPECT_EQ(h[k].size(), 30u) << k;
  }
  EXPECT_TRUE(h["x_mean_N"] && h["y_mean_N"]);
  EXPECT_TRUE(truth.tests["sifs/static-x"]["drift_N_per_min"]);
}

TEST_F(SifsSynthWriter, HarmonicsAreAFitOfTheForceFile) {
  const YAML::Node cut = ctx_->truth.tests["sifs/cut-n09000"];
  std::ifstream in(dir_->path() / cut["force_file"].as<std::string>());
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t,fx,fy,fz");
  std::vector<std::array<double, 4>> rows;
  while (std::getline(in, line)) {
    std::array<double, 4> r{};
    std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf", &r[0], &r[1], &r[2], &r[3]);
    rows.push_back(r);
  }
  ASSERT_EQ(rows.size(), 12800u);
  EXPECT_DOUBLE_EQ(rows[1][0], 1.0 / 12800);
  // A direct least-squares fit (Eigen QR) of c0 + sum_h Re(c_h e^{j h Omega t}) over window_s,
  // each c_h divided by the boxcar's sinc(h SF / fs) (rows are interval means), equals the truth.
  const double fs = 12800, sf = 150, w0 = cut["window_s"][0].as<double>(),
               w1 = cut["window_s"][1].as<double>();
  const YAML::Node h = cut["harmonics"];
  const int H = static_cast<int>(h["h"].size());
  std::vector<Eigen::Index> ks;
  for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(rows.size()); ++k) {
    const double t = static_cast<double>(k) / fs;
    if (t >= w0 - 1e-9 && t < w1 - 1e-9) ks.push_back(k);
  }
  Eigen::MatrixXd A(static_cast<Eigen::Index>(ks.size()), 1 + 2 * H);
  for (std::size_t i = 0; i < ks.size(); ++i) {
    const double t = static_cast<double>(ks[i]) / fs;
    A(static_cast<Eigen::Index>(i), 0) = 1.0;
    for (int j = 0; j < H; ++j) {
      A(static_cast<Eigen::Index>(i), 1 + 2 * j) = std::cos((j + 1) * kTwoPi * sf * t);
      A(static_cast<Eigen::Index>(i), 2 + 2 * j) = -std::sin((j + 1) * kTwoPi * sf * t);
    }
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(A);
  const char* ax[2] = {"x", "y"};
  for (int a = 0; a < 2; ++a) {
    Eigen::VectorXd x(static_cast<Eigen::Index>(ks.size()));
    for (std::size_t i = 0; i < ks.size(); ++i)
      x[static_cast<Eigen::Index>(i)] = rows[ks[i]][1 + a];
    const Eigen::VectorXd p = qr.solve(x);
    const std::string k = ax[a];
    EXPECT_NEAR(p[0], h[k + "_mean_N"].as<double>(), 1e-6);
    double largest = 0.0;
    for (int j = 0; j < H; ++j) largest = std::max(largest, std::hypot(p[1 + 2 * j], p[2 + 2 * j]));
    for (int j = 0; j < H; ++j) {
      const double xs = kPi * (j + 1) * sf / fs, sinc = std::sin(xs) / xs;
      EXPECT_NEAR(p[1 + 2 * j] / sinc, h[k + "_re_N"][j].as<double>(), 1e-6 * largest) << k << j;
      EXPECT_NEAR(p[2 + 2 * j] / sinc, h[k + "_im_N"][j].as<double>(), 1e-6 * largest) << k << j;
      // *_meas_* = G_true(j h Omega) c_h.
      const std::complex<double> c(h[k + "_re_N"][j].as<double>(), h[k + "_im_N"][j].as<double>());
      const auto& plant = a == 0 ? sifs::default_plant_x() : sifs::default_plant_y();
      const std::complex<double> m = sifs::sensor_response(plant, (j + 1) * sf) * c;
      EXPECT_NEAR(m.real(), h[k + "_meas_re_N"][j].as<double>(), 1e-8 * largest + 1e-9);
      EXPECT_NEAR(m.imag(), h[k + "_meas_im_N"][j].as<double>(), 1e-8 * largest + 1e-9);
    }
  }
}

TEST_F(SifsSynthWriter, SameSeedSameBytes) {
  TempDir again, other;
  SynthContext a = context(again.path()), b = context(other.path(), 2);
  write(kSection, a);
  write(kSection, b);
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir_->path())) {
    if (!e.is_regular_file()) continue;
    const fs::path rel = fs::relative(e.path(), dir_->path());
    EXPECT_EQ(bytes(e.path()), bytes(again.path() / rel)) << rel;
    ++files;
  }
  EXPECT_EQ(files, 6 * 2 + 1);
  YAML::Emitter t1, t2;
  t1 << ctx_->truth.tests;
  t2 << a.truth.tests;
  EXPECT_EQ(std::string(t1.c_str()), std::string(t2.c_str()));
  // Another seed: other noise.
  EXPECT_NE(bytes(dir_->path() / "sifs/cut-n09000/cut.f32"),
            bytes(other.path() / "sifs/cut-n09000/cut.f32"));
}

TEST(SifsSynthSpec, EmptySectionTakesTheDefaults) {
  TempDir d;
  YamlReader r("spec.yaml");
  const auto spec = parse_sifs_synth(YAML::Load("{}"), context(d.path()), r);
  EXPECT_TRUE(r.errors().empty());
  const auto& s = dynamic_cast<const SifsSynthSpec&>(*spec);
  EXPECT_EQ(s.folder, "sifs");
  EXPECT_EQ(s.rpm, (std::vector<double>{4500, 9000, 11600}));
  EXPECT_EQ(s.cut.force.teeth, 4);
  EXPECT_DOUBLE_EQ(s.radial_immersion_mm, 9.525);  // the tool radius
  EXPECT_EQ(s.plant_x.size(), 3u);
  EXPECT_DOUBLE_EQ(s.plant_y[0].fn_hz, 441.0);
}

TEST(SifsSynthSpec, BadKeysAreNamed) {
  TempDir d;
  const SynthContext ctx = context(d.path());
  const auto one = [&](const std::string& section) {
    const auto e = errors_of(section, ctx);
    return e.size() == 1 ? e.front() : "(" + std::to_string(e.size()) + " errors)";
  };
  EXPECT_EQ(one("filter_rate_hz: -1"), "spec.yaml: key 'sifs.filter_rate_hz' must be > 0");
  EXPECT_EQ(one("cuts: {rpm: [9000, 9000.2]}"),
            "spec.yaml: key 'sifs.cuts.rpm' 9000.2 rpm is listed twice (tests are named by rpm)");
  EXPECT_EQ(one("plant: {x: {modes: [{fn_hz: 400, zeta: 1.5, alpha: 1}]}}"),
            "spec.yaml: key 'sifs.plant.x.modes[0].zeta' must be in (0, 1)");
  EXPECT_EQ(one("calibration_matrix: [[1, 0, 0], [0, 1, 0], [1, 0, 0]]"),
            "spec.yaml: key 'sifs.calibration_matrix' is singular (S = C^-1 is needed)");
  EXPECT_EQ(one("taps: {hit_spacing_s: 0.2}"),
            "spec.yaml: key 'sifs.taps.hit_spacing_s' must be >= window_s + 0.04 s (windows "
            "never overlap)");
  EXPECT_EQ(one("cuts: {oversample: 3}"), "spec.yaml: key 'sifs.cuts.oversample' must be even");
  // A misspelt key is a warning, not an error.
  YamlReader r("spec.yaml");
  parse_sifs_synth(YAML::Load("taps: {hitz: 3}"), ctx, r);
  EXPECT_TRUE(r.errors().empty());
  ASSERT_EQ(r.warnings().size(), 1u);
  EXPECT_NE(r.warnings().front().find("sifs.taps.hitz"), std::string::npos);
}

TEST(SifsSynthSpec, CutsNeedTheTool) {
  TempDir d;
  SynthContext ctx = context(d.path());
  ctx.tool.reset();
  ctx.tool_given = false;
  YamlReader r("spec.yaml");
  parse_sifs_synth(YAML::Load("{}"), ctx, r);
  ASSERT_EQ(r.errors().size(), 1u);
  EXPECT_EQ(r.errors().front(),
            "spec.yaml: key 'sifs' needs the spec's tool ({teeth, radius_mm}) for its cut tests");
  // Without cuts the tool is not needed.
  EXPECT_TRUE(errors_of("cuts: {rpm: []}", ctx).empty());
}

}  // namespace
}  // namespace chatterlab::app
