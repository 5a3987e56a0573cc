// End to end: campaigns written by `synth` and by hand (as another tool would write them to
// EXPERIMENT_FORMAT.md) through `report`, checked in results.json and index.html.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "analysis/cutting/slot_synth.h"
#include "analysis/lobes/lobes.h"
#include "app/cli/validate.h"
#include "app/core/campaign.h"
#include "app/core/signals.h"
#include "app/lobes/lobes_run.h"
#include "app/report/report.h"
#include "app/simulate/simulate.h"
#include "app/synth/synth.h"
#include "render/subprocess.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::kCampaignYaml;
using chatterlab::testing::TempDir;
using nlohmann::json;

json read_json(const std::filesystem::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

double rel_err(double est, double truth) { return std::abs(est - truth) / std::abs(truth); }

// The demo spec through synth and report: the numbers of the foundation issue.
TEST(ReportEndToEnd, DemoCampaignRecoversTruth) {
  TempDir d;
  const auto campaign = d.path() / "demo";
  const auto out = d.path() / "report";
  synthesize_campaign(std::filesystem::path(CHATTERLAB_SOURCE_DIR) / "experiments/demo.synth.yaml",
                      campaign);
  std::ostringstream log;
  ReportOptions opt;
  opt.pdf = false;  // the PDF path has its own test below
  ASSERT_EQ(run_report(campaign, out, opt, log), 0) << log.str();
  const json r = read_json(out / "results.json");
  EXPECT_EQ(r["format"], "chatterlab-results/1");
  EXPECT_EQ(r["campaign"], "demo-al6061");

  // Truth of experiments/demo.synth.yaml, mode 1 of x and y (the hammer test at rest of 000
  // sec. 5.1): m = 0.03211 kg, c = 13.39 kg/s, k = 1.023e6 N/m. Tolerances: the foundation
  // issue's (fn 0.3 %, m and k 2 %, c 5 %).
  const double m = 0.03211, c = 13.39, k = 1.023e6;
  const double fn = std::sqrt(k / m) / (2 * M_PI);
  for (const char* id : {"tap/x", "tap/y"}) {
    const json& t = r["tests"][id];
    ASSERT_EQ(t["status"], "ok") << id << ": " << t.dump();
    ASSERT_GE(t["modes"].size(), 2u) << id;
    const json& m1 = t["modes"][0];
    EXPECT_LT(rel_err(m1["fn_hz"], fn), 0.003) << id;
    EXPECT_LT(rel_err(m1["m_kg"], m), 0.02) << id;
    EXPECT_LT(rel_err(m1["k_N_m"], k), 0.02) << id;
    EXPECT_LT(rel_err(m1["c_kg_s"], c), 0.05) << id;
  }
  // Hit 3 of x bounces (demo spec): rejected and said so.
  int rejected = 0;
  for (const auto& h : r["tests"]["tap/x"]["hits"]) {
    if (!h["accepted"].get<bool>()) {
      ++rejected;
      EXPECT_NE(h["rejected_because"].get<std::string>().find("double hit"), std::string::npos);
    }
  }
  EXPECT_EQ(rejected, 1);
  EXPECT_EQ(r["tests"]["tap/x"]["hits_used"], 4);

  // Dyno group: appendix values of the spec; Ktc, Krc within 3 %, Kte, Kre within 15 %.
  const json& g = r["groups"]["dyno-slot"];
  ASSERT_TRUE(g.contains("Ktc_N_m2")) << g.dump();
  EXPECT_LT(rel_err(g["Ktc_N_m2"], 5.89e8), 0.03);
  EXPECT_LT(rel_err(g["Krc_N_m2"], 3.19e8), 0.03);
  EXPECT_LT(rel_err(g["Kte_N_m"], 9080), 0.15);
  EXPECT_LT(rel_err(g["Kre_N_m"], 11300), 0.15);
  EXPECT_EQ(g["tests"].size(), 6u);

  // Every input hashed; the truth comparison present.
  // campaign, truth, 25 tests x (test.yaml, signals), the grinding test's inspections file,
  // the spindle-current cut's dynamometer file and the two force records' reference files (11
  // tests of the main document and grinding, 8 of the spindle-sensor set, 2 of the spindle
  // drive, 4 of the table dynamometer)
  EXPECT_EQ(r["inputs_sha256"].size(), 1u + 1u + 2u * 25u + 1u + 1u + 2u);
  // The table dynamometer (004): both records reconstructed on both axes by all three methods
  // (their figures against truth: force_record_e2e_test).
  for (const char* id : {"forcerec/cuts/resonant", "forcerec/cuts/calm"}) {
    ASSERT_EQ(r["tests"][id]["status"], "ok") << id;
    for (const char* a : {"x", "y"}) {
      for (const char* method : {"akf", "smo", "rd"}) {
        EXPECT_TRUE(r["tests"][id]["axes"][a]["methods"][method].contains("nrmse_pct"))
            << id << a << method;
      }
    }
  }
  // Cut tests: offset angle against truth.yaml, modulo the half turn: the equal-teeth model of
  // 000 sec. 5.1 (hammer modes and dyno Ktc, Krc on both teeth) cannot tell the half turns
  // apart, and the identified one fixes them only up to the tooth labels. offset_angle_deg is
  // the offset found again with the identified values: the 0.5 deg target. The hammer/dyno
  // offset matches the measured revolution only roughly (teeth 27-fold apart, hammer damping
  // -40 %): 1.5 deg. Measured: 148.1 and 33.6 (hammer/dyno), 147.0 and 32.5 (identified).
  const auto off_by = [](double est, double truth) {
    const double diff = std::fmod(std::abs(est - truth), 180.0);
    return std::min(diff, 180.0 - diff);
  };
  const json& c1 = r["tests"]["cuts/constant-1mm"];
  ASSERT_EQ(c1["status"], "ok") << c1.dump();
  EXPECT_LT(off_by(c1["offset_hammer_dyno_deg"], 147.0), 1.5);
  EXPECT_LT(off_by(c1["offset_angle_deg"], 147.0), 0.5);
  EXPECT_EQ(c1["offset_source"], "identified");
  EXPECT_FALSE(c1.contains("bifurcation_depth_mm"));  // constant depth: the key is absent
  const json& ci = r["tests"]["cuts/incline"];
  ASSERT_EQ(ci["status"], "ok") << ci.dump();
  EXPECT_LT(off_by(ci["offset_hammer_dyno_deg"], 212.5), 1.5);
  EXPECT_LT(off_by(ci["offset_angle_deg"], 212.5), 0.5);
  EXPECT_EQ(ci["air_revolutions"], 48);
  // Measured bifurcation depth against the same cut simulated directly with the truth values
  // (no sensors, runout or tachometer in between), read by the same detector.
  const auto spec =
      d.write("incline.yaml",
              "format: chatterlab-simulation/1\n"
              "tool: {teeth: 2, radius_mm: 6.35}\n"
              "modal: {m_kg: 0.03134, c_kg_s: 22.21, k_N_m: 9.84e5}\n"
              "coefficients: {Kt_N_m2: [2.483e8, 6.641e9], Kr_N_m2: [2.196e8, 4.154e9]}\n"
              "cut: {spindle_rpm: 15000, feed_per_tooth_mm: 0.0635, radial_immersion_mm: 0.382,\n"
              "      axial_depth_mm: [0.0, 4.0], revolutions_per_mm: 500}\n");
  SimulateOptions so;
  so.report = false;
  ASSERT_EQ(run_simulate(spec, d.path() / "sim", so, log), 0);
  const double simulated = read_json(d.path() / "sim/results.json")["bifurcation_depth_mm"];
  EXPECT_NEAR(ci["bifurcation_depth_mm"].get<double>(), simulated, 0.1);
  // The same cut simulated with the incline's identified values (000 table 5.1): within
  // 0.2 mm of the measured depth (measured 2.50 and 2.50).
  ASSERT_TRUE(ci["simulated_identified"]["traditional"].contains("bifurcation_depth_mm"))
      << ci["simulated_identified"].dump();
  EXPECT_NEAR(ci["simulated_identified"]["traditional"]["bifurcation_depth_mm"].get<double>(),
              ci["bifurcation_depth_mm"].get<double>(), 0.2);
  EXPECT_TRUE(ci["simulated_identified"]["numerical"].contains("bifurcation_depth_mm"));

  // Every estimator variant on both cuts, with steps, runtime and rank; the EKFs with their
  // repeatability (the unscented twins are not repeated: docs/estimators.md).
  for (const json* cut : {&c1, &ci}) {
    ASSERT_EQ((*cut)["estimators"].size(), 13u) << (*cut)["estimators"].dump();
    for (const auto& [id, v] : (*cut)["estimators"].items()) {
      ASSERT_TRUE(v.contains("estimates")) << id << ": " << v.dump();
      EXPECT_GT(v["steps"].get<double>(), 390000) << id;
      EXPECT_GT(v["runtime_s"].get<double>(), 0) << id;
      EXPECT_TRUE(v.contains("observability_rank")) << id;
      const bool unscented = id.rfind("ukf-", 0) == 0;
      const bool feedback = id == "ekf-coeff-xy-feedback";
      EXPECT_EQ(v["filter"], unscented  ? "unscented"
                             : feedback ? "extended-feedback"
                                        : "extended")
          << id;
      if (feedback) {
        // The difference table (results.json chip_feedback) says the same, per key.
        ASSERT_EQ((*cut)["chip_feedback"].size(), 4u) << (*cut)["chip_feedback"].dump();
        for (const auto& [key, difference] : (*cut)["chip_feedback"].items()) {
          EXPECT_LT(std::abs(difference.get<double>()), 1.0) << key;
        }
        // At the demo's 5e-7 m noise the measured chip is nearly unbiased: the feedback filter
        // agrees with the measured-chip per-tooth filter within 1 % (estimate_feedback_test
        // has the noisier cuts where it does not).
        EXPECT_FALSE(v.contains("repeatability")) << id;
        const json& twin = (*cut)["estimators"]["ekf-coeff-xy-per-tooth"];
        for (const auto& [key, value] : v["estimates"].items()) {
          const double e = twin["estimates"][key].get<double>();
          EXPECT_NEAR(value.get<double>(), e, 1e-2 * std::abs(e)) << id << " " << key;
        }
      } else if (unscented) {
        EXPECT_FALSE(v.contains("repeatability")) << id;
        // Against the EKF twin: the coefficient models are linear, so the two agree to
        // rounding (1e-8 relative); the modal ones within 1 % (measured: 0.25 % on c, less on
        // m and k).
        const json& twin = (*cut)["estimators"]["ekf-" + id.substr(4)];
        const double tolerance = id.rfind("ukf-coeff", 0) == 0 ? 1e-8 : 1e-2;
        for (const auto& [key, value] : v["estimates"].items()) {
          const double e = twin["estimates"][key].get<double>();
          EXPECT_NEAR(value.get<double>(), e, tolerance * std::abs(e)) << id << " " << key;
        }
      } else {
        EXPECT_EQ(v["repeatability"]["runs"], 10) << id;
        EXPECT_EQ(v["repeatability"]["status"], "ok") << id;
      }
    }
  }
  EXPECT_EQ(r["identified_from"], "cuts/constant-1mm");
  for (const char* key :
       {"m_kg", "c_kg_s", "k_N_m", "Kt1_N_m2", "Kr1_N_m2", "Kt2_N_m2", "Kr2_N_m2"}) {
    EXPECT_TRUE(r["identified"].contains(key)) << key;
  }

  // Truth rows: offsets (hammer/dyno within 1.5 deg, identified within 0.5 deg) and the
  // identified values of both cuts, the incline's relabelled (its offset is a half turn from
  // the truth's): coefficients 2 %, m and k 2 %, c 10 %; the scale-free fn, K / k 2 %,
  // zeta 10 %.
  EXPECT_GT(r["truth_comparison"].size(), 10u);
  int offset_rows = 0, identified_rows = 0;
  for (const auto& row : r["truth_comparison"]) {
    const std::string q = row["quantity"];
    const double err = std::abs(row["error_pct"].get<double>());
    if (q == "offset_angle_deg" || q == "offset_hammer_dyno_deg") {
      ++offset_rows;
      EXPECT_LT(std::abs(row["estimate"].get<double>() - row["truth"].get<double>()),
                q == "offset_angle_deg" ? 0.5 : 1.5);
    } else if (q.rfind("identified.", 0) == 0) {
      ++identified_rows;
      const bool damping = q == "identified.c_kg_s" || q == "identified.zeta";
      EXPECT_LT(err, damping ? 10.0 : 2.0) << q << " " << row["source"];
    }
  }
  EXPECT_EQ(offset_rows, 4);
  EXPECT_EQ(identified_rows, 2 * (7 + 6));  // m, c, k, 4 coefficients; fn, zeta, 4 K / k

  // The constant-depth cut at 1 mm is chatter-free (000 table 5.2's tool at 15,000 rpm is
  // stable to about 1.24 mm under the linear model): its Poincare map is a fixed point.
  const json& c1mm = r["tests"]["cuts/constant-1mm"];
  EXPECT_EQ(c1mm["orbit"], "fixed point");
  EXPECT_EQ(c1mm["chatter"], false);
  EXPECT_FALSE(c1mm.contains("bifurcation_depth_mm"));  // constant depth: absent (format)
  // Stability lobes of the campaign: one condition (up-milling, 0.382 mm), the hammer/dyno
  // lobes and one per cut's identified set, both cuts drawn over them.
  const json& lobes = r["groups"]["lobes"];
  ASSERT_TRUE(lobes.contains("diagrams")) << lobes.dump().substr(0, 400);
  ASSERT_EQ(lobes["diagrams"].size(), 1u);
  const json& dia = lobes["diagrams"][0];
  EXPECT_EQ(dia["operation"], "up-milling");
  EXPECT_DOUBLE_EQ(dia["radial_immersion_mm"].get<double>(), 0.382);
  for (const char* src :
       {"hammer-dyno", "identified:cuts/constant-1mm", "identified:cuts/incline"}) {
    ASSERT_TRUE(dia["sources"].contains(src)) << src;
    EXPECT_EQ(dia["sources"][src]["methods"]["semi-discretization"]["limit_depth_mm"].size(), 200u);
  }
  EXPECT_EQ(dia["sources"]["hammer-dyno"]["modes_x"].size(), 2u);  // both fitted modes of x
  ASSERT_EQ(dia["measured"].size(), 2u);
  // The truth's limit at the cuts' speed, by the same method and discretization: the lobes of
  // each identified set agree within 5 % (measured: 1.8 % and 2.5 %; truth 1.238 mm).
  lobes::LobesInput truth;
  truth.teeth = 2;
  truth.radius_m = 6.35e-3;
  truth.Kt_N_m2 = {2.483e8, 6.641e9};
  truth.Kr_N_m2 = {2.196e8, 4.154e9};
  truth.radial_immersion_m = 0.382e-3;
  truth.x_modes = truth.y_modes = {ModalParameters{0.03134, 22.21, 9.84e5}};
  truth.spindle_rpm = {15000};
  const auto truth_limit =
      lobes::semi_discretization(truth, semi_discretization_options(truth, 0, 1)).speeds[0];
  ASSERT_TRUE(truth_limit.limit_depth_m);
  for (const json& cut : dia["measured"]) {
    EXPECT_DOUBLE_EQ(cut["spindle_rpm"].get<double>(), 15000.0);
    for (const char* src : {"identified:cuts/constant-1mm", "identified:cuts/incline"}) {
      EXPECT_LT(rel_err(cut["predicted"][src]["limit_depth_mm"], *truth_limit.limit_depth_m * 1e3),
                0.05)
          << src;
    }
    if (cut["test"] == "cuts/constant-1mm") {
      EXPECT_EQ(cut["state"], "stable");
      for (const auto& [src, p] : cut["predicted"].items()) EXPECT_EQ(p["agrees"], true) << src;
    } else {
      EXPECT_EQ(cut["ramp"], true);
      EXPECT_EQ(cut["state"], "changes");
      EXPECT_NEAR(cut["bifurcation_depth_mm"].get<double>(),
                  r["tests"]["cuts/incline"]["bifurcation_depth_mm"].get<double>(), 1e-12);
    }
  }
  const std::string html = read_text(out / "index.html");
  EXPECT_NE(html.find("Cutting-force coefficients"), std::string::npos);
  EXPECT_NE(html.find("figures/tap-tap-x-frf.svg"), std::string::npos);
  // The screen page loads only the SVGs (the PNGs are print's), lazily; each test and figure
  // has an anchor, which the nested contents and the summary table link to.
  EXPECT_EQ(html.find("figures/tap-tap-x-frf.png"), std::string::npos);
  EXPECT_NE(
      html.find("<img loading=\"lazy\" class=\"screen-only\" src=\"figures/tap-tap-x-frf.svg\""),
      std::string::npos);
  EXPECT_NE(html.find("<figure class=\"fig\" id=\"fig-tap-tap-x-frf\">"), std::string::npos);
  EXPECT_NE(html.find("<section class=\"test\" id=\"test-tap-x\">"), std::string::npos);
  EXPECT_NE(html.find("<li><a href=\"#test-tap-x\">tap/x</a></li>"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"#test-tap-x\">tap/x</a></td>"), std::string::npos);
  EXPECT_NE(html.find("<section id=\"references\">"), std::string::npos);
  // No path of the machine: the campaign folder appears by its name only.
  const std::string root = std::filesystem::absolute(campaign).string();
  EXPECT_EQ(html.find(root), std::string::npos);
  EXPECT_EQ(read_text(out / "results.json").find(root), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(out / ".print.html"));
  // results.csv: results.json's values as rows, the first mode's frequency among them.
  EXPECT_EQ(r["results_csv"], "results.csv");
  const std::string table = read_text(out / "results.csv");
  char row[96];
  std::snprintf(row, sizeof(row), "\ntap/x,modes.0.fn_hz,%.10g\n",
                r["tests"]["tap/x"]["modes"][0]["fn_hz"].get<double>());
  EXPECT_NE(table.find(row), std::string::npos) << row;
  EXPECT_TRUE(std::filesystem::exists(out / "figures/tap-tap-x-frf.png"));
  EXPECT_TRUE(std::filesystem::exists(out / "figures/tap-tap-x-frf.svg"));
  EXPECT_TRUE(std::filesystem::exists(out / "figures/dyno-force-vs-feed.svg"));
  EXPECT_TRUE(std::filesystem::exists(out / "figures/lobes-up-0.382mm.svg"));
  EXPECT_NE(html.find("<section id=\"lobes\">"), std::string::npos);
  EXPECT_NE(html.find("figures/lobes-up-0.382mm.svg"), std::string::npos);
}

void write_raw_dyno(const TempDir& d, const std::string& id, double feed_mm, std::uint64_t seed) {
  cutting::SlotRecordSpec s;
  s.spindle_rpm = 500;
  s.feed_per_tooth_m = feed_mm * 1e-3;
  s.depth_m = 2e-3;
  s.coefficients = {6.61e8, 3.17e8, 9740, 7620};  // appendix, "30-deg Uncoated Short"
  s.theta_dyn_rad = -0.41;
  s.offset_x_N = -4;
  s.noise_std_N = 1.0;
  s.fs_hz = 10000;
  s.duration_s = 1.5;
  s.seed = seed;
  const auto rec = cutting::generate_slot_record(s);
  const auto dir = d.path() / id;
  std::filesystem::create_directories(dir);
  write_signals(dir / "rec.f64", {"zero", "Fy", "Fx"}, {&rec.zero_V, &rec.Fy_N, &rec.Fx_N});
  std::ostringstream y;
  y << "kind: dyno-slot\nspindle_rpm: 500\nfeed_per_tooth_mm: " << feed_mm
    << "\naxial_depth_mm: 2\nsample_rate_hz: 10000\n"
    << "data: {file: rec.f64, channels: [zero, Fy, Fx]}\n"
    << "acquisition_pc: lab-3   # a key of another tool: ignored with a warning\n";
  d.write(id + "/test.yaml", y.str());
}

// A campaign as another tool writes it: raw .f64 files with their own channel order, deep
// folders, extra keys; and broken tests beside it that must be skipped with their reasons.
TEST(ReportEndToEnd, BrokenTestsAreSkippedAndTheRestRuns) {
  TempDir d;
  d.write("campaign.yaml", std::string(kCampaignYaml) + "operator: someone\n");
  write_raw_dyno(d, "2026-11-20/dyno/a", 0.05, 1);
  write_raw_dyno(d, "2026-11-20/dyno/b", 0.10, 2);
  write_raw_dyno(d, "2026-11-20/dyno/c", 0.15, 3);
  d.write("broken/ragged/test.yaml",
          "kind: tap\naxis: x\nsample_rate_hz: 1000\ndata: {file: h.csv}\nresponse: velocity\n");
  d.write("broken/ragged/h.csv", "force,response\n1,2\n3\n");
  d.write("broken/nan/test.yaml",
          "kind: tap\naxis: y\nsample_rate_hz: 1000\ndata: {file: h.csv}\nresponse: velocity\n");
  d.write("broken/nan/h.csv", "force,response\n1,2\nNaN,2\n");
  d.write("broken/nohit/test.yaml",
          "kind: tap\naxis: y\nsample_rate_hz: 1000\ndata: {file: h.csv}\nresponse: velocity\n");
  std::string flat = "force,response\n";
  for (int i = 0; i < 2000; ++i) flat += "0,0\n";
  d.write("broken/nohit/h.csv", flat);
  d.write("broken/kind/test.yaml", "kind: laser-scan\nsample_rate_hz: 1\ndata: {file: h.csv}\n");
  d.write("broken/kind/h.csv", "a\n1\n");
  d.write("broken/missing/test.yaml", "kind: dyno-slot\nsample_rate_hz: 1000\n");
  const std::string tap_head = "kind: tap\naxis: x\nresponse: velocity\n";
  d.write("broken/type/test.yaml", tap_head + "sample_rate_hz: fast\ndata: {file: h.csv}\n");
  d.write("broken/type/h.csv", "force,response\n1,2\n");
  d.write("broken/rate/test.yaml", tap_head + "sample_rate_hz: -5\ndata: {file: h.csv}\n");
  d.write("broken/rate/h.csv", "force,response\n1,2\n");
  d.write("broken/cell/test.yaml", tap_head + "sample_rate_hz: 100\ndata: {file: h.csv}\n");
  d.write("broken/cell/h.csv", "force,response\n1,2\n1,2x\n");
  d.write("broken/nofile/test.yaml", tap_head + "sample_rate_hz: 100\ndata: {file: gone.csv}\n");
  d.write("broken/misspelt/test.yaml", tap_head + "sample_rate: 100\ndata: {file: h.csv}\n");
  d.write("broken/misspelt/h.csv", "force,response\n1,2\n");
  d.write("broken/truncated/test.yaml",
          "kind: dyno-slot\nspindle_rpm: 500\nfeed_per_tooth_mm: 0.1\naxial_depth_mm: 2\n"
          "sample_rate_hz: 10000\ndata: {file: rec.f32, channels: [Fx, Fy, zero]}\n");
  d.write("broken/truncated/rec.f32", std::string(4 * 3 * 100 + 8, '\0'));
  // A cut whose tachometer never pulses (all samples 0 V): the test is skipped, no number shown.
  d.write("broken/notach/test.yaml",
          "kind: cut\noperation: up-milling\nspindle_rpm: 15000\nfeed_per_tooth_mm: 0.0635\n"
          "radial_immersion_mm: 0.382\naxial_depth_mm: 1.0\ncut_window_s: [0.01, 0.02]\n"
          "sample_rate_hz: 100000\ndata: {file: s.f32, channels: [x, y, tach]}\n");
  d.write("broken/notach/s.f32", std::string(4 * 3 * 2500, '\0'));

  std::ostringstream log;
  ReportOptions opt;
  opt.pdf = false;
  ASSERT_EQ(run_report(d.path(), d.path() / "out", opt, log), 0) << log.str();
  const json r = read_json(d.path() / "out/results.json");
  const json& t = r["tests"];
  ASSERT_EQ(t.size(), 15u);
  for (const char* id : {"2026-11-20/dyno/a", "2026-11-20/dyno/b", "2026-11-20/dyno/c"}) {
    EXPECT_EQ(t[id]["status"], "ok") << id << t[id].dump();
    // theta_dyn defined modulo 180 deg; -0.41 rad = -23.49 deg.
    EXPECT_NEAR(t[id]["theta_dyn_deg"].get<double>(), -0.41 * 180 / M_PI, 0.5) << id;
  }
  EXPECT_LT(rel_err(r["groups"]["dyno-slot"]["Ktc_N_m2"], 6.61e8), 0.03);
  EXPECT_LT(rel_err(r["groups"]["dyno-slot"]["Krc_N_m2"], 3.17e8), 0.03);

  auto reason = [&](const char* id) {
    EXPECT_EQ(t[id]["status"], "skipped") << id;
    EXPECT_FALSE(t[id].contains("modes")) << id;  // no number from a failed step
    return t[id]["skip_reason"].get<std::string>();
  };
  EXPECT_EQ(reason("broken/ragged"),
            "broken/ragged/h.csv: line 3 has 1 cells, the header has 2 (ragged row)");
  EXPECT_EQ(reason("broken/nan"), "broken/nan/h.csv: NaN value at line 3, column 'force'");
  EXPECT_NE(reason("broken/nohit").find("no hit above threshold"), std::string::npos);
  EXPECT_NE(reason("broken/kind").find("'laser-scan' is not a known test kind"), std::string::npos);
  EXPECT_NE(reason("broken/missing").find("broken/missing/test.yaml: key 'data' is missing"),
            std::string::npos);
  EXPECT_NE(reason("broken/missing").find("key 'spindle_rpm' is missing"), std::string::npos);
  EXPECT_EQ(reason("broken/type"),
            "broken/type/test.yaml: key 'sample_rate_hz' must be a number, got 'fast'");
  EXPECT_NE(reason("broken/rate").find("broken/rate/test.yaml: key 'sample_rate_hz' = -5"),
            std::string::npos);
  EXPECT_EQ(reason("broken/cell"),
            "broken/cell/h.csv: line 3, column 'response': '2x' is not a number");
  EXPECT_EQ(reason("broken/nofile"),
            "broken/nofile/test.yaml: key 'data.file' 'gone.csv': file not found");
  EXPECT_EQ(reason("broken/misspelt"),
            "broken/misspelt/test.yaml: key 'sample_rate_hz' is missing (found 'sample_rate': "
            "misspelt?)");
  EXPECT_EQ(
      reason("broken/notach"),
      "broken/notach/s.f32: tachometer: no tachometer edges: the tach channel is flat at 0 V");
  EXPECT_FALSE(t["broken/notach"].contains("offset_angle_deg"));
  EXPECT_EQ(reason("broken/truncated"),
            "broken/truncated/rec.f32: size 1208 bytes is not a multiple of 3 channels x 4 bytes "
            "(truncated file or wrong data.channels)");

  const std::string html = read_text(d.path() / "out/index.html");
  EXPECT_NE(html.find("line 3 has 1 cells, the header has 2 (ragged row)"), std::string::npos);
  EXPECT_NE(html.find("acquisition_pc"), std::string::npos);  // the ignored key is reported
}

TEST(ReportEndToEnd, ValidateListsProblemsAndFails) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write("t/test.yaml",
          "kind: tap\naxis: z\nsample_rate_hz: 1000\ndata: {file: h.csv}\nresponse: velocity\n");
  d.write("t/h.csv", "force,response\n1,2\n");
  d.write("u/test.yaml",
          "kind: tap\naxis: x\nsample_rate_hz: 1000\ndata: {file: h.csv}\nresponse: velocity\n");
  d.write("u/h.csv", "force,resp\n1,2\n");
  CampaignSpec c = load_campaign(d.path());
  std::ostringstream out;
  EXPECT_EQ(validate_campaign(c, out), 1);
  EXPECT_NE(out.str().find("t/test.yaml: key 'axis' must be x or y, got 'z'"), std::string::npos);
  EXPECT_NE(out.str().find("u/h.csv: channel 'response' is required for a tap test (channels: "
                           "force, resp)"),
            std::string::npos);
  EXPECT_NE(out.str().find("2 tests found, 0 usable, 2 unusable"), std::string::npos);
}

// The real measured campaign in shared/data (read only): the whole report with its PDF.
TEST(ReportEndToEnd, RealImpactCampaignWithPdf) {
  const std::filesystem::path campaign = std::string(CHATTERLAB_SHARED_DATA) + "/real-pyfrf-impact";
  ASSERT_TRUE(std::filesystem::exists(campaign / "campaign.yaml")) << campaign;
  TempDir d;
  std::ostringstream log;
  ASSERT_EQ(run_report(campaign, d.path(), {}, log), 0) << log.str();
  const json r = read_json(d.path() / "results.json");
  const json& t = r["tests"]["tap/x"];
  ASSERT_EQ(t["status"], "ok") << t.dump();
  EXPECT_EQ(t["hits_used"], 5);
  // The two largest receptance peaks found by independent peak picking (frf_real_tap_test):
  // 810.21 Hz and 899.99 Hz; a fitted mode within half a bin (df = 1 Hz) of each.
  for (const double peak : {810.21, 899.99}) {
    double best = 1e9;
    for (const auto& m : t["modes"])
      best = std::min(best, std::abs(m["fn_hz"].get<double>() - peak));
    EXPECT_LT(best, 0.5) << peak;
  }
  EXPECT_GT(t["fit_nrmse_pct"].get<double>(), 85.0);
  // 1 s records cannot resolve damping of ~0.1 %: flagged per mode and said once.
  EXPECT_TRUE(t["modes"][0]["resolution_limited"].get<bool>());
  int resolution_lines = 0;
  for (const auto& w : t["warnings"]) {
    resolution_lines += w.get<std::string>().find("resolution-limited") != std::string::npos;
  }
  EXPECT_EQ(resolution_lines, 1);
  EXPECT_GT(std::filesystem::file_size(d.path() / "report.pdf"), 20000u);
  EXPECT_EQ(r["inputs_sha256"]["tap/x/hits.csv"].get<std::string>().size(), 64u);
  // The PDF is PDF/A-3b and carries results.json byte for byte (its checks in full:
  // tests/render/html_to_pdf_pdfa_test.cpp); the print page it came from is gone.
  const auto pdf = (d.path() / "report.pdf").string();
  const auto meta = render::run_process({"pdfinfo", "-meta", pdf});
  EXPECT_NE(meta.out.find("<pdfaid:part>3</pdfaid:part>"), std::string::npos) << meta.out;
  const auto attached = d.path() / "attached.json";
  const auto saved = render::run_process({"pdfdetach", "-save", "1", "-o", attached.string(), pdf});
  ASSERT_EQ(saved.exit_code, 0) << saved.err;
  EXPECT_EQ(read_text(attached), read_text(d.path() / "results.json"));
  EXPECT_FALSE(std::filesystem::exists(d.path() / ".print.html"));
  // Nothing of the machine's paths in the PDF's text either.
  const auto text = render::run_process({"pdftotext", pdf, "-"});
  EXPECT_EQ(text.out.find(std::filesystem::absolute(campaign).string()), std::string::npos);
}

TEST(ReportEndToEnd, MissingCampaignFolderFails) {
  TempDir d;
  std::ostringstream log;
  EXPECT_EQ(run_report(d.path() / "nothing", d.path() / "out", {}, log), 1);
  EXPECT_NE(log.str().find("not a folder"), std::string::npos);
}

}  // namespace
}  // namespace chatterlab::app
