// The OSMesa density rasterizer: where points land, how counts add up, what is dropped,
// how counts become colour, and that it runs from several threads at once.
#include "render/density_raster.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <thread>

#include "render/render_error.h"

namespace chatterlab::render {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Pixel (column, row) of the only non-empty pixel, or (-1, -1).
std::pair<int, int> only_pixel(const DensityGrid& g) {
  std::pair<int, int> at{-1, -1};
  for (int r = 0; r < g.height; ++r) {
    for (int c = 0; c < g.width; ++c) {
      if (g.at(c, r) == 0) continue;
      if (at.first >= 0) return {-2, -2};
      at = {c, r};
    }
  }
  return at;
}

// Whole points, each counted in the pixel it falls in.
DensityOptions whole_points(bool log_x = false, bool log_y = false) {
  DensityOptions o;
  o.style.antialias = false;
  o.log_x = log_x;
  o.log_y = log_y;
  return o;
}

std::pair<int, int> pixel_of(double x, double y, const Range& xr, const Range& yr, int w, int h,
                             const DensityOptions& o = whole_points()) {
  return only_pixel(count_density(std::vector<double>{x}, std::vector<double>{y}, xr, yr, w, h, o));
}

TEST(CountDensity, PointsLandInTheirPixelsRowZeroAtTheTop) {
  // 1 unit per pixel: x in [0, 10] over 10 columns, y in [0, 5] over 5 rows.
  const Range xr{0, 10}, yr{0, 5};
  EXPECT_EQ(pixel_of(2.5, 3.5, xr, yr, 10, 5), std::make_pair(2, 1));
  EXPECT_EQ(pixel_of(7.2, 0.4, xr, yr, 10, 5), std::make_pair(7, 4));
  // The axis ends: the low ends are the first column and the bottom row, the high ends
  // (closed) the last column and the top row.
  EXPECT_EQ(pixel_of(0.0, 0.0, xr, yr, 10, 5), std::make_pair(0, 4));
  EXPECT_EQ(pixel_of(10.0, 5.0, xr, yr, 10, 5), std::make_pair(9, 0));
  EXPECT_EQ(pixel_of(10.0, 0.0, xr, yr, 10, 5), std::make_pair(9, 4));
  EXPECT_EQ(pixel_of(0.0, 5.0, xr, yr, 10, 5), std::make_pair(0, 0));
}

TEST(CountDensity, PixelCentresOfAFigureSizedGrid) {
  // An angle axis of 1000 columns and a deflection axis of 600 rows (a 5 in x 3 in plot area
  // at 200 dpi): the centre of pixel (c, r) must land in (c, r) for every tested c and r.
  const Range xr{-180, 180}, yr{-40, 40};
  const int w = 1000, h = 600;
  const double dx = 360.0 / w, dy = 80.0 / h;
  for (int c : {0, 1, 250, 499, 500, 998, 999}) {
    for (int r : {0, 1, 299, 300, 599}) {
      const double x = -180 + (c + 0.5) * dx, y = 40 - (r + 0.5) * dy;
      EXPECT_EQ(pixel_of(x, y, xr, yr, w, h), std::make_pair(c, r)) << "x " << x << " y " << y;
      // Antialiased, a point on a pixel's centre is wholly in that pixel too.
      EXPECT_EQ(pixel_of(x, y, xr, yr, w, h, DensityOptions{}), std::make_pair(c, r));
    }
  }
}

TEST(CountDensity, LogAxesPlacePointsByDecade) {
  // x over three decades, 100 columns each; y over 1e-6 .. 1e-3 in 30 rows.
  const DensityOptions o = whole_points(true, true);
  const Range xr{10, 1e4}, yr{1e-6, 1e-3};
  for (int c : {0, 99, 100, 150, 299}) {
    const double x = std::pow(10.0, 1.0 + (c + 0.5) / 100.0);
    EXPECT_EQ(pixel_of(x, 3e-5, xr, yr, 300, 30, o).first, c) << x;
  }
  // Decades are equal: 1e-5 .. 1e-4 are rows 19 .. 10 from the top (10 rows per decade).
  EXPECT_EQ(pixel_of(20, 1.5e-5, xr, yr, 300, 30, o).second, 18);
  EXPECT_EQ(pixel_of(20, 9e-5, xr, yr, 300, 30, o).second, 10);
  // The ends.
  EXPECT_EQ(pixel_of(10, 1e-6, xr, yr, 300, 30, o), std::make_pair(0, 29));
  EXPECT_EQ(pixel_of(1e4, 1e-3, xr, yr, 300, 30, o), std::make_pair(299, 0));
}

TEST(CountDensity, CountsAddUpOnOnePixel) {
  const std::vector<double> x(1000, 3.3), y(1000, 1.2);
  const DensityGrid g = count_density(x, y, {0, 10}, {0, 5}, 10, 5, whole_points());
  EXPECT_EQ(g.at(3, 3), 1000.0f);
  EXPECT_EQ(g.max_count(), 1000.0f);
  EXPECT_EQ(g.total(), 1000.0);
  // Antialiased, on the pixel's centre (3.5, 1.5): the same.
  const std::vector<double> xc(1000, 3.5), yc(1000, 1.5);
  EXPECT_EQ(count_density(xc, yc, {0, 10}, {0, 5}, 10, 5).at(3, 3), 1000.0f);
}

// Antialias: a point's weight is shared by the 4 pixels whose centres surround it, in
// proportion to its distance from them (bilinear), so a grid of samples finer than the
// pixels fills the columns evenly. Weights are in 1/16 pixel steps: exact here.
TEST(CountDensity, AntialiasSharesAPointBilinearly) {
  const Range xr{0, 10}, yr{0, 5};
  const auto grid = [&](double x, double y) {
    return count_density(std::vector<double>{x}, std::vector<double>{y}, xr, yr, 10, 5);
  };
  // On the corner of pixels (2, 1), (3, 1), (2, 2), (3, 2): a quarter each.
  const DensityGrid corner = grid(3.0, 3.0);
  EXPECT_EQ(corner.at(2, 1), 0.25f);
  EXPECT_EQ(corner.at(3, 1), 0.25f);
  EXPECT_EQ(corner.at(2, 2), 0.25f);
  EXPECT_EQ(corner.at(3, 2), 0.25f);
  // A quarter pixel right of column 6's centre, on row 2's centre: 3/4 and 1/4.
  const DensityGrid quarter = grid(6.75, 2.5);
  EXPECT_EQ(quarter.at(6, 2), 0.75f);
  EXPECT_EQ(quarter.at(7, 2), 0.25f);
  EXPECT_EQ(quarter.total(), 1.0);
  // At the axis ends the share beyond the edge stays in the edge pixel.
  EXPECT_EQ(grid(10.0, 5.0).at(9, 0), 1.0f);
  EXPECT_EQ(grid(0.0, 0.0).at(0, 4), 1.0f);
  // A regular grid of 148 samples over 100 columns (like 1600 sample angles over 1084
  // pixels): whole points stripe the columns 1, 2, 1, 2 (+-33 %). Antialiased every column
  // holds 1.48 within 15.5 %: the tent filter passes 2 sinc^2(1.48) = 9.2 % of the comb's
  // 1.48 / px ripple, and the 1/16-step weights err by <= 1/32 for each of the <= 3 samples
  // touching a column (6.3 %).
  std::vector<double> xs, ys;
  for (int k = 0; k < 148; ++k) {
    xs.push_back((k + 0.5) * 100.0 / 148);
    ys.push_back(0.5);
  }
  const DensityGrid whole = count_density(xs, ys, {0, 100}, {0, 1}, 100, 1, whole_points());
  const DensityGrid smooth = count_density(xs, ys, {0, 100}, {0, 1}, 100, 1);
  EXPECT_EQ(*std::min_element(whole.counts.begin(), whole.counts.end()), 1.0f);
  EXPECT_EQ(*std::max_element(whole.counts.begin(), whole.counts.end()), 2.0f);
  for (int c = 1; c < 99; ++c) EXPECT_NEAR(smooth.at(c, 0), 1.48, 0.155 * 1.48) << c;
}

TEST(CountDensity, PointsOutsideTheRangeAndInvalidOnesAreDropped) {
  const std::vector<double> x{5, -0.01, 10.01, 5, 5, kNaN, 5, kInf, -kInf, 1e300, 5};
  const std::vector<double> y{2, 2, 2, -0.01, 5.01, 2, kNaN, 2, 2, 2, 2};
  const DensityGrid g = count_density(x, y, {0, 10}, {0, 5}, 10, 5, whole_points());
  EXPECT_EQ(g.total(), 2.0);
  EXPECT_EQ(g.at(5, 2), 2.0f);
  // On a log axis, x <= 0 cannot be drawn.
  const DensityGrid lg =
      count_density(std::vector<double>{-1, 0, 1e-300, 5}, std::vector<double>{2, 2, 2, 2}, {1, 10},
                    {0, 5}, 10, 5, whole_points(true, false));
  EXPECT_EQ(lg.total(), 1.0);
}

TEST(CountDensity, ManyPointsAcrossChunksAllCounted) {
  // 2.5 million points: three dispatches of up to 2^20. A fixed seed (CONVENTIONS.md).
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.1f, 1.1f);
  std::vector<float> x(2'500'000), y(x.size());
  std::size_t inside = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = u(rng);
    y[i] = u(rng);
    inside += x[i] >= 0.0f && x[i] <= 1.0f && y[i] >= 0.0f && y[i] <= 1.0f;
  }
  const DensityGrid g = count_density(x, y, {0, 1}, {0, 1}, 64, 48, whole_points());
  EXPECT_EQ(g.total(), static_cast<double>(inside));
  // Antialiased the weights (in 1/256) still add up to one per point.
  EXPECT_EQ(count_density(x, y, {0, 1}, {0, 1}, 64, 48).total(), static_cast<double>(inside));
  // Uniform points: each of the 3072 pixels holds inside / 3072 ~ 565 on average; Poisson
  // spread sqrt(565) ~ 24, so every pixel lies within 6 sigma (150) of the mean.
  const double mean = static_cast<double>(inside) / (64 * 48);
  for (const float c : g.counts) EXPECT_NEAR(c, mean, 150.0);
}

TEST(CountDensity, FloatAndDoublePointsGiveTheSameGrid) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<double> x(20000), y(20000);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = n(rng);
    y[i] = 0.5 * x[i] + 0.2 * n(rng);
  }
  // Pixel edges fall on binary fractions, where float rounding cannot move a point across.
  const std::vector<float> xf(x.begin(), x.end()), yf(y.begin(), y.end());
  EXPECT_EQ(count_density(x, y, {-4, 4}, {-2, 2}, 64, 32).counts,
            count_density(xf, yf, {-4, 4}, {-2, 2}, 64, 32).counts);
}

TEST(CountDensity, EmptyInputGivesAnEmptyGridAndATransparentImage) {
  const DensityGrid g =
      count_density(std::vector<double>{}, std::vector<double>{}, {0, 1}, {0, 1}, 40, 30);
  EXPECT_EQ(g.width, 40);
  EXPECT_EQ(g.height, 30);
  EXPECT_EQ(g.total(), 0.0);
  const RgbaImage img =
      rasterize_density(std::vector<double>{}, std::vector<double>{}, {0, 1}, {0, 1}, 40, 30);
  ASSERT_EQ(img.rgba.size(), 40u * 30u * 4u);
  for (const std::uint8_t b : img.rgba) ASSERT_EQ(b, 0);
}

TEST(CountDensity, TwoThreadsAtOnceGiveTheSingleThreadResult) {
  // Two clouds with different shapes; each thread rasterizes its own 40 times with its own
  // OSMesa context, while the other does the same.
  std::vector<double> xa(200000), ya(200000), xb(150000), yb(150000);
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  for (std::size_t i = 0; i < xa.size(); ++i) {
    xa[i] = n(rng);
    ya[i] = n(rng);
  }
  for (std::size_t i = 0; i < xb.size(); ++i) {
    xb[i] = std::cos(0.001 * static_cast<double>(i)) + 0.05 * n(rng);
    yb[i] = std::sin(0.001 * static_cast<double>(i)) + 0.05 * n(rng);
  }
  const auto a = [&] { return count_density(xa, ya, {-3, 3}, {-3, 3}, 300, 200); };
  const auto b = [&] { return count_density(xb, yb, {-1.5, 1.5}, {-1.5, 1.5}, 256, 256); };
  const DensityGrid ref_a = a(), ref_b = b();
  ASSERT_GT(ref_a.total(), 190000.0);
  bool same_a = true, same_b = true;
  std::thread ta([&] {
    for (int i = 0; i < 40; ++i) same_a = same_a && a().counts == ref_a.counts;
  });
  std::thread tb([&] {
    for (int i = 0; i < 40; ++i) same_b = same_b && b().counts == ref_b.counts;
  });
  ta.join();
  tb.join();
  EXPECT_TRUE(same_a);
  EXPECT_TRUE(same_b);
}

TEST(CountDensity, BadArgumentsNameTheirRule) {
  const std::vector<double> two{1, 2}, one{1};
  const auto message = [](auto&& call) {
    try {
      call();
    } catch (const RenderError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message([&] {
              count_density(two, one, {0, 1}, {0, 1}, 10, 10);
            }),
            "count_density: x has 2 values, y has 1: must be equal");
  EXPECT_EQ(message([&] {
              count_density(two, two, {0, 1}, {0, 1}, 0, 10);
            }),
            "count_density: width_px = 0: must be in [1, 16384]");
  EXPECT_EQ(message([&] {
              count_density(two, two, {0, 1}, {1, 1}, 10, 10);
            }),
            "count_density: y_range = [1, 1]: must be finite with max > min");
  DensityOptions log;
  log.log_x = true;
  EXPECT_EQ(message([&] {
              count_density(two, two, {0, 1}, {0, 1}, 10, 10, log);
            }),
            "count_density: x_range = [0, 1]: must be > 0 on a log axis");
  EXPECT_EQ(message([&] { shade_density(DensityGrid{}, "blue"); }),
            "shade_density: colour = 'blue': must be #RRGGBB");
}

// Counts become opacity of one colour (density_raster.h): n = 1 at min_alpha, the largest
// count at max_alpha, log(n) / log(full) between. Alphas are compared after the same
// rounding to 1/255, exactly.
TEST(ShadeDensity, LogScaleFromMinToMaxAlpha) {
  DensityGrid g;
  g.width = 5;
  g.height = 1;
  g.counts = {0, 1, 100, 10000, 0.5};
  DensityStyle log;
  log.scale = DensityScale::kLog;
  const RgbaImage img = shade_density(g, "#D55E00", log);
  const auto alpha = [](double a) { return static_cast<int>(std::lround(255 * a)); };
  EXPECT_EQ(img.at(0, 0)[3], 0);
  EXPECT_EQ(img.at(1, 0)[3], alpha(0.2));              // DensityStyle::min_alpha
  EXPECT_EQ(img.at(2, 0)[3], alpha(0.2 + 0.8 * 0.5));  // ln 100 / ln 10^4 = 1/2
  EXPECT_EQ(img.at(3, 0)[3], 255);                     // max_alpha 1
  EXPECT_EQ(img.at(4, 0)[3], alpha(0.5 * 0.2));        // half a point: half of min_alpha
  EXPECT_EQ(img.at(2, 0)[0], 0xD5);
  EXPECT_EQ(img.at(2, 0)[1], 0x5E);
  EXPECT_EQ(img.at(2, 0)[2], 0x00);
  EXPECT_EQ(img.at(0, 0)[0], 0);  // empty pixels are transparent black
}

TEST(ShadeDensity, SqrtAndLinearScalesAndAFixedFullCount) {
  DensityGrid g;
  g.width = 3;
  g.height = 1;
  g.counts = {1, 25, 81};
  DensityStyle s;
  s.min_alpha = 0.1;
  s.max_alpha = 0.9;
  s.scale = DensityScale::kSqrt;
  const auto alpha = [](double a) { return static_cast<int>(std::lround(255 * a)); };
  EXPECT_EQ(shade_density(g, "#000000", s).at(1, 0)[3], alpha(0.1 + 0.8 * 4.0 / 8.0));
  s.scale = DensityScale::kLinear;
  EXPECT_EQ(shade_density(g, "#000000", s).at(1, 0)[3], alpha(0.1 + 0.8 * 24.0 / 80.0));
  // full_count 25: 25 and above are at max_alpha, so figures can share one scale.
  s.full_count = 25;
  const RgbaImage fixed = shade_density(g, "#000000", s);
  EXPECT_EQ(fixed.at(1, 0)[3], alpha(0.9));
  EXPECT_EQ(fixed.at(2, 0)[3], alpha(0.9));
  EXPECT_EQ(fixed.at(0, 0)[3], alpha(0.1));
}

TEST(ShadeDensity, EqualizedSpreadsOpacityByRank) {
  // Counts 1, 2, 3, 1000: ranks 0, 1, 2, 3 of 4 non-empty pixels give t = 0, 1/3, 2/3, 1
  // whatever the counts' sizes.
  DensityGrid g;
  g.width = 5;
  g.height = 1;
  g.counts = {1, 2, 3, 1000, 0};
  DensityStyle s;
  s.scale = DensityScale::kEqualized;
  const RgbaImage img = shade_density(g, "#009E73", s);
  const auto alpha = [](double a) { return static_cast<int>(std::lround(255 * a)); };
  EXPECT_EQ(img.at(0, 0)[3], alpha(0.2));
  EXPECT_EQ(img.at(1, 0)[3], alpha(0.2 + 0.8 / 3));
  EXPECT_EQ(img.at(2, 0)[3], alpha(0.2 + 0.8 * 2 / 3));
  EXPECT_EQ(img.at(3, 0)[3], 255);
  EXPECT_EQ(img.at(4, 0)[3], 0);
}

TEST(DensityRenderer, RunsOnMesaLlvmpipe) {
  EXPECT_NE(density_renderer().find("llvmpipe"), std::string::npos) << density_renderer();
}

// Without a GL 4.3 driver (softpipe offers 3.3), the rasterizer says what is missing. In a
// fresh process: Mesa reads GALLIUM_DRIVER once, when it creates its screen.
TEST(DensityRendererDeathTest, MissingOpenGl43IsARenderError) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        ::setenv("GALLIUM_DRIVER", "softpipe", 1);
        try {
          count_density(std::vector<double>{1}, std::vector<double>{1}, {0, 2}, {0, 2}, 4, 4);
        } catch (const RenderError& e) {
          std::fprintf(stderr, "%s\n", e.what());
          std::exit(3);
        }
        std::exit(0);
      },
      ::testing::ExitedWithCode(3), "OSMesa cannot create an OpenGL 4.3 core context");
}

}  // namespace
}  // namespace chatterlab::render
