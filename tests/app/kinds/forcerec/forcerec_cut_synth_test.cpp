// The `cuts:` block of the synth section `forcerec` (app/kinds/forcerec/forcerec_cut_synth.cpp):
// force-record tests measured through 004 Table 3.1's dynamometer axes, with their truth.
//
// References:
//  - Mean force of a straight-tooth cut over whole revolutions, no edge terms (closed form of
//    the integrals of 000 eqs 2.3-2.4 over the engagement window [s, e], n teeth, on the
//    workpiece): Fx = (n a f / 2 pi) (Kt S1 + Kr S2), Fy = -(n a f / 2 pi) (Kt S2 - Kr S1),
//    S1 = int sin cos = (sin^2 e - sin^2 s) / 2, S2 = int sin^2 = (e - s) / 2 - (sin 2e -
//    sin 2s) / 4.
//  - A two-tooth slot is exactly mean + first tooth harmonic (one tooth in [0, pi) at a time:
//    Fx_tool = -(a f / 2)(Kr + Kt sin 2phi - Kr cos 2phi)), of amplitude (a f / 2)
//    sqrt(Kt^2 + Kr^2); the interval mean of the reference scales it by sin(x) / x,
//    x = pi f_tp / fs.
//  - Noise-free output against the true model discretized at fs driven by the reference: for a
//    sinusoid at w the steady-state mismatch per N of amplitude is |Gd(z) M - Gf(zf) e^(j w
//    dt_f / 2)|, Gd at fs, Gf the model at 16 fs (the writer's), M the mean of the 16 fine
//    mid-point phasors (the reference's interval mean): the oversampling error, in closed form.
//  - Truth figures recomputed from the files with analysis/forcerec/force_metrics.h.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/forcerec/force_metrics.h"
#include "analysis/forcerec/model.h"
#include "analysis/forcerec/transfer_fit.h"
#include "app/kinds/forcerec/forcerec_synth.h"
#include "app/synth/synth.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::TempDir;

// 2 teeth, 6.35 mm diameter (004's end mill); 15360 rpm: f_tp = 512 Hz, exactly 20 samples per
// tooth period at 10240 Hz and 320 fine steps (the tooth changes fall on fine-step edges).
const char* kExactSpec =
    "format: chatterlab-synth/1\n"
    "name: forcerec-cut-exact\n"
    "seed: 11\n"
    "tool: {teeth: 2, radius_mm: 3.175}\n"
    "forcerec:\n"
    "  axes: [x, y]\n"
    "  hits: 1\n"
    "  cuts:\n"
    "    duration_s: 1.5\n"
    "    noise_N: 0\n"
    "    coefficients: {Ktc_N_m2: 6.0e8, Krc_N_m2: 2.4e8, Kte_N_m: 0, Kre_N_m: 0}\n"
    "    list:\n"
    "      - {name: slot, spindle_rpm: 15360, operation: down-milling, axial_depth_mm: 0.5,\n"
    "         radial_immersion_mm: 6.35, feed_per_tooth_mm: 0.0326}\n"
    "      - {name: half-down, spindle_rpm: 15360, operation: down-milling,\n"
    "         axial_depth_mm: 0.5, radial_immersion_mm: 3.175, feed_per_tooth_mm: 0.0326}\n";

std::string noisy_spec(int seed) {
  return "format: chatterlab-synth/1\n"
         "name: forcerec-cut-noisy\n"
         "seed: " +
         std::to_string(seed) +
         "\n"
         "tool: {teeth: 2, radius_mm: 6.35}\n"
         "forcerec:\n"
         "  axes: [x, y]\n"
         "  hits: 1\n"
         "  cuts:\n"
         "    duration_s: 1.5\n"
         "    drift: {fn_scale: 0.97}\n"
         "    list:\n"
         "      - {name: resonant, spindle_rpm: 15345, operation: down-milling,\n"
         "         axial_depth_mm: 0.5, radial_immersion_mm: 6.35, feed_per_tooth_mm: 0.0326}\n"
         "      - {name: calm, spindle_rpm: 6000, operation: down-milling, axial_depth_mm: 0.5,\n"
         "         radial_immersion_mm: 6.35, feed_per_tooth_mm: 0.0326}\n";
}

constexpr double kKt = 6.0e8, kKr = 2.4e8;  // kExactSpec's coefficients (no edge forces), N/m^2
constexpr double kDepth_m = 0.5e-3, kFeed_m = 0.0326e-3;
constexpr double kFs = 10240.0, kToothHz = 512.0;
constexpr Eigen::Index kPeriod = 20;  // samples per tooth period
// The files hold float32: two units in the last place relative to the largest value.
constexpr double kFloatRel = 2.5e-7;
// Mid-point rule over 320 fine steps per tooth period, the pieces smooth between fine-step
// edges: relative error ~ (pi / 320)^2 / 24 = 4e-6; 1e-4 leaves room for float32 sums.
constexpr double kMidpointRel = 1e-4;
// truth.yaml numbers carry 10 significant digits.
constexpr double kTruthRel = 1e-8;

struct Channels {
  Eigen::VectorXd x, y;
};
Channels read_f32_pair(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::vector<float> v;
  float f;
  while (in.read(reinterpret_cast<char*>(&f), sizeof f)) v.push_back(f);
  Channels c;
  const Eigen::Index n = static_cast<Eigen::Index>(v.size() / 2);
  c.x.resize(n);
  c.y.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    c.x[k] = v[static_cast<std::size_t>(2 * k)];
    c.y[k] = v[static_cast<std::size_t>(2 * k + 1)];
  }
  return c;
}
// forces.f32 in N (test.yaml channels: Fx 50 N/V offset -2.2, Fy 50 N/V offset 0.4).
Channels read_forces_N(const fs::path& p) {
  Channels c = read_f32_pair(p);
  c.x = (c.x.array() * 50.0 - 2.2).matrix();
  c.y = (c.y.array() * 50.0 + 0.4).matrix();
  return c;
}
std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

// The mean force on the workpiece of the closed form above.
Eigen::Vector2d closed_form_mean_N(double entry, double exit) {
  const double s1 = (std::pow(std::sin(exit), 2) - std::pow(std::sin(entry), 2)) / 2.0;
  const double s2 = (exit - entry) / 2.0 - (std::sin(2 * exit) - std::sin(2 * entry)) / 4.0;
  const double g = 2.0 * kDepth_m * kFeed_m / kTwoPi;
  return {g * (kKt * s1 + kKr * s2), -g * (kKt * s2 - kKr * s1)};
}

class ForcerecCutSynth : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    synthesize_campaign(dir_->write("exact.yaml", kExactSpec), exact());
    synthesize_campaign(dir_->write("noisy.yaml", noisy_spec(5)), noisy());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path exact() { return dir_->path() / "exact"; }
  static fs::path noisy() { return dir_->path() / "noisy"; }
  static TempDir* dir_;
};
TempDir* ForcerecCutSynth::dir_ = nullptr;

TEST_F(ForcerecCutSynth, SlotReferenceIsMeanPlusFirstHarmonicOfTheClosedForm) {
  const Channels ref = read_f32_pair(exact() / "forcerec/cuts/slot/reference.f32");
  ASSERT_EQ(ref.x.size(), 15360);
  const double max_abs = std::max(ref.x.cwiseAbs().maxCoeff(), ref.y.cwiseAbs().maxCoeff());
  // Air: samples whose interval ends by air_s = 0.5 s are exactly zero.
  EXPECT_EQ(ref.x.head(5120).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(ref.y.head(5120).cwiseAbs().maxCoeff(), 0.0);
  // Tooth periodicity after the ramp (0.52 s): F(k + 20) = F(k).
  for (Eigen::Index k = 5400; k + kPeriod < ref.x.size(); ++k) {
    ASSERT_NEAR(ref.x[k + kPeriod], ref.x[k], kFloatRel * max_abs) << k;
    ASSERT_NEAR(ref.y[k + kPeriod], ref.y[k], kFloatRel * max_abs) << k;
  }
  const forcerec::IndexWindow w = forcerec::harmonic_window(ref.x.size(), kFs, kToothHz, 0.6, 1.45);
  const int count = forcerec::harmonic_count(kFs, kToothHz);
  ASSERT_EQ(count, 8);
  const Eigen::Vector2d mean = closed_form_mean_N(0.0, kPi);
  const double a1 = kDepth_m * kFeed_m / 2.0 * std::hypot(kKt, kKr) *
                    std::sin(kPi * kToothHz / kFs) / (kPi * kToothHz / kFs);
  for (const auto& [v, m] :
       {std::pair<const Eigen::VectorXd*, double>{&ref.x, mean.x()}, {&ref.y, mean.y()}}) {
    const forcerec::Harmonics h = forcerec::tooth_harmonics(*v, w, kFs, kToothHz, count);
    EXPECT_LT(rel(h.mean_N, m), kMidpointRel) << h.mean_N << " vs " << m;
    EXPECT_LT(rel(h.amplitudes_N[0], a1), kMidpointRel) << h.amplitudes_N[0] << " vs " << a1;
    for (int k = 1; k < count; ++k) EXPECT_LT(h.amplitudes_N[k], kMidpointRel * a1) << k;
  }
  // The slot's mean: Fx = a f Kr / 2 > 0, Fy = -a f Kt / 2 (workpiece pushed away from the tool).
  EXPECT_GT(mean.x(), 0.0);
  EXPECT_LT(mean.y(), 0.0);
}

TEST_F(ForcerecCutSynth, HalfImmersionDownMillingMeanMatchesClosedForm) {
  const Channels ref = read_f32_pair(exact() / "forcerec/cuts/half-down/reference.f32");
  const forcerec::IndexWindow w = forcerec::harmonic_window(ref.x.size(), kFs, kToothHz, 0.6, 1.45);
  const Eigen::Vector2d mean = closed_form_mean_N(kPi / 2.0, kPi);  // down-milling, r_i = r
  const double mx = ref.x.segment(w.begin, w.size()).mean();
  const double my = ref.y.segment(w.begin, w.size()).mean();
  EXPECT_LT(rel(mx, mean.x()), kMidpointRel) << mx << " vs " << mean.x();
  EXPECT_LT(rel(my, mean.y()), kMidpointRel) << my << " vs " << mean.y();
  const YAML::Node truth = YAML::LoadFile((exact() / "truth.yaml").string());
  const YAML::Node axes = truth["tests"]["forcerec/cuts/half-down"]["axes"];
  EXPECT_LT(rel(axes["x"]["mean_N"].as<double>(), mean.x()), kMidpointRel);
  EXPECT_LT(rel(axes["y"]["mean_N"].as<double>(), mean.y()), kMidpointRel);
}

TEST_F(ForcerecCutSynth, NoiseFreeOutputIsTheTrueModelOfTheReference) {
  const Channels ref = read_f32_pair(exact() / "forcerec/cuts/slot/reference.f32");
  const Channels out = read_forces_N(exact() / "forcerec/cuts/slot/forces.f32");
  const double w = kTwoPi * kToothHz, dt = 1.0 / kFs, dt_fine = dt / 16.0;
  const double a1 = kDepth_m * kFeed_m / 2.0 * std::hypot(kKt, kKr);
  // The reference's first harmonic per unit of the force's: the mean of 16 mid-point values.
  std::complex<double> mean_of_midpoints = 0.0;
  for (int j = 0; j < 16; ++j) mean_of_midpoints += std::polar(1.0 / 16.0, w * (j + 0.5) * dt_fine);
  const Eigen::VectorXd f = Eigen::VectorXd::Constant(1, kToothHz);
  for (const auto& [axis, r, y] :
       {std::tuple<char, const Eigen::VectorXd*, const Eigen::VectorXd*>{'x', &ref.x, &out.x},
        {'y', &ref.y, &out.y}}) {
    const forcerec::TransferModel m = forcerec_synth::table31_model(axis);
    const forcerec::DiscreteModel dm = forcerec::zoh(forcerec::realize_scaled_modal(m), kFs);
    const forcerec::DiscreteModel fine = forcerec_synth::oversampled_model(m, kFs);
    const Eigen::VectorXd predicted = forcerec::simulate(dm, *r);
    // Steady state per unit force: the file's output (the fine model driven by mid-point
    // values) against the prediction (the model at fs driven by the reference).
    const std::complex<double> g_fine =
        forcerec::frequency_response(fine, f)[0] * std::polar(1.0, w * dt_fine / 2.0);
    const std::complex<double> g_pred = forcerec::frequency_response(dm, f)[0] * mean_of_midpoints;
    const double mismatch = a1 * std::abs(g_pred - g_fine);
    // Over the cut window (0.6 .. 1.45 s): the ramp's transient has decayed (e^-17 at x's
    // slowest pole, zeta 0.02 at 1.4 kHz).
    const Eigen::Index k0 = 6144, k1 = 14848;
    const double err = ((*y) - predicted).segment(k0, k1 - k0).cwiseAbs().maxCoeff();
    // 20 samples per period: the sampled sinusoid peaks within cos(pi / 20) of its amplitude.
    // kFloatN: float32 files (reference ~10 N, volts ~0.3 V x 50 N/V) through the model's gain.
    constexpr double kFloatN = 1e-4;
    EXPECT_LE(err, mismatch + kFloatN) << axis << " mismatch " << mismatch;
    EXPECT_GE(err, mismatch * std::cos(kPi / 20.0) - kFloatN) << axis << " mismatch " << mismatch;
    // The oversampling error is small against the output's harmonic.
    EXPECT_LT(mismatch, 0.05 * a1 * std::abs(g_fine)) << axis;
    std::cout << axis << ": oversampling mismatch " << mismatch << " N, max error " << err
              << " N, harmonic " << a1 * std::abs(g_fine) << " N\n";
  }
}

TEST_F(ForcerecCutSynth, TruthAndTestYamlAreConsistentWithTheFiles) {
  const YAML::Node truth = YAML::LoadFile((noisy() / "truth.yaml").string());
  for (const std::string name : {"resonant", "calm"}) {
    SCOPED_TRACE(name);
    const std::string id = "forcerec/cuts/" + name;
    const YAML::Node e = truth["tests"][id];
    ASSERT_TRUE(e.IsMap());
    const double rpm = name == "resonant" ? 15345.0 : 6000.0;
    const double ftp = rpm * 2.0 / 60.0;
    EXPECT_EQ(e["samples"].as<long>(), 15360);
    EXPECT_EQ(e["sample_rate_hz"].as<double>(), kFs);
    EXPECT_LT(rel(e["tooth_freq_hz"].as<double>(), ftp), kTruthRel);
    EXPECT_EQ(e["harmonic_count"].as<int>(), std::min(12, static_cast<int>(0.4 * kFs / ftp)));
    EXPECT_EQ(e["cut_window_s"][0].as<double>(), 0.6);
    EXPECT_EQ(e["cut_window_s"][1].as<double>(), 1.45);
    EXPECT_EQ(e["force_file"].as<std::string>(), id + "/reference.f32");
    EXPECT_EQ(e["channels"][0].as<std::string>(), "Fx");
    EXPECT_EQ(e["channels"][1].as<std::string>(), "Fy");

    const YAML::Node t = YAML::LoadFile((noisy() / id / "test.yaml").string());
    EXPECT_EQ(t["kind"].as<std::string>(), "force-record");
    EXPECT_EQ(t["operation"].as<std::string>(), "down-milling");
    EXPECT_EQ(t["spindle_rpm"].as<double>(), rpm);
    EXPECT_EQ(t["data"]["file"].as<std::string>(), "forces.f32");
    EXPECT_EQ(t["channels"]["Fx"]["offset"].as<double>(), -2.2);
    EXPECT_EQ(t["channels"]["Fy"]["scale"].as<double>(), 50.0);
    EXPECT_EQ(t["air_window_s"][1].as<double>(), 0.45);
    EXPECT_EQ(t["cut_window_s"][0].as<double>(), 0.6);
    EXPECT_EQ(t["frf_tests"]["x"].as<std::string>(), "forcerec/hammer/x");
    EXPECT_EQ(t["frf_tests"]["y"].as<std::string>(), "forcerec/hammer/y");
    EXPECT_EQ(t["reference"]["force"]["file"].as<std::string>(), "reference.f32");

    const Channels ref = read_f32_pair(noisy() / e["force_file"].as<std::string>());
    const Channels meas = read_forces_N(noisy() / id / "forces.f32");
    ASSERT_EQ(ref.x.size(), 15360);
    ASSERT_EQ(meas.x.size(), 15360);
    const forcerec::IndexWindow eval = forcerec::evaluation_window(15360, kFs);
    const forcerec::IndexWindow hw = forcerec::harmonic_window(15360, kFs, ftp, 0.6, 1.45);
    const int count = e["harmonic_count"].as<int>();
    for (const auto& [axis, r, y] :
         {std::tuple<std::string, const Eigen::VectorXd*, const Eigen::VectorXd*>{"x", &ref.x,
                                                                                  &meas.x},
          {"y", &ref.y, &meas.y}}) {
      SCOPED_TRACE(axis);
      const YAML::Node a = e["axes"][axis];
      ASSERT_TRUE(a.IsMap());
      EXPECT_EQ(a["frf_test"].as<std::string>(), "forcerec/hammer/" + axis);
      EXPECT_TRUE(truth["tests"][a["frf_test"].as<std::string>()].IsMap());
      EXPECT_LT(rel(a["noise_var_N2"].as<double>(), 0.1 * 0.1), kTruthRel);  // the default noise_N
      const forcerec::Harmonics h = forcerec::tooth_harmonics(*r, hw, kFs, ftp, count);
      const forcerec::Harmonics hm = forcerec::tooth_harmonics(*y, hw, kFs, ftp, count);
      EXPECT_LT(rel(a["mean_N"].as<double>(), h.mean_N), kTruthRel);
      ASSERT_EQ(a["harmonics_N"].size(), static_cast<std::size_t>(count));
      ASSERT_EQ(a["measured_harmonics_N"].size(), static_cast<std::size_t>(count));
      for (int k = 0; k < count; ++k) {
        EXPECT_LT(rel(a["harmonics_N"][k].as<double>(), h.amplitudes_N[k]), kTruthRel) << k;
        EXPECT_LT(rel(a["measured_harmonics_N"][k].as<double>(), hm.amplitudes_N[k]), 1e-6)
            << k;  // measured: the calibration's round trip in double
      }
      const double rms = std::sqrt(r->segment(eval.begin, eval.size()).squaredNorm() / eval.size());
      EXPECT_LT(rel(a["force_rms_N"].as<double>(), rms), kTruthRel);
      EXPECT_LT(rel(a["measured_nrmse_pct"].as<double>(), forcerec::nrmse_pct(*y, *r, eval)), 1e-6);
      const double inverse = a["oracle_inverse_nrmse_pct"].as<double>();
      const double tikhonov = a["oracle_tikhonov_nrmse_pct"].as<double>();
      EXPECT_GT(tikhonov, 0.0);
      EXPECT_LE(tikhonov, inverse);
      std::cout << name << " " << axis << ": measured " << a["measured_nrmse_pct"].as<double>()
                << " %, inverse " << inverse << " %, tikhonov " << tikhonov << " %\n";
    }
  }
  // drift: hammer-before tests of Table 3.1 with every frequency times 0.97.
  for (const std::string axis : {"x", "y"}) {
    const YAML::Node before = truth["tests"]["forcerec/hammer-before/" + axis];
    const YAML::Node after = truth["tests"]["forcerec/hammer/" + axis];
    ASSERT_TRUE(before.IsMap()) << axis;
    EXPECT_TRUE(fs::exists(noisy() / "forcerec/hammer-before" / axis / "hits.f32"));
    EXPECT_NE(before["source"].as<std::string>().find("0.97"), std::string::npos);
    ASSERT_EQ(before["modes"].size(), after["modes"].size());
    for (std::size_t i = 0; i < after["modes"].size(); ++i) {
      EXPECT_LT(rel(before["modes"][i]["fn_hz"].as<double>(),
                    0.97 * after["modes"][i]["fn_hz"].as<double>()),
                kTruthRel);
      EXPECT_LT(
          rel(before["modes"][i]["zeta"].as<double>(), after["modes"][i]["zeta"].as<double>()),
          1e-6);  // from roots that went through a polynomial round trip
    }
    EXPECT_LT(rel(before["dc_gain"].as<double>(), after["dc_gain"].as<double>()), kTruthRel);
  }
}

TEST_F(ForcerecCutSynth, SameSeedSameFilesOtherSeedOtherNoise) {
  TempDir d;
  synthesize_campaign(d.write("same.yaml", noisy_spec(5)), d.path() / "same");
  synthesize_campaign(d.write("other.yaml", noisy_spec(6)), d.path() / "other");
  const std::string cut = "forcerec/cuts/resonant/";
  EXPECT_EQ(read_bytes(d.path() / "same" / cut / "forces.f32"),
            read_bytes(noisy() / cut / "forces.f32"));
  EXPECT_EQ(read_bytes(d.path() / "same" / "truth.yaml"), read_bytes(noisy() / "truth.yaml"));
  EXPECT_NE(read_bytes(d.path() / "other" / cut / "forces.f32"),
            read_bytes(noisy() / cut / "forces.f32"));
  // The force itself does not depend on the seed.
  EXPECT_EQ(read_bytes(d.path() / "other" / cut / "reference.f32"),
            read_bytes(noisy() / cut / "reference.f32"));
}

TEST(ForcerecCutSynthSpec, BadKeysAreNamed) {
  const std::string head =
      "format: chatterlab-synth/1\nname: bad\nseed: 1\ntool: {teeth: 2, radius_mm: 3.175}\n"
      "forcerec:\n  cuts:\n";
  const std::string cut =
      "{name: a, spindle_rpm: 6000, operation: down-milling, axial_depth_mm: 0.5, "
      "radial_immersion_mm: 3, feed_per_tooth_mm: 0.03}";
  struct Case {
    std::string body, key;
  };
  const std::vector<Case> cases = {
      {"    sample_rate_hz: -1\n    list: [" + cut + "]\n", "forcerec.cuts.sample_rate_hz'"},
      {"    duration_s: 3000\n    list: [" + cut + "]\n", "forcerec.cuts.duration_s'"},
      {"    air_s: 2.8\n    list: [" + cut + "]\n", "forcerec.cuts.air_s'"},
      {"    noise_N: -0.1\n    list: [" + cut + "]\n", "forcerec.cuts.noise_N'"},
      {"    coefficients: {Ktc_N_m2: 0}\n    list: [" + cut + "]\n",
       "forcerec.cuts.coefficients.Ktc_N_m2'"},
      {"    drift: {fn_scale: 3}\n    list: [" + cut + "]\n", "forcerec.cuts.drift.fn_scale'"},
      {"    list: []\n", "forcerec.cuts.list'"},
      {"    sample_rate_hz: 100\n", "forcerec.cuts.list'"},
      {"    list: [" + cut + ", " + cut + "]\n", "forcerec.cuts.list[1].name'"},
      {"    list: [{name: ../up, spindle_rpm: 6000, operation: down-milling, axial_depth_mm: 0.5, "
       "radial_immersion_mm: 3, feed_per_tooth_mm: 0.03}]\n",
       "forcerec.cuts.list[0].name'"},
      {"    list: [{name: a, spindle_rpm: 150000, operation: down-milling, axial_depth_mm: 0.5, "
       "radial_immersion_mm: 3, feed_per_tooth_mm: 0.03}]\n",
       "forcerec.cuts.list[0].spindle_rpm'"},
      {"    list: [{name: a, spindle_rpm: 6000, operation: sideways, axial_depth_mm: 0.5, "
       "radial_immersion_mm: 3, feed_per_tooth_mm: 0.03}]\n",
       "forcerec.cuts.list[0].operation'"},
      {"    list: [{name: a, spindle_rpm: 6000, operation: up-milling, axial_depth_mm: 0.5, "
       "radial_immersion_mm: 7, feed_per_tooth_mm: 0.03}]\n",
       "forcerec.cuts.list[0].radial_immersion_mm'"},
  };
  for (const Case& c : cases) {
    TempDir d;
    try {
      synthesize_campaign(d.write("spec.yaml", head + c.body), d.path() / "out");
      ADD_FAILURE() << "no error for\n" << c.body;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("key '" + c.key), std::string::npos)
          << e.what() << "\nfor\n"
          << c.body;
    }
  }
  // No tool: the block cannot be written.
  TempDir d;
  try {
    synthesize_campaign(d.write("spec.yaml",
                                "format: chatterlab-synth/1\nname: bad\nseed: 1\n"
                                "forcerec:\n  cuts:\n    list: [" +
                                    cut + "]\n"),
                        d.path() / "out");
    ADD_FAILURE() << "no error without a tool";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'forcerec.cuts' needs the spec's `tool`"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace chatterlab::app
