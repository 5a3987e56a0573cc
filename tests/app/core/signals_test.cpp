#include "app/core/signals.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <utility>

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
  const Eigen::VectorXd force = t.channel("force", ChannelSpec{2.0, 1.0, {}, {}, {}, {}});
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
  EXPECT_DOUBLE_EQ(t.channel("tach", ChannelSpec{0.5, 0.0, {}, {}, {}, {}})[0], 50.0);
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

// ---- CSV dialects (EXPERIMENT_FORMAT.md section 1: delimiter, decimal, skip_lines, column) ----

DataSpec dialect(const std::filesystem::path& f, char delimiter, char decimal, int skip) {
  DataSpec d = spec(f);
  d.delimiter = delimiter;
  d.decimal = decimal;
  d.skip_lines = skip;
  return d;
}

ChannelSpec column(const std::string& header) {
  ChannelSpec c;
  c.column = ColumnRef{header, -1};
  return c;
}

ChannelSpec column(int index) {
  ChannelSpec c;
  c.column = ColumnRef{"", index};
  return c;
}

TEST(SignalsDialect, StatedDelimiters) {
  TempDir d;
  const auto semi = d.write("s.csv", "force;response\n1.5;-2\n2.5;3e-3\n");
  const auto tab = d.write("t.tsv", "force\tresponse\n1.5\t-2\n2.5\t3e-3\n");
  const auto comma = d.write("c.txt", "force,response\n1.5,-2\n2.5,3e-3\n");
  for (const auto& [f, delim] :
       {std::pair{semi, ';'}, std::pair{tab, '\t'}, std::pair{comma, ','}}) {
    const SignalTable t = SignalTable::open(dialect(f, delim, '.', 0), f.filename().string());
    ASSERT_EQ(t.samples(), 2u) << f;
    EXPECT_EQ(t.delimiter(), delim);
    EXPECT_DOUBLE_EQ(t.channel("force")[1], 2.5) << f;
    EXPECT_DOUBLE_EQ(t.channel("response")[1], 3e-3) << f;
  }
}

TEST(SignalsDialect, DelimiterDetectedFromHeaderAndRows) {
  TempDir d;
  const std::pair<const char*, char> cases[] = {
      {"force,response\n1.5,-2\n", ','},
      {"force;response\n1.5;-2\n", ';'},
      {"force\tresponse\n1.5\t-2\n", '\t'},
      {"force, N;response, m/s2\n1.5;-2\n", ';'},  // commas inside names: ';' splits every row
      {"force\n1.5\n", ','},                       // one column: the default
  };
  for (const auto& [text, delim] : cases) {
    const auto f = d.write("a.csv", text);
    const SignalTable t = SignalTable::open(spec(f), "a.csv");
    EXPECT_EQ(t.delimiter(), delim) << text;
    EXPECT_DOUBLE_EQ(t.channel(t.names()[0])[0], 1.5) << text;
  }
  // With a decimal comma the comma never splits: ';' is detected, and also the default.
  const auto f = d.write("b.csv", "force;response\n1,5;-2\n");
  EXPECT_EQ(SignalTable::open(dialect(f, 0, ',', 0), "b.csv").delimiter(), ';');
}

TEST(SignalsDialect, DecimalComma) {
  TempDir d;
  const auto f = d.write("h.txt", "force;response\n1,5;-2\n+2,5e-3;-0,125\n3;4\n");
  const SignalTable t = SignalTable::open(dialect(f, ';', ',', 0), "h.txt");
  ASSERT_EQ(t.samples(), 3u);
  EXPECT_DOUBLE_EQ(t.channel("force")[0], 1.5);
  EXPECT_DOUBLE_EQ(t.channel("force")[1], 2.5e-3);
  EXPECT_DOUBLE_EQ(t.channel("response")[1], -0.125);
  EXPECT_DOUBLE_EQ(t.channel("force")[2], 3.0);
  // A point in a decimal-comma file (a thousands separator) is not read.
  const auto g = d.write("g.txt", "force;response\n1.234,5;2\n");
  EXPECT_EQ(message_of(dialect(g, ';', ',', 0)),
            "t/g.txt: line 2, column 'force': '1.234,5' is not a number");
  // A decimal comma cannot go with a comma delimiter.
  EXPECT_EQ(message_of(dialect(g, ',', ',', 0)),
            "t/g.txt: data.decimal \",\" needs data.delimiter \";\" or tab");
}

TEST(SignalsDialect, SkipLinesBeforeTheHeaderAndLineNumbersOfTheFile) {
  TempDir d;
  const auto f = d.write("h.lvm",
                         "LabVIEW Measurement\t\nOperator\tlab\n***End_of_Header***\t\n"
                         "X_Value\tforce\tresponse\r\n0\t1.5\t2\r\n1e-3\t2.5\t3\r\n");
  const SignalTable t = SignalTable::open(dialect(f, 0, '.', 3), "h.lvm");
  ASSERT_EQ(t.samples(), 2u);
  EXPECT_EQ(t.delimiter(), '\t');
  EXPECT_EQ(t.names(), (std::vector<std::string>{"X_Value", "force", "response"}));
  EXPECT_DOUBLE_EQ(t.channel("response")[1], 3.0);
  // Messages give the line of the file, header block included.
  const auto g = d.write("g.lvm", "a\tb\nX_Value\tforce\n0\t1\n1\tx\n");
  EXPECT_EQ(message_of(dialect(g, '\t', '.', 1)),
            "t/g.lvm: line 4, column 'force': 'x' is not a number");
  EXPECT_EQ(message_of(dialect(g, '\t', '.', 9)),
            "t/g.lvm: data.skip_lines is 9 but the file has only 4 lines");
}

TEST(SignalsDialect, ByteOrderMarkAndQuotedHeader) {
  TempDir d;
  const auto f = d.write("h.csv", "\xEF\xBB\xBF\"Force (N)\",\"Acceleration (m/s^2)\"\n1,2\n");
  const SignalTable t = SignalTable::open(spec(f), "h.csv");
  EXPECT_EQ(t.names(), (std::vector<std::string>{"Force (N)", "Acceleration (m/s^2)"}));
}

TEST(SignalsDialect, ColumnByHeaderTextAndByIndex) {
  TempDir d;
  const auto f = d.write("h.csv", "t,Force (N),Accel\n0,1.5,-2\n0.001,2.5,3\n");
  const SignalTable t = SignalTable::open(spec(f), "h.csv");
  EXPECT_DOUBLE_EQ(t.channel("force", column("Force (N)"))[1], 2.5);
  EXPECT_DOUBLE_EQ(t.channel("response", column(2))[0], -2.0);
  EXPECT_DOUBLE_EQ(t.channel("time", column(0))[1], 0.001);  // the time column counts
  ChannelSpec scaled = column(2);
  scaled.scale = 9.81;
  EXPECT_DOUBLE_EQ(t.channel("response", scaled)[1], 3 * 9.81);
  EXPECT_EQ(t.column_of("force", column("Force (N)")), 1u);
  // A raw file: the column names an entry of data.channels, or its index.
  const auto r = d.write("s.f64", raw_bytes<double>({1, 10, 2, 20}));
  const SignalTable raw = SignalTable::open(spec(r, {"a", "b"}), "s.f64");
  EXPECT_DOUBLE_EQ(raw.channel("force", column("b"))[1], 20.0);
  EXPECT_DOUBLE_EQ(raw.channel("force", column(0))[1], 2.0);
}

TEST(SignalsDialect, BadColumnNamesFileAndKey) {
  TempDir d;
  const auto f = d.write("h.csv", "t,Force (N),Accel\n0,1.5,-2\n");
  const SignalTable t = SignalTable::open(spec(f), "x/h.csv");
  const auto message = [&](const ChannelSpec& c) {
    try {
      t.channel("force", c);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(column("Force(N)")),
            "x/h.csv: channels.force.column 'Force(N)' is not a column of the header (columns: "
            "'t', 'Force (N)', 'Accel') (did you mean 'Force (N)'?)");
  EXPECT_EQ(message(column("Hammer")),
            "x/h.csv: channels.force.column 'Hammer' is not a column of the header (columns: "
            "'t', 'Force (N)', 'Accel')");
  EXPECT_EQ(message(column(3)),
            "x/h.csv: channels.force.column is 3, out of range: the file has 3 columns, 0 to 2 "
            "(t, Force (N), Accel)");
}

TEST(SignalsDialect, MissingChannelsSuggestAColumn) {
  TempDir d;
  const auto f = d.write("h.csv", "t,Force (N),Acceleration [m/s^2]\n0,1.5,-2\n");
  const SignalTable t = SignalTable::open(spec(f), "x/h.csv");
  std::map<std::string, ChannelSpec> channels;
  auto problems = missing_channels(t, {"force", "response"}, channels, "a tap test");
  ASSERT_EQ(problems.size(), 2u);
  // A header whose name without its unit is the channel's: proposed, never taken silently.
  EXPECT_EQ(problems[0],
            "x/h.csv: channel 'force' is required for a tap test (channels: t, Force (N), "
            "Acceleration [m/s^2]); the column 'Force (N)' looks like it: set "
            "channels.force.column: \"Force (N)\" (units in headers are not read: add a scale "
            "when the unit is not the one the test needs)");
  EXPECT_EQ(problems[1],
            "x/h.csv: channel 'response' is required for a tap test (channels: t, Force (N), "
            "Acceleration [m/s^2]); set channels.response.column to the header text of its "
            "column ('Force (N)', 'Acceleration [m/s^2]') or its 0-based index");
  // Once force is mapped, its column is no longer proposed for response.
  channels["force"] = column("Force (N)");
  problems = missing_channels(t, {"force", "response"}, channels, "a tap test");
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("('Acceleration [m/s^2]') or its 0-based index"), std::string::npos)
      << problems[0];
  channels["response"] = column(2);
  EXPECT_TRUE(missing_channels(t, {"force", "response"}, channels, "a tap test").empty());
  // A bad mapping is reported with its key.
  channels["response"] = column(7);
  problems = missing_channels(t, {"force", "response"}, channels, "a tap test");
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].rfind("x/h.csv: channels.response.column is 7, out of range", 0), 0u)
      << problems[0];
  // No column left to map: the message stays as it was.
  const auto g = d.write("g.csv", "force,resp\n1,2\n");
  const SignalTable u = SignalTable::open(spec(g), "g.csv");
  EXPECT_EQ(missing_channels(u, {"force", "resp", "response"}, {}, "a tap test"),
            std::vector<std::string>{
                "g.csv: channel 'response' is required for a tap test (channels: force, resp)"});
}

TEST(SignalsDialect, AnotherDialectIsNamedWithTheKeysToSet) {
  TempDir d;
  // ';' with decimal commas, read with the defaults.
  const auto a = d.write("a.csv", "force;response\n1,5;-2,25\n2,5;3\n3,5;4,75\n");
  EXPECT_EQ(message_of(spec(a)),
            "t/a.csv: line 2, column 'force': '1,5' is not a number; the file looks like "
            "';'-separated with decimal comma: set data.delimiter: \";\" and data.decimal: \",\"");
  // Plain CSV read as ';'.
  const auto b = d.write("b.csv", "force,response\n1.5,-2\n2.5,3\n");
  EXPECT_EQ(message_of(dialect(b, ';', '.', 0)),
            "t/b.csv: line 2, column 'force,response': '1.5,-2' is not a number; the file looks "
            "like ','-separated with decimal point: set data.delimiter: \",\"");
  // Tab-separated with decimal commas read with a decimal point.
  const auto c = d.write("c.txt", "force\tresponse\n1,5\t-2,25\n2,5\t3\n");
  EXPECT_EQ(message_of(dialect(c, 0, '.', 0)),
            "t/c.txt: line 2, column 'force': '1,5' is not a number; the file looks like "
            "tab-separated with decimal comma: set data.delimiter: tab and data.decimal: \",\"");
  // A header block not skipped.
  const auto e = d.write("e.txt", "Date\t2016/03/01\nOperator\tlab\nforce\tresponse\n1\t2\n3\t4\n");
  EXPECT_EQ(message_of(spec(e)),
            "t/e.txt: line 2, column 'Date': 'Operator' is not a number; the file looks like "
            "tab-separated with decimal point, header on line 3: set data.delimiter: tab and "
            "data.skip_lines: 2");
  // A file that looks like nothing else: no suggestion.
  const auto g = d.write("g.csv", "force,response\n1,2\n3,abc\n");
  EXPECT_EQ(message_of(spec(g)), "t/g.csv: line 3, column 'response': 'abc' is not a number");
}

TEST(SignalsDialect, TextExtensions) {
  EXPECT_TRUE(is_text_signal_file("a/h.csv"));
  EXPECT_TRUE(is_text_signal_file("h.TXT"));
  EXPECT_TRUE(is_text_signal_file("h.tsv"));
  EXPECT_TRUE(is_text_signal_file("h.lvm"));
  EXPECT_FALSE(is_text_signal_file("h.f32"));
  EXPECT_FALSE(is_text_signal_file("h.mat"));
}

}  // namespace
}  // namespace chatterlab::app
