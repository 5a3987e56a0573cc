// Figure file names unique per figure (issue 16): a stem that an earlier figure took gets "-2",
// "-3", ..., never a number another figure has as its own stem.
#include <gtest/gtest.h>

#include "app/report/figure_jobs.h"

namespace chatterlab::app {
namespace {

using Stems = std::vector<std::string>;

TEST(UniqueFigureStems, ACollidingStemGetsTheFirstFreeNumber) {
  EXPECT_EQ(unique_figure_stems({}), Stems{});
  EXPECT_EQ(unique_figure_stems({"figures/a", "figures/b"}), (Stems{"figures/a", "figures/b"}));
  // "tap/x" and "tap-x" give the same stem.
  EXPECT_EQ(figure_stem("tap", "tap/x"), figure_stem("tap", "tap-x"));
  EXPECT_EQ(unique_figure_stems({"figures/tap-tap-x-frf", "figures/tap-tap-x-frf"}),
            (Stems{"figures/tap-tap-x-frf", "figures/tap-tap-x-frf-2"}));
  // "-2" is another figure's own stem: the next number.
  EXPECT_EQ(unique_figure_stems({"figures/s", "figures/s", "figures/s-2", "figures/s"}),
            (Stems{"figures/s", "figures/s-3", "figures/s-2", "figures/s-4"}));
}

}  // namespace
}  // namespace chatterlab::app
