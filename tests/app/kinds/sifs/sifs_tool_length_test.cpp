// Calibration against tool length (003 eq. 3-4 generalised to every entry of C; docs/sifs.md):
// static tests with `tool_length_mm` give one calibration per length and the straight line of
// each entry; a consumer takes its own length's matrix, the law between lengths, and must name
// its length when several were calibrated.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "analysis/sifs/sifs_synth.h"
#include "app/core/campaign.h"
#include "app/core/signals.h"
#include "app/kinds/sifs/sifs_kinds.h"
#include "app/pipeline/pipeline.h"
#include "app/report/results_json.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::TempDir;

constexpr double kMatrixTol = 0.005;  // max |C - C_true| / max |C_true|, as in sifs_e2e_test

// C at tool length L: the lateral rows fall with L as 003 table 3's c_X, c_Y do (about
// -0.06 per mm), the axial row is independent of L (003 table 3: c_Z).
Eigen::Matrix3d true_C(double L) {
  Eigen::Matrix3d C = sifs::default_calibration_matrix();
  C.row(0) *= 1.0 - 0.003 * (L - 100.0);
  C.row(1) *= 1.0 - 0.0035 * (L - 100.0);
  return C;
}

void write_static(const TempDir& d, const std::string& id, sifs::Axis axis, double L,
                  std::uint64_t seed) {
  sifs::StaticSynthOptions o;
  o.C = true_C(L);
  o.seed = seed;
  o.unloaded_s = 3;
  o.hold_s = 2;
  o.steps = 3;
  o.load_sign = axis == sifs::Axis::kZ ? -1.0 : 1.0;
  const sifs::StaticSynth s = sifs::synthesize_static(axis, o);
  std::vector<Eigen::VectorXd> cols;
  std::vector<const Eigen::VectorXd*> ptrs;
  for (int c = 0; c < 6; ++c) cols.push_back(s.washers_n.col(c));
  for (const auto& c : cols) ptrs.push_back(&c);
  fs::create_directories(d.path() / id);
  write_signals(d.path() / id / "static.csv", {"x1", "x2", "y1", "y2", "z1", "z2"}, ptrs);
  std::ostringstream y;
  y << "kind: sifs-static\naxis: " << sifs::to_string(axis)
    << "\nsample_rate_hz: 1024\ndata: {file: static.csv}\ntool_length_mm: " << L << "\nloads:\n";
  y.precision(10);
  for (const auto& w : s.windows) {
    y << "  - [" << w.start_s << ", " << w.end_s << ", " << w.load_n << "]\n";
  }
  d.write(id + "/test.yaml", y.str());
}

double matrix_error(const nlohmann::json& m, const Eigen::Matrix3d& truth) {
  double err = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      err = std::max(
          err, std::abs(m[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)].get<double>() -
                        truth(i, j)));
    }
  }
  return err / truth.cwiseAbs().maxCoeff();
}

TEST(SifsToolLength, OneCalibrationPerLengthAndTheLaw) {
  TempDir d;
  d.write("campaign.yaml", chatterlab::testing::kCampaignYaml);
  const double lengths[2] = {100.0, 140.0};
  std::uint64_t seed = 1;
  for (double L : lengths) {
    for (auto a : {sifs::Axis::kX, sifs::Axis::kY, sifs::Axis::kZ}) {
      write_static(d, "L" + std::to_string(static_cast<int>(L)) + "/" + sifs::to_string(a), a, L,
                   seed++);
    }
  }
  CampaignResults r = run_campaign(load_campaign(d.path()), {});
  const GroupOutcome* g = r.group("sifs-static");
  ASSERT_NE(g, nullptr);
  ASSERT_TRUE(g->status.ok()) << g->status.message;
  const nlohmann::json j = builtin_kinds().find_group("sifs-static")->results(*g);
  ASSERT_EQ(j["by_tool_length"].size(), 2u) << j.dump();
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(j["by_tool_length"][k]["tool_length_mm"], lengths[k]);
    EXPECT_LT(matrix_error(j["by_tool_length"][k]["calibration_matrix"], true_C(lengths[k])),
              kMatrixTol);
  }
  // The law at a length between them is the straight line of the two, which the truth is.
  const SifsCalibration& cal = g->result_as<SifsStaticGroupResult>()->calibration;
  std::string note;
  const Eigen::Matrix3d mid = cal.at(120.0, &note);
  EXPECT_LT((mid - true_C(120.0)).cwiseAbs().maxCoeff() / true_C(120.0).cwiseAbs().maxCoeff(),
            kMatrixTol);
  EXPECT_NE(note.find("tool-length law"), std::string::npos) << note;
  note.clear();
  EXPECT_EQ(cal.at(140.0, &note), cal.by_length[1].second);
  EXPECT_TRUE(note.empty());
  try {
    cal.at(std::nullopt, &note);
    ADD_FAILURE() << "no tool length accepted with two calibrated";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tool_length_mm"), std::string::npos) << e.what();
  }
}

TEST(SifsToolLength, MixedNamedAndUnnamedLengthsAreRefused) {
  TempDir d;
  d.write("campaign.yaml", chatterlab::testing::kCampaignYaml);
  write_static(d, "a/x", sifs::Axis::kX, 100, 1);
  write_static(d, "a/y", sifs::Axis::kY, 100, 2);
  write_static(d, "a/z", sifs::Axis::kZ, 100, 3);
  write_static(d, "b/x", sifs::Axis::kX, 140, 4);
  write_static(d, "b/y", sifs::Axis::kY, 140, 5);
  write_static(d, "b/z", sifs::Axis::kZ, 140, 6);
  // b/z without its length.
  std::string y = chatterlab::testing::kCampaignYaml;
  {
    std::ifstream in(d.path() / "b/z/test.yaml");
    std::stringstream s;
    s << in.rdbuf();
    y = s.str();
  }
  const auto at = y.find("tool_length_mm: 140\n");
  ASSERT_NE(at, std::string::npos) << y;
  y.erase(at, std::string("tool_length_mm: 140\n").size());
  d.write("b/z/test.yaml", y);
  CampaignResults r = run_campaign(load_campaign(d.path()), {});
  const GroupOutcome* g = r.group("sifs-static");
  ASSERT_NE(g, nullptr);
  EXPECT_FALSE(g->status.ok());
  EXPECT_NE(g->status.message.find("tool_length_mm in every sifs-static test"), std::string::npos)
      << g->status.message;
}

}  // namespace
}  // namespace chatterlab::app
