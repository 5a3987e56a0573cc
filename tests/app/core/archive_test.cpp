// The bytes of the per-test cache (app/core/archive.h): every member type a kind's result holds
// comes back equal, bit for bit (NaN included); bytes cut short or too long are refused.
#include "app/core/archive.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "tests/support/expect_input_error.h"

namespace chatterlab::app {
namespace {

enum class Colour { kRed, kGreen };

struct Inner {
  double a = 0;
  std::string name;
};
template <class Ar>
void fields(Ar& ar, Inner& s) {
  ar(s.a, s.name);
}

struct Everything {
  int i = 0;
  bool flag = false;
  Colour colour = Colour::kRed;
  double nan = 0;
  std::string text;
  std::vector<double> numbers;
  std::vector<bool> bits;
  std::vector<Inner> inners;
  std::optional<Inner> maybe, none;
  std::pair<double, std::string> pair;
  std::array<Inner, 2> two;
  std::map<std::string, double> map;
  std::shared_ptr<const Inner> shared, null_shared;
  Eigen::VectorXd vec;
  Eigen::VectorXcd cvec;
  Eigen::MatrixX2d mx2;
  Eigen::Matrix3d m3;
  StepSummary summary;
};
template <class Ar>
void fields(Ar& ar, Everything& s) {
  ar(s.i, s.flag, s.colour, s.nan, s.text, s.numbers, s.bits, s.inners, s.maybe, s.none, s.pair,
     s.two, s.map, s.shared, s.null_shared, s.vec, s.cvec, s.mx2, s.m3, s.summary);
}

Everything sample() {
  Everything e;
  e.i = -7;
  e.flag = true;
  e.colour = Colour::kGreen;
  e.nan = std::numeric_limits<double>::quiet_NaN();
  e.text = std::string("with a \0 byte", 13);
  e.numbers = {1.5, -2.25, 1e300};
  e.bits = {true, false, true};
  e.inners = {{1, "a"}, {2, "bb"}};
  e.maybe = Inner{3, "c"};
  e.pair = {4.5, "d"};
  e.two = {Inner{5, "e"}, Inner{6, "f"}};
  e.map = {{"k1", 1.0}, {"k2", 2.0}};
  e.shared = std::make_shared<const Inner>(Inner{7, "g"});
  e.vec = Eigen::VectorXd::LinSpaced(5, 0, 1);
  e.cvec = Eigen::VectorXcd::Constant(3, std::complex<double>(1, -2));
  e.mx2 = Eigen::MatrixX2d::Random(4, 2);
  e.m3 = Eigen::Matrix3d::Identity() * 2;
  e.summary.fail("why", "more");
  e.summary.warnings = {"w"};
  return e;
}

TEST(Archive, EveryMemberTypeComesBackEqual) {
  const Everything e = sample();
  const std::string bytes = to_bytes(e);
  Everything r;
  from_bytes(bytes, r);
  EXPECT_EQ(r.i, -7);
  EXPECT_TRUE(r.flag);
  EXPECT_EQ(r.colour, Colour::kGreen);
  EXPECT_TRUE(std::isnan(r.nan));
  EXPECT_EQ(r.text, e.text);
  EXPECT_EQ(r.numbers, e.numbers);
  EXPECT_EQ(r.bits, e.bits);
  ASSERT_EQ(r.inners.size(), 2u);
  EXPECT_EQ(r.inners[1].name, "bb");
  ASSERT_TRUE(r.maybe.has_value());
  EXPECT_EQ(r.maybe->a, 3);
  EXPECT_FALSE(r.none.has_value());
  EXPECT_EQ(r.pair, e.pair);
  EXPECT_EQ(r.two[1].name, "f");
  EXPECT_EQ(r.map, e.map);
  ASSERT_NE(r.shared, nullptr);
  EXPECT_EQ(r.shared->name, "g");
  EXPECT_EQ(r.null_shared, nullptr);
  EXPECT_EQ(r.vec, e.vec);
  EXPECT_EQ(r.cvec, e.cvec);
  EXPECT_EQ(r.mx2, e.mx2);
  EXPECT_EQ(r.m3, e.m3);
  EXPECT_EQ(r.summary.status, StepStatus::kFailed);
  EXPECT_EQ(r.summary.message, "why");
  EXPECT_EQ(r.summary.details, "more");
  EXPECT_EQ(r.summary.warnings, std::vector<std::string>{"w"});
  // Written again, the same bytes.
  EXPECT_EQ(to_bytes(r), bytes);
}

TEST(Archive, DamagedBytesAreRefused) {
  const std::string bytes = to_bytes(sample());
  Everything r;
  chatterlab::testing::expect_input_error([&] { from_bytes(bytes.substr(0, 6), r); },
                                          "a cached result ends early (damaged cache)");
  chatterlab::testing::expect_input_error(
      [&] { from_bytes(bytes + "x", r); },
      "a cached result is longer than its value (damaged cache)");
  // A length beyond the bytes left never allocates it.
  std::vector<double> v;
  std::string huge(8, '\xff');
  chatterlab::testing::expect_input_error(
      [&] { from_bytes(huge, v); }, "a cached result holds an impossible length (damaged cache)");
}

}  // namespace
}  // namespace chatterlab::app
