#include "render/decimate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace chatterlab::render {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(ReduceLine, KeepsEnvelopeAndOrder) {
  // 100000 samples of a sine with one spike: the spike and both extremes must survive.
  const std::size_t n = 100000, bins = 500;
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = static_cast<double>(i);
    y[i] = std::sin(static_cast<double>(i) * 1e-3);
  }
  y[31337] = 5.0;
  const XY r = reduce_line(x, y, bins);
  EXPECT_LE(r.x.size(), 4 * bins);
  EXPECT_GE(r.x.size(), 2 * bins);  // every bin keeps at least its first and last sample
  EXPECT_EQ(*std::max_element(r.y.begin(), r.y.end()), 5.0);
  EXPECT_EQ(*std::min_element(r.y.begin(), r.y.end()), *std::min_element(y.begin(), y.end()));
  EXPECT_TRUE(std::is_sorted(r.x.begin(), r.x.end()));
  EXPECT_EQ(r.x.front(), 0.0);
  EXPECT_EQ(r.x.back(), static_cast<double>(n - 1));
  // Each kept sample is an original one.
  for (std::size_t i = 0; i < r.x.size(); ++i) {
    EXPECT_EQ(r.y[i], y[static_cast<std::size_t>(r.x[i])]);
  }
}

TEST(ReduceLine, GapsStayGaps) {
  std::vector<double> x(10000), y(10000);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = static_cast<double>(i);
    y[i] = (i >= 4000 && i < 4500) ? kNaN : 1.0;
  }
  const XY r = reduce_line(x, y, 100);
  const auto nans = std::count_if(r.y.begin(), r.y.end(), [](double v) { return std::isnan(v); });
  EXPECT_EQ(nans, 1) << "one NaN between the two runs";
  EXPECT_FALSE(std::isnan(r.y.front()));
  EXPECT_FALSE(std::isnan(r.y.back()));
}

TEST(ReduceLine, LogAxisDropsNonPositiveAsGaps) {
  std::vector<double> x(1000), y(1000);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = 1.0 + static_cast<double>(i);
    y[i] = i == 500 ? -1.0 : 2.0;
  }
  const XY r = reduce_line(x, y, 50, true, true);
  EXPECT_EQ(std::count_if(r.y.begin(), r.y.end(), [](double v) { return std::isnan(v); }), 1);
  EXPECT_EQ(std::count(r.y.begin(), r.y.end(), -1.0), 0);
}

TEST(ReduceLine, UnsortedInputIsReturnedUnchanged) {
  const std::vector<double> x{0, 2, 1, 3}, y{1, 2, 3, 4};
  const XY r = reduce_line(x, y, 1);
  EXPECT_EQ(r.x, x);
  EXPECT_EQ(r.y, y);
}

TEST(ReducePoints, KeepsOnePointPerCellAndDropsInvalid) {
  // 1000 copies of 3 distinct points plus invalid ones, on a 10 x 10 grid.
  std::vector<double> x, y;
  for (int k = 0; k < 1000; ++k) {
    x.insert(x.end(), {0.0, 5.0, 10.0, kNaN, 1.0});
    y.insert(y.end(), {0.0, 5.0, 10.0, 1.0, std::numeric_limits<double>::infinity()});
  }
  const XY r = reduce_points(x, y, 10);
  EXPECT_EQ(r.x, (std::vector<double>{0.0, 5.0, 10.0}));
  EXPECT_EQ(r.y, (std::vector<double>{0.0, 5.0, 10.0}));
}

}  // namespace
}  // namespace chatterlab::render
