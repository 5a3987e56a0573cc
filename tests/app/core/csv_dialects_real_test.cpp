// Issue 15's acceptance for the CSV dialects: five exports of the same real hammer record
// (shared/data/real-pyfrf-impact, read only) as a lab's tools write them -- headers with units
// mapped by `column:`, other column names mapped, ';' with decimal commas, a LabVIEW-style text
// file with a header block, and the plain CSV -- each loaded by the campaign loader, checked
// like `validate` does, and run through the tap step. Every export carries the same number
// texts (only the decimal mark changes), so the samples, and therefore the fitted modes, must be
// the same: fn, zeta, m, c and k agree to 1e-12 relative.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/core/campaign.h"
#include "app/core/signals.h"
#include "app/kinds/tap/tap_step.h"
#include "app/pipeline/pipeline.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::TempDir;

const std::string kReal = std::string(CHATTERLAB_SHARED_DATA) + "/real-pyfrf-impact";

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The record's rows as the two number texts of each line (the header dropped).
std::vector<std::pair<std::string, std::string>> real_rows() {
  std::istringstream in(read_text(kReal + "/tap/x/hits.csv"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "force,response");
  std::vector<std::pair<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const auto comma = line.find(',');
    rows.emplace_back(line.substr(0, comma), line.substr(comma + 1));
  }
  return rows;
}

std::string decimal_comma(std::string s) {
  for (auto& ch : s) {
    if (ch == '.') ch = ',';
  }
  return s;
}

std::string time_text(std::size_t i) {
  std::ostringstream s;
  s.precision(10);
  s << static_cast<double>(i) / 25600.0;
  return s.str();
}

const char* kTapKeys =
    "kind: tap\naxis: x\nsample_rate_hz: 25600\nresponse: acceleration\nhits: auto\n";

struct Export {
  std::string id;
  std::string file;
  std::string yaml;  // data and channels keys
  std::string text;
};

std::vector<Export> five_exports() {
  const auto rows = real_rows();
  std::vector<Export> e(5);
  e[0] = {"1-units", "hits.csv",
          "data: {file: hits.csv}\n"
          "channels:\n  force: {column: \"Force (N)\"}\n"
          "  response: {column: \"Acceleration (m/s^2)\"}\n",
          "Time (s),Force (N),Acceleration (m/s^2)\n"};
  e[1] = {"2-names", "hits.csv",
          "data: {file: hits.csv}\nchannels:\n  force: {column: Hammer}\n  response: {column: 2}\n",
          "t,Hammer,Accel\n"};
  e[2] = {"3-semicolon-comma", "hits.txt",
          "data: {file: hits.txt, delimiter: \";\", decimal: \",\"}\n", "force;response\n"};
  e[3] = {"4-labview", "hits.lvm", "data: {file: hits.lvm, skip_lines: 22}\n", ""};
  e[4] = {"5-plain", "hits.csv", "data: {file: hits.csv}\n", "force,response\n"};
  // LabVIEW-style header block: 22 lines of key<TAB>value, then the tab-separated header.
  const char* keys[] = {"LabVIEW Measurement",
                        "Writer_Version",
                        "Reader_Version",
                        "Separator",
                        "Decimal_Separator",
                        "Multi_Headings",
                        "X_Columns",
                        "Time_Pref",
                        "Operator",
                        "Date",
                        "Time",
                        "***End_of_Header***",
                        "Channels",
                        "Samples",
                        "Date",
                        "Time",
                        "Y_Unit_Label",
                        "X_Dimension",
                        "X0",
                        "Delta_X",
                        "Comment",
                        "***End_of_Header***"};
  const char* values[] = {"",
                          "2",
                          "2",
                          "Tab",
                          ".",
                          "No",
                          "One",
                          "Relative",
                          "lab",
                          "2016/03/01",
                          "10:00:00",
                          "",
                          "2",
                          "128000",
                          "2016/03/01",
                          "10:00:00",
                          "N\tm/s^2",
                          "Time",
                          "0",
                          "3.906250E-5",
                          "hammer test",
                          ""};
  for (int i = 0; i < 22; ++i) e[3].text += std::string(keys[i]) + "\t" + values[i] + "\n";
  e[3].text += "X_Value\tforce\tresponse\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& [f, x] = rows[i];
    e[0].text += time_text(i) + "," + f + "," + x + "\n";
    e[1].text += time_text(i) + "," + f + "," + x + "\n";
    e[2].text += decimal_comma(f) + ";" + decimal_comma(x) + "\n";
    e[3].text += time_text(i) + "\t" + f + "\t" + x + "\r\n";
    e[4].text += f + "," + x + "\n";
  }
  return e;
}

TEST(CsvDialectsReal, FiveExportsOfTheRealHammerRecordGiveTheSameModes) {
  ASSERT_TRUE(std::filesystem::exists(kReal + "/tap/x/hits.csv")) << kReal;
  TempDir d;
  d.write("campaign.yaml", read_text(kReal + "/campaign.yaml"));
  const auto exports = five_exports();
  for (const auto& e : exports) {
    d.write(e.id + "/test.yaml", std::string(kTapKeys) + e.yaml);
    d.write(e.id + "/" + e.file, e.text);
  }
  CampaignSpec c = load_campaign(d.path());
  ASSERT_TRUE(c.errors.empty());
  ASSERT_EQ(c.tests.size(), 5u);

  std::vector<std::vector<frf::Mode>> modes;
  for (auto& t : c.tests) {
    check_signals(t);
    EXPECT_TRUE(t.errors.empty()) << t.id << ": " << (t.errors.empty() ? "" : t.errors[0]);
    EXPECT_TRUE(t.warnings.empty()) << t.id << ": " << (t.warnings.empty() ? "" : t.warnings[0]);
    ASSERT_TRUE(t.usable()) << t.id;
    const TapOutcome out = run_tap_test(t, TapStepOptions{});
    ASSERT_TRUE(out.summary.ok()) << t.id << ": " << out.summary.message;
    ASSERT_TRUE(out.fit_ok) << t.id << ": " << out.fit_message;
    EXPECT_EQ(out.hits_used, 5) << t.id;
    ASSERT_FALSE(out.modes.empty()) << t.id;
    for (const auto& m : out.modes) {
      std::printf("%-18s fn %.6f Hz  zeta %.6e  m %.6e kg  c %.6e kg/s  k %.6e N/m\n", t.id.c_str(),
                  m.fn_hz, m.zeta, m.m_kg, m.c_kg_s, m.k_N_m);
    }
    modes.push_back(out.modes);
  }
  // The plain CSV (the last id) is the reference.
  const auto& ref = modes.back();
  const auto close = [](double a, double b) { return std::abs(a - b) <= 1e-12 * std::abs(b); };
  for (std::size_t i = 0; i + 1 < modes.size(); ++i) {
    ASSERT_EQ(modes[i].size(), ref.size()) << c.tests[i].id;
    for (std::size_t k = 0; k < ref.size(); ++k) {
      const auto& a = modes[i][k];
      const auto& b = ref[k];
      EXPECT_TRUE(close(a.fn_hz, b.fn_hz)) << c.tests[i].id << " mode " << k;
      EXPECT_TRUE(close(a.zeta, b.zeta)) << c.tests[i].id << " mode " << k;
      EXPECT_TRUE(close(a.m_kg, b.m_kg)) << c.tests[i].id << " mode " << k;
      EXPECT_TRUE(close(a.c_kg_s, b.c_kg_s)) << c.tests[i].id << " mode " << k;
      EXPECT_TRUE(close(a.k_N_m, b.k_N_m)) << c.tests[i].id << " mode " << k;
    }
  }
}

// The same exports read with the defaults (no dialect keys, no column mapping): each fails
// with a message that names the file and says what to set.
TEST(CsvDialectsReal, ExportsReadWithDefaultsSuggestTheFix) {
  ASSERT_TRUE(std::filesystem::exists(kReal + "/tap/x/hits.csv")) << kReal;
  TempDir d;
  d.write("campaign.yaml", read_text(kReal + "/campaign.yaml"));
  auto exports = five_exports();
  for (const auto& e : exports) {
    d.write(e.id + "/test.yaml", std::string(kTapKeys) + "data: {file: " + e.file + "}\n");
    d.write(e.id + "/" + e.file, e.text);
  }
  CampaignSpec c = load_campaign(d.path());
  ASSERT_EQ(c.tests.size(), 5u);
  for (auto& t : c.tests) check_signals(t);
  const auto first_error = [&](std::size_t i) {
    return c.tests[i].errors.empty() ? std::string("no error") : c.tests[i].errors[0];
  };
  EXPECT_EQ(first_error(0),
            "1-units/hits.csv: channel 'force' is required for a tap test (channels: Time (s), "
            "Force (N), Acceleration (m/s^2)); the column 'Force (N)' looks like it: set "
            "channels.force.column: \"Force (N)\" (units in headers are not read: add a scale "
            "when the unit is not the one the test needs)");
  EXPECT_EQ(first_error(1),
            "2-names/hits.csv: channel 'force' is required for a tap test (channels: t, Hammer, "
            "Accel); set channels.force.column to the header text of its column ('Hammer', "
            "'Accel') or its 0-based index");
  EXPECT_EQ(first_error(2),
            "3-semicolon-comma/hits.txt: line 2, column 'force': '-0,0166735103' is not a "
            "number; the file looks like ';'-separated with decimal comma: set data.delimiter: "
            "\";\" and data.decimal: \",\"");
  EXPECT_EQ(first_error(3),
            "4-labview/hits.lvm: line 2, column 'LabVIEW Measurement': 'Writer_Version' is not a "
            "number; the file looks like tab-separated with decimal point, header on line 23: "
            "set data.delimiter: tab and data.skip_lines: 22");
  EXPECT_TRUE(c.tests[4].usable()) << first_error(4);
}

}  // namespace
}  // namespace chatterlab::app
