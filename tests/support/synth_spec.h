// The text of a synth spec (docs/format/synth-spec.md) for tests that write a campaign of every
// kind: tap tests at the hammer values of 000 sec. 5.1 on x and y, a three-feed dyno-slot group
// at the coefficients of 000 sec. 3.2, and cut tests at the in-cut modal parameters and per-tooth
// coefficients of 000 table 5.2. Keys a test does not vary keep synth's defaults.
#pragma once

#include <string>

namespace chatterlab::testing {

struct SynthSpecText {
  std::string name = "synth-test";
  int seed = 1;
  // tap
  double tap_sample_rate_hz = 25600;
  int tap_hits = 3;
  double tap_hit_spacing_s = 1.0;
  int tap_double_hit_x = 0;  // 0: none
  // dyno
  double dyno_duration_s = 1.0;
  // cut
  std::string cut_modal = "{m_kg: 0.03134, c_kg_s: 22.21, k_N_m: 9.84e5}";
  std::string cut_coefficients = "{Kt_N_m2: [2.483e8, 6.641e9], Kr_N_m2: [2.196e8, 4.154e9]}";
  int cut_air_revolutions = 30;
  // The `tests:` entries of the cut section, one "    - {...}\n" line each; empty: no cut
  // section.
  std::string cut_tests;

  std::string text() const {
    const auto num = [](double v) {
      std::string s = std::to_string(v);
      s.erase(s.find_last_not_of('0') + 1);
      if (!s.empty() && s.back() == '.') s.pop_back();
      return s;
    };
    std::string t = "format: chatterlab-synth/1\nname: " + name +
                    "\nseed: " + std::to_string(seed) +
                    "\ntool: {teeth: 2, radius_mm: 6.35}\n"
                    "tap:\n"
                    "  sample_rate_hz: " +
                    num(tap_sample_rate_hz) + "\n  hits: " + std::to_string(tap_hits) +
                    "\n  hit_spacing_s: " + num(tap_hit_spacing_s) +
                    "\n  axes:\n"
                    "    x: {modes: [{m_kg: 0.03211, c_kg_s: 13.39, k_N_m: 1.023e6}]" +
                    (tap_double_hit_x > 0 ? ", double_hit: " + std::to_string(tap_double_hit_x)
                                          : std::string()) +
                    "}\n"
                    "    y: {modes: [{m_kg: 0.03211, c_kg_s: 13.39, k_N_m: 1.023e6}]}\n"
                    "dyno:\n"
                    "  spindle_rpm: 600\n"
                    "  axial_depth_mm: 1.0\n"
                    "  feeds_mm: [0.05, 0.10, 0.15]\n"
                    "  sample_rate_hz: 20000\n"
                    "  duration_s: " +
                    num(dyno_duration_s) +
                    "\n  theta_dyn_deg: 20\n"
                    "  noise_N: 2.0\n"
                    "  coefficients: {Ktc_N_m2: 5.89e8, Kte_N_m: 9080, Krc_N_m2: 3.19e8, "
                    "Kre_N_m: 11300}\n";
    if (cut_tests.empty()) return t;
    return t +
           "cut:\n"
           "  sample_rate_hz: 100000\n"
           "  spindle_rpm: 15000\n"
           "  feed_per_tooth_mm: 0.0635\n"
           "  radial_immersion_mm: 0.382\n"
           "  modal: " +
           cut_modal + "\n  coefficients: " + cut_coefficients +
           "\n  air_revolutions: " + std::to_string(cut_air_revolutions) + "\n  tests:\n" +
           cut_tests;
  }
};

}  // namespace chatterlab::testing
