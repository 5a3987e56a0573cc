// The small archive the nightly tests run (nightly_e2e_test, nightly_slurm_e2e_test).
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "app/synth/synth.h"
#include "tests/support/synth_spec.h"

namespace chatterlab::testing {

// Writes the archive: a/ (tap, dyno-slot and one short cut), b/ (tap and dyno-slot, another
// seed) and broken/ (a campaign.yaml that is not YAML). The synth specs go to `scratch`.
inline void write_nightly_archive(const std::filesystem::path& root,
                                  const std::filesystem::path& scratch) {
  for (const std::string name : {"a", "b"}) {
    SynthSpecText st;
    st.name = "nightly-" + name;
    st.seed = name == "a" ? 3 : 4;
    st.tap_sample_rate_hz = 12800;
    st.tap_hit_spacing_s = 0.5;
    st.dyno_duration_s = 0.5;
    st.cut_air_revolutions = 10;
    if (name == "a") {
      st.cut_tests =
          "    - {name: constant, axial_depth_mm: 1.0, duration_s: 0.1, offset_angle_deg: 147.0}\n";
    }
    const std::filesystem::path spec = scratch / (name + ".synth.yaml");
    std::ofstream(spec) << st.text();
    app::synthesize_campaign(spec, root / name);
    if (name == "a") {
      std::ofstream(root / name / "campaign.yaml", std::ios::app)
          << "estimation: {window_s: 0.02, max_passes: 1, repeat_runs: 0, settle_revolutions: 5}\n";
    }
  }
  std::filesystem::create_directories(root / "broken");
  std::ofstream(root / "broken" / "campaign.yaml") << "name: [unclosed\n";
}

}  // namespace chatterlab::testing
