// frf::dominant_mode: the fitted mode with the largest peak receptance, checked against the
// receptance itself at each mode's natural frequency (|H(wn)| = 1 / (c wn) for one mode).
#include <gtest/gtest.h>

#include <complex>
#include <vector>

#include "analysis/frf/mode.h"

namespace chatterlab {
namespace frf {
namespace {

// The mode whose single-mode receptance peaks highest, by frf::receptance (second method).
std::size_t largest_peak(const std::vector<Mode>& modes) {
  std::size_t best = 0;
  double peak = -1.0;
  for (std::size_t i = 0; i < modes.size(); ++i) {
    const Eigen::VectorXd f = Eigen::VectorXd::Constant(1, modes[i].fn_hz);
    const double h = std::abs(receptance({modes[i]}, f)[0]);
    if (h > peak) {
      peak = h;
      best = i;
    }
  }
  return best;
}

TEST(DominantMode, TheMostFlexibleModeWinsWhateverItsOrder) {
  // 000 sec. 5.1's hammer-test tool mode (897 Hz) and the demo's holder modes (2.76, 2.95 kHz).
  const Mode tool = mode_from_mck(0.03211, 13.39, 1.023e6);
  const Mode holder_x = mode_from_mck(0.06, 30.0, 1.8e7);
  const Mode holder_y = mode_from_mck(0.07, 35.0, 2.4e7);
  for (const std::vector<Mode>& modes :
       {std::vector<Mode>{tool, holder_x, holder_y}, std::vector<Mode>{holder_x, tool, holder_y},
        std::vector<Mode>{holder_y, holder_x, tool}}) {
    const auto d = dominant_mode(modes);
    ASSERT_TRUE(d.has_value());
    EXPECT_EQ(d->k_N_m, tool.k_N_m);
    EXPECT_EQ(d->k_N_m, modes[largest_peak(modes)].k_N_m);
  }
}

TEST(DominantMode, ReceptanceNotFrequencyDecides) {
  // A stiffer mode with so little damping that its peak is the higher one: c = 2 zeta sqrt(k m)
  // = 1.885 kg/s, 1 / (c wn) = 2.8e-5 m/N against 1 / (13.39 * 2 pi 897) = 1.3e-5 m/N.
  const Mode tool = mode_from_mck(0.03211, 13.39, 1.023e6);
  const Mode sharp = mode_from_modal(3000.0, 0.0005, 0.1);
  const std::vector<Mode> modes = {tool, sharp};
  ASSERT_EQ(largest_peak(modes), 1u);
  EXPECT_EQ(dominant_mode(modes)->fn_hz, sharp.fn_hz);
}

TEST(DominantMode, NoModesNoDominantMode) { EXPECT_FALSE(dominant_mode({}).has_value()); }

}  // namespace
}  // namespace frf
}  // namespace chatterlab
