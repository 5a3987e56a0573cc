// Decisions the backend makes before gnuplot runs: tics, ranges, legend corners, layout.
#include "render/plot_layout.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "render/axis_tics.h"
#include "render/render_error.h"

namespace chatterlab::render {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(ChooseTics, LinearStepThinsToFitTheRoom) {
  // Phase in degrees: every 20 deg when there is room, every 50 deg in a short panel.
  EXPECT_DOUBLE_EQ(choose_tics({-180, 0}, false, 12).step, 20.0);
  EXPECT_DOUBLE_EQ(choose_tics({-180, 0}, false, 4).step, 50.0);  // -150 .. 0: 4 tics
  EXPECT_DOUBLE_EQ(choose_tics({-180, 0}, false, 3).step, 100.0);
  EXPECT_EQ(choose_tics({-180, 0}, false, 12).label_chars, 4u);  // "-180"
}

TEST(ChooseTics, LogAxisOverDecades) {
  const AxisTics hz = choose_tics({50, 5000}, true, 10);
  EXPECT_TRUE(hz.decades);
  EXPECT_DOUBLE_EQ(hz.start, 100.0);
  EXPECT_DOUBLE_EQ(hz.step, 10.0);
  EXPECT_FALSE(hz.power_format);  // 100, 1000: plain numbers
  EXPECT_EQ(hz.label_chars, 4u);

  const AxisTics mag = choose_tics({3e-10, 2e-6}, true, 10);
  EXPECT_TRUE(mag.power_format);  // 10^{-9} .. 10^{-6}
  EXPECT_DOUBLE_EQ(mag.step, 10.0);

  // Twelve decades in a panel with room for four labels: every third decade.
  EXPECT_DOUBLE_EQ(choose_tics({1e-12, 1.0}, true, 5).step, 1000.0);
}

TEST(ChooseTics, LogAxisUnderTwoDecadesGetsLabelledOneTwoFive) {
  const AxisTics t = choose_tics({20, 700}, true, 10);
  EXPECT_FALSE(t.decades);
  EXPECT_EQ(t.values, (std::vector<double>{20, 50, 100, 200, 500}));
  EXPECT_EQ(t.labels, (std::vector<std::string>{"20", "50", "100", "200", "500"}));
  // Within one decade no 1-2-5 value fits twice: linear steps instead.
  const AxisTics inside = choose_tics({3, 8}, true, 10);
  EXPECT_EQ(inside.values, (std::vector<double>{3, 4, 5, 6, 7, 8}));
}

Figure frf_like() {
  Figure fig;
  fig.share_x = true;
  Axes& a = fig.panels.emplace_back();
  a.log_x = a.log_y = true;
  a.relative_height = 2.0;
  a.y_label = "|H| [m/N]";
  a.series.push_back({{10, 100, 1000}, {1e-6, 1e-5, 1e-7}, "measured"});
  Axes& b = fig.panels.emplace_back();
  b.log_x = true;
  b.x_label = "frequency [Hz]";
  b.series.push_back({{20, 2000}, {0.5, 1.0}, "coherence"});
  return fig;
}

TEST(PlanFigure, SharedXAxisIsTheUnionOfThePanelsData) {
  const FigurePlan plan = plan_figure(frf_like());
  for (const PanelPlan& p : plan.panels) {
    EXPECT_DOUBLE_EQ(p.x.min, 10.0);
    EXPECT_NEAR(p.x.max, 2000.0, 1e-9);
  }
}

TEST(PlanFigure, YRangesArePaddedFivePercent) {
  const FigurePlan plan = plan_figure(frf_like());
  // Linear [0.5, 1] padded by 0.025 on each side; log [1e-7, 1e-5] by 0.1 decade.
  EXPECT_DOUBLE_EQ(plan.panels[1].y.min, 0.475);
  EXPECT_DOUBLE_EQ(plan.panels[1].y.max, 1.025);
  EXPECT_NEAR(std::log10(plan.panels[0].y.min), -7.1, 1e-12);
  EXPECT_NEAR(std::log10(plan.panels[0].y.max), -4.9, 1e-12);
}

TEST(PlanFigure, PanelsStackWithRelativeHeightsAndAlignedMargins) {
  const FigurePlan plan = plan_figure(frf_like());
  const PanelPlan& top = plan.panels[0];
  const PanelPlan& bottom = plan.panels[1];
  EXPECT_LT(top.top, 1.0);
  EXPECT_GT(top.bottom, bottom.top);  // a gap, no overlap
  EXPECT_GT(bottom.bottom, 0.0);
  EXPECT_NEAR((top.top - top.bottom) / (bottom.top - bottom.bottom), 2.0, 1e-12);
  // Widest y tic label "0.5"/"1" or the log decades "10^-6" (4) + 2 gap + 3 for the label.
  EXPECT_EQ(plan.left_margin_chars, 9);
}

TEST(PlanFigure, NanAndEmptySeriesAreNotData) {
  Figure fig;
  Axes& a = fig.panels.emplace_back();
  a.series.push_back({{1, 2}, {kNaN, kNaN}, "nan"});
  a.series.push_back({{}, {}, "empty"});
  const FigurePlan plan = plan_figure(fig);
  EXPECT_FALSE(plan.panels[0].has_data);
  EXPECT_EQ(plan.panels[0].series[0].drawable, 0u);
  EXPECT_DOUBLE_EQ(plan.panels[0].x.min, 0.0);  // a default window instead of no range
  EXPECT_DOUBLE_EQ(plan.panels[0].x.max, 1.0);
}

TEST(PlanFigure, TooShortFigureIsRefused) {
  Figure fig = frf_like();
  fig.height_in = 1.0;
  EXPECT_THROW(plan_figure(fig), RenderError);
}

TEST(Validate, NamesFieldValueAndRule) {
  const auto message = [](const Figure& f) {
    try {
      validate(f);
    } catch (const RenderError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Figure f = frf_like();
  EXPECT_EQ(message(f), "no error");
  f.panels[1].x_range = Range{0.0, 10.0};
  EXPECT_EQ(message(f), "figure.panels[1].x_range = [0, 10]: must be > 0 on a log axis");
  f = frf_like();
  f.panels[0].series[0].color = "red";
  EXPECT_EQ(message(f), "figure.panels[0].series[0].color = 'red': must be #RRGGBB or empty");
  f = frf_like();
  f.panels[0].relative_height = 0.0;
  EXPECT_EQ(message(f), "figure.panels[0].relative_height = 0: must be > 0");
  EXPECT_EQ(message(Figure{}), "figure.panels is empty: a figure needs at least one panel");
}

// A panel whose data fills the top right: the legend goes to another corner.
TEST(Legend, AutoAvoidsTheCornerWithData) {
  Figure fig;
  Axes& a = fig.panels.emplace_back();
  std::vector<double> x, y;
  for (int i = 0; i <= 100; ++i) {
    x.push_back(i);
    y.push_back(i * i);  // rises into the top right corner
  }
  a.series.push_back({x, y, "parabola"});
  const FigurePlan plan = plan_figure(fig);
  EXPECT_EQ(plan.panels[0].legend, LegendPosition::kTopLeft);
}

TEST(Legend, AutoGoesAboveWhenEveryCornerHidesData) {
  Figure fig;
  Axes& a = fig.panels.emplace_back();
  std::vector<double> x, y;
  for (int i = 0; i <= 4000; ++i) {  // a dense oscillation filling the whole plot
    x.push_back(i);
    y.push_back(i % 2 ? 1.0 : -1.0);
  }
  a.series.push_back({x, y, "signal"});
  a.series.push_back({x, y, "signal again"});
  const FigurePlan plan = plan_figure(fig);
  EXPECT_EQ(plan.panels[0].legend, LegendPosition::kAbove);
  EXPECT_EQ(plan.panels[0].key_columns, 2u);
  EXPECT_EQ(plan.panels[0].key_rows, 1u);
}

TEST(Legend, NoLabelsNoLegend) {
  Figure fig;
  fig.panels.emplace_back().series.push_back({{0, 1}, {0, 1}, ""});
  EXPECT_EQ(plan_figure(fig).panels[0].legend, LegendPosition::kNone);
}

}  // namespace
}  // namespace chatterlab::render
