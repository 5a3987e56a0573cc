// Figure file names unique per figure (issue 16): a stem that an earlier figure took gets "-2",
// "-3", ..., never a number another figure has as its own stem. A figure's data file that
// cannot be written fails, also when only closing it fails (a full device).
#include <gtest/gtest.h>

#include <filesystem>

#include "analysis/common/summary.h"
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

TEST(WriteFigureCsv, AFullDeviceFails) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  render::Figure fig;
  render::Axes& a = fig.panels.emplace_back();
  a.series.push_back({{1.0, 2.0}, {0.5, 1.0}, "small"});  // all of it still in the buffer
  EXPECT_THROW(write_figure_csv(fig, "/dev/full", "figures/f"), InputError);
}

}  // namespace
}  // namespace chatterlab::app
