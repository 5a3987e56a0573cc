#include "app/core/signals.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "analysis/common/summary.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::TempDir;

DataSpec spec(const std::filesystem::path& f, std::vector<std::string> ch = {}) {
  DataSpec d;
  d.file = f;
  d.relative_file = f.filename().string();
  d.channels = std::move(ch);
  return d;
}

std::string message_of(const DataSpec& d) {
  try {
    SignalTable::open(d, "t/" + d.relative_file);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

template <typename T>
std::string raw_bytes(const std::vector<T>& v) {
  std::string s(v.size() * sizeof(T), '\0');
  std::memcpy(s.data(), v.data(), s.size());
  return s;
}

TEST(Signals, CsvWithCalibrationAndIgnoredTimeColumn) {
  TempDir d;
  const auto f = d.write("a.csv", "t,force,response\n0,1.5,-2\n0.001,2.5,3e-3\n");
  const SignalTable t = SignalTable::open(spec(f), "a.csv");
  ASSERT_EQ(t.samples(), 2u);
  const Eigen::VectorXd force = t.channel("force", ChannelSpec{2.0, 1.0, {}});
  EXPECT_DOUBLE_EQ(force[0], 4.0);  // 2 * 1.5 + 1
  EXPECT_DOUBLE_EQ(force[1], 6.0);
  EXPECT_DOUBLE_EQ(t.channel("response")[1], 3e-3);
}

TEST(Signals, RawF32InterleavedAndF64) {
  TempDir d;
  const auto f32 = d.write("s.f32", raw_bytes<float>({1, 10, 100, 2, 20, 200}));
  const SignalTable t = SignalTable::open(spec(f32, {"x", "y", "tach"}), "s.f32");
  ASSERT_EQ(t.samples(), 2u);
  EXPECT_DOUBLE_EQ(t.channel("y")[1], 20.0);
  EXPECT_DOUBLE_EQ(t.channel("tach", ChannelSpec{0.5, 0.0, {}})[0], 50.0);
  const auto f64 = d.write("s.f64", raw_bytes<double>({0.25, -0.5}));
  EXPECT_DOUBLE_EQ(SignalTable::open(spec(f64, {"x"}), "s.f64").channel("x")[1], -0.5);
}

TEST(Signals, RawSizeNotMultipleOfChannels) {
  TempDir d;
  const auto f = d.write("s.f32", raw_bytes<float>({1, 2, 3, 4, 5}));
  EXPECT_EQ(message_of(spec(f, {"x", "y", "tach"})),
            "t/s.f32: size 20 bytes is not a multiple of 3 channels x 4 bytes (truncated file or "
            "wrong data.channels)");
}

TEST(Signals, RaggedCsvRow) {
  TempDir d;
  const auto f = d.write("h.csv", "force,response\n1,2\n3\n");
  EXPECT_EQ(message_of(spec(f)), "t/h.csv: line 3 has 1 cells, the header has 2 (ragged row)");
}

TEST(Signals, NonNumericCsvCell) {
  TempDir d;
  const auto f = d.write("h.csv", "force,response\n1,2\n3,abc\n");
  EXPECT_EQ(message_of(spec(f)), "t/h.csv: line 3, column 'response': 'abc' is not a number");
}

TEST(Signals, NanAndInfiniteSamples) {
  TempDir d;
  const auto f = d.write("h.csv", "force,response\n1,2\nnan,2\n");
  EXPECT_EQ(message_of(spec(f)), "t/h.csv: NaN value at line 3, column 'force'");
  const auto r = d.write("s.f32", raw_bytes<float>({1, 2, INFINITY, 4}));
  EXPECT_EQ(message_of(spec(r, {"x", "y"})), "t/s.f32: infinite value at channel 'x', sample 1");
}

TEST(Signals, MissingFileAndMissingChannel) {
  TempDir d;
  EXPECT_EQ(message_of(spec(d.path() / "none.csv")), "t/none.csv: file not found");
  const auto f = d.write("h.csv", "force,response\n1,2\n");
  const SignalTable t = SignalTable::open(spec(f), "h.csv");
  try {
    t.channel("tach");
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "h.csv: no channel named 'tach' (channels: force, response)");
  }
}

TEST(Signals, HeaderOnlyHasNoSamples) {
  TempDir d;
  const auto f = d.write("h.csv", "force,response\n");
  EXPECT_EQ(message_of(spec(f)), "t/h.csv: no samples");
}

TEST(Signals, WriteReadRoundTrip) {
  TempDir d;
  Eigen::VectorXd a(3), b(3);
  a << 1.0 / 3.0, -2e-9, 7.0;
  b << 0.1, 0.2, 0.3;
  for (const char* name : {"w.csv", "w.f64"}) {
    const auto f = d.path() / name;
    write_signals(f, {"a", "b"}, {&a, &b});
    const SignalTable t = SignalTable::open(spec(f, {"a", "b"}), name);
    // to_chars writes the shortest representation that round-trips exactly.
    EXPECT_EQ(t.channel("a"), a) << name;
    EXPECT_EQ(t.channel("b"), b) << name;
  }
}

}  // namespace
}  // namespace chatterlab::app
