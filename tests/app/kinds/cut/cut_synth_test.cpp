// `synth` cut tests read back through the campaign loader: tachometer edges where theta_1
// equals the offset angle, calibrated sensor signals that give back the simulated tip
// deflection, runout periodic in the angle.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/milling/simulation.h"
#include "app/core/campaign.h"
#include "app/core/signals.h"
#include "app/kinds/cut/cut_spec.h"
#include "app/synth/synth.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::TempDir;

const char* kSpec =
    "format: chatterlab-synth/1\n"
    "name: cut-synth\n"
    "seed: 5\n"
    "tool: {teeth: 2, radius_mm: 6.35}\n"
    "cut:\n"
    "  sample_rate_hz: 100000\n"
    "  spindle_rpm: 15000\n"
    "  modal: {m_kg: 0.03134, c_kg_s: 22.21, k_N_m: 9.84e5}\n"
    "  coefficients: {Kt_N_m2: [2.483e8, 6.641e9], Kr_N_m2: [2.196e8, 4.154e9]}\n"
    "  noise_m: 0.0\n"
    "  air_revolutions: 10\n"
    "  tests:\n"
    "    - {name: c1, axial_depth_mm: 1.0, duration_s: 0.04, offset_angle_deg: 147.0}\n";

TEST(SynthCut, TachometerSensorsAndTruth) {
  TempDir d;
  d.write("spec.yaml", kSpec);
  const auto s = synthesize_campaign(d.path() / "spec.yaml", d.path() / "c");
  EXPECT_EQ(s.tests_written, 1);
  const CampaignSpec c = load_campaign(d.path() / "c");
  ASSERT_EQ(c.tests.size(), 1u);
  const TestSpec& t = c.tests[0];
  ASSERT_TRUE(t.usable()) << t.errors.front();
  ASSERT_NE(dynamic_cast<const CutSpec*>(t.params.get()), nullptr);
  EXPECT_DOUBLE_EQ(t.kind_spec<CutSpec>().cut_window_s.first,
                   10 * 0.004);  // 10 air revolutions of 4 ms
  const SignalTable table = SignalTable::open(t.data, "signals.f32");
  const Eigen::VectorXd tach = table.channel("tach", t.channel("tach"));
  const Eigen::VectorXd x = table.channel("x", t.channel("x"));  // metres at the sensor
  const int P = 400;                                             // samples per revolution
  ASSERT_EQ(table.samples(), static_cast<std::size_t>((10 + 10 + 2) * P));

  // Rising edges at theta_1 = 147 deg: sample 147/360 * 400 = 163.33 of each revolution.
  int edges = 0;
  for (Eigen::Index i = 1; i < tach.size(); ++i) {
    if (tach[i - 1] < 2.5 && tach[i] >= 2.5) {
      const double at = static_cast<double>(i - 1) + (2.5 - tach[i - 1]) / (tach[i] - tach[i - 1]);
      EXPECT_NEAR(std::fmod(at, P) / P * 360.0, 147.0, 1e-5);  // float storage
      ++edges;
    }
  }
  EXPECT_EQ(edges, 22);

  // Air: the contour repeats every revolution exactly (no noise in this spec).
  for (Eigen::Index i = 0; i < 8 * P; i += 37) EXPECT_NEAR(x[i], x[i + P], 1e-10);

  // Cut: (sensor - air contour at the same angle) * sensor_to_tip is the simulated deflection.
  milling::SimulationOptions o;
  o.modal_x = {0.03134, 22.21, 9.84e5};
  o.coefficients = {milling::cutting_coefficients(2.483e8, 2.196e8),
                    milling::cutting_coefficients(6.641e9, 4.154e9)};
  o.depth = milling::DepthProfile::constant(1e-3, 10);
  o.steps_per_tooth = 800;  // 1600 steps per revolution: every 4th step is a sample
  milling::RecordingRequest rec;
  rec.trace_revolutions = 10;
  const auto sim = milling::simulate(o, rec);
  ASSERT_TRUE(sim.summary.ok());
  double worst = 0, largest = 0;
  for (Eigen::Index k = 0; k < 10 * P; ++k) {
    const Eigen::Index i = 10 * P + k;
    const double tip = (x[i] - x[i % P]) * t.kind_spec<CutSpec>().sensor_to_tip;
    const double truth = sim.trace.x_m[static_cast<std::size_t>(4 * k)];
    worst = std::max(worst, std::abs(tip - truth));
    largest = std::max(largest, std::abs(truth));
  }
  EXPECT_GT(largest, 1e-6);  // the tool does deflect in this cut
  // float32 volts: ~1e-7 relative of the 5 V gap voltage, 3.9e-5 m/V -> 2e-11 m at the sensor.
  EXPECT_LT(worst, 1e-9);
}

}  // namespace
}  // namespace chatterlab::app
