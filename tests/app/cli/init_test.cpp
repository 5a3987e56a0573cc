// `chatterlab init` (issue 15, real lab data in): a folder of data files gives campaign.yaml and
// test.yaml proposals whose kinds, channel mappings, dialects and sample rates come from the
// files, with a TODO for each key it cannot decide that `validate` then names; nothing is
// written without --write, and --write never overwrites an existing campaign.yaml or test.yaml.
#include "app/cli/init.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "app/cli/exit_codes.h"
#include "app/cli/output_folder.h"
#include "app/cli/validate.h"
#include "app/core/campaign.h"
#include "app/formats/matfile.h"
#include "app/formats/uff58.h"
#include "tests/app/cli/run_binary.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using chatterlab::testing::file_text;
using chatterlab::testing::quoted;
using chatterlab::testing::TempDir;

const fs::path kUffSamples = fs::path(CHATTERLAB_SHARED_DATA) / "uff-pyuff-samples";

std::string comma_decimal(double v) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.9g", v);
  std::string s = buf;
  for (auto& c : s) {
    if (c == '.') c = ',';
  }
  return s;
}

// A hammer record as a German-locale spreadsheet writes it: ';' between cells, decimal commas,
// a time column, units in the headers; two hits at 25.6 kHz.
std::string tap_csv_decimal_comma() {
  std::string s = "Time (s);Force (N);Accel (m/s^2)\n";
  const double fs = 25600.0;
  for (int i = 0; i < 12800; ++i) {
    const double t = i / fs;
    const double hit = std::fmod(t, 0.25);
    const double f = hit < 3e-4 ? 150.0 * std::sin(M_PI * hit / 3e-4) : 0.0;
    const double a =
        hit >= 3e-4 ? 40.0 * std::exp(-60.0 * hit) * std::sin(2 * M_PI * 900 * hit) : 0.0;
    s += comma_decimal(t) + ";" + comma_decimal(f) + ";" + comma_decimal(a) + "\n";
  }
  return s;
}

const InitFile* file_named(const InitProposal& p, const std::string& path) {
  for (const auto& f : p.files) {
    if (f.path == path) return &f;
  }
  return nullptr;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

int validate(const fs::path& folder, std::string* out) {
  CampaignSpec c = load_campaign(folder);
  std::ostringstream s;
  const int rc = validate_campaign(c, s);
  *out = s.str();
  return rc;
}

TEST(Init, DecimalCommaTapCsvGivesAMappedTapTestThatValidates) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  d.write("lab/hits-x.csv", tap_csv_decimal_comma());

  const InitProposal p = propose_campaign(lab);
  EXPECT_EQ(p.data_files, 1);
  EXPECT_EQ(p.tests, 1);
  ASSERT_EQ(p.files.size(), 2u);
  EXPECT_EQ(p.files[0].path, "campaign.yaml");
  EXPECT_TRUE(has(p.files[0].content, "format: chatterlab-campaign/1\n"));
  EXPECT_TRUE(has(p.files[0].content, "name: lab "));
  const InitFile* t = file_named(p, "hits-x/test.yaml");
  ASSERT_NE(t, nullptr);
  const std::string& y = t->content;
  EXPECT_TRUE(has(y, "kind: tap ")) << y;
  EXPECT_TRUE(has(y, "# guessed: a force column 'Force (N)' and a response column 'Accel (m/s^2)'"))
      << y;
  EXPECT_TRUE(has(y, "axis: x ")) << y;
  EXPECT_TRUE(has(y, "# from the name 'hits-x'")) << y;
  EXPECT_TRUE(has(y, "sample_rate_hz: 25600 ")) << y;
  EXPECT_TRUE(has(y, "# from the time column 'Time (s)': 12800 samples 3.90625e-05 s apart")) << y;
  EXPECT_TRUE(has(y, "response: acceleration ")) << y;
  EXPECT_TRUE(has(y, "hits: auto ")) << y;
  EXPECT_TRUE(has(y, "data: {file: ../hits-x.csv, delimiter: \";\", decimal: \",\"}")) << y;
  EXPECT_TRUE(has(y, "  force: {column: \"Force (N)\"}")) << y;
  EXPECT_TRUE(has(y, "  response: {column: \"Accel (m/s^2)\"}")) << y;
  EXPECT_TRUE(has(y, "# from the unit m/s^2 of 'Accel (m/s^2)'")) << y;
  EXPECT_TRUE(has(y, "  force: {column: \"Force (N)\"}        # recognised as the force\n")) << y;
  EXPECT_FALSE(has(y, "# TODO")) << y;
  EXPECT_FALSE(fs::exists(lab / "hits-x")) << "propose_campaign writes nothing";

  std::ostringstream out;
  EXPECT_EQ(run_init(lab, true, out), kExitOk);
  EXPECT_TRUE(has(out.str(), "init: wrote 2 files: campaign.yaml, hits-x/test.yaml")) << out.str();

  // What the loader reads from the written files.
  const CampaignSpec c = load_campaign(lab);
  ASSERT_EQ(c.tests.size(), 1u);
  const TestSpec& ts = c.tests[0];
  EXPECT_EQ(ts.id, "hits-x");
  EXPECT_EQ(ts.kind, "tap");
  EXPECT_EQ(ts.sample_rate_hz, 25600.0);
  EXPECT_EQ(ts.data.delimiter, ';');
  EXPECT_EQ(ts.data.decimal, ',');
  ASSERT_TRUE(ts.channel("force").column.has_value());
  EXPECT_EQ(ts.channel("force").column->header, "Force (N)");
  ASSERT_TRUE(ts.channel("response").column.has_value());
  EXPECT_EQ(ts.channel("response").column->header, "Accel (m/s^2)");
  EXPECT_TRUE(ts.errors.empty()) << ts.errors.front();

  std::string listing;
  EXPECT_EQ(validate(lab, &listing), 0) << listing;
  EXPECT_TRUE(has(listing, "1 tests found, 1 usable, 0 unusable")) << listing;
}

TEST(Init, WithoutWriteNothingIsWritten) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  d.write("lab/tap/x/hits.csv", tap_csv_decimal_comma());
  const auto before = files_below(lab);
  std::ostringstream out;
  EXPECT_EQ(run_init(lab, false, out), kExitOk);
  EXPECT_EQ(files_below(lab), before);
  EXPECT_EQ(before, std::vector<std::string>{"tap/x/hits.csv"});
  // The folder holding one data file is the test: data.file names it without ../.
  EXPECT_TRUE(has(out.str(), "=== tap/x/test.yaml (new)\n")) << out.str();
  EXPECT_TRUE(has(out.str(), "data: {file: hits.csv, delimiter: \";\", decimal: \",\"}"))
      << out.str();
  EXPECT_TRUE(has(out.str(), "axis: x ")) << out.str();
  EXPECT_TRUE(has(out.str(), "init: nothing written; run again with --write to write 2 files"))
      << out.str();
}

TEST(Init, WriteNeverOverwritesCampaignOrTestYaml) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  d.write("lab/hits-x.csv", tap_csv_decimal_comma());
  d.write("lab/campaign.yaml", "# mine\nformat: chatterlab-campaign/1\nname: mine\n");
  d.write("lab/hits-x/test.yaml", "# mine too\n");
  std::ostringstream out;
  EXPECT_EQ(run_init(lab, true, out), kExitOk);
  EXPECT_EQ(file_text(lab / "campaign.yaml"),
            "# mine\nformat: chatterlab-campaign/1\nname: mine\n");
  EXPECT_EQ(file_text(lab / "hits-x/test.yaml"), "# mine too\n");
  EXPECT_TRUE(has(out.str(), "=== campaign.yaml: exists, kept as it is (init never overwrites it)"))
      << out.str();
  EXPECT_TRUE(has(out.str(), "init: wrote 0 files\n")) << out.str();
  EXPECT_TRUE(
      has(out.str(), "init: skipped campaign.yaml, hits-x/test.yaml (exist: never overwritten)"))
      << out.str();

  // A data file that a test.yaml names is already described: no second test for it.
  d.write("lab/hits-x/test.yaml", "kind: tap\ndata: {file: ../hits-x.csv}\n");
  // So is a file that truth.yaml names (a synthetic campaign's known values).
  d.write("lab/traj.csv", "cycle,j\n1,0\n1,1\n");
  d.write("lab/truth.yaml", "tests:\n  g: {trajectory: {file: traj.csv}}\n");
  const InitProposal again = propose_campaign(lab);
  EXPECT_EQ(again.tests, 0);
  EXPECT_EQ(again.data_files, 2);
  EXPECT_EQ(again.findings,
            (std::vector<std::string>{
                "hits-x.csv: already named by a test.yaml or truth.yaml; left as it is",
                "traj.csv: already named by a test.yaml or truth.yaml; left as it is"}));
}

// The real pyuff samples: a microphone time record (record 1 text "Mic 01.0Scalar": no kind's
// channels) and a file of spectra.
TEST(Init, UffSamplesGiveAProposalWithTheRecordsRateAndAKindTodo) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  fs::create_directories(lab);
  fs::copy_file(kUffSamples / "Sample_UFF58_ascii.uff", lab / "Sample_UFF58_ascii.uff");
  fs::copy_file(kUffSamples / "sample_dataset58_psd.uff", lab / "sample_dataset58_psd.uff");

  const InitProposal p = propose_campaign(lab);
  EXPECT_EQ(p.data_files, 2);
  EXPECT_EQ(p.tests, 1);
  ASSERT_EQ(p.findings.size(), 2u);
  EXPECT_EQ(p.findings[0],
            "Sample_UFF58_ascii.uff: kind not decided (channels: 'Mic 01.0Scalar') -> "
            "Sample_UFF58_ascii/test.yaml");
  EXPECT_EQ(p.findings[1].rfind("sample_dataset58_psd.uff: no test proposed: no dataset 58 time "
                                "record or FRF in the file (it holds #1 ",
                                0),
            0u)
      << p.findings[1];
  const InitFile* t = file_named(p, "Sample_UFF58_ascii/test.yaml");
  ASSERT_NE(t, nullptr);
  EXPECT_TRUE(has(t->content, "# TODO kind: no kind's channels recognised among 'Mic 01.0Scalar'"))
      << t->content;
  EXPECT_TRUE(has(t->content, "sample_rate_hz: 65536 ")) << t->content;
  EXPECT_TRUE(has(t->content, "# from the records' abscissa step dx (1.52588e-05 s)"))
      << t->content;
  EXPECT_TRUE(has(t->content, "data: {file: ../Sample_UFF58_ascii.uff}")) << t->content;

  std::ostringstream out;
  ASSERT_EQ(run_init(lab, true, out), kExitOk);
  std::string listing;
  EXPECT_EQ(validate(lab, &listing), 1);
  EXPECT_TRUE(has(listing, "Sample_UFF58_ascii/test.yaml: key 'kind' is missing")) << listing;
}

// A frequency / real / imaginary table is a tap test with `frf:` (no data, no sample rate).
TEST(Init, FrfTableGivesATapTestWithFrf) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  std::string frf = "Frequency (Hz);Real (m/N);Imag (m/N)\n";
  for (int k = 1; k <= 200; ++k) {
    frf += comma_decimal(10.0 * k) + ";" + comma_decimal(1e-7 / k) + ";" +
           comma_decimal(-2e-7 / k) + "\n";
  }
  d.write("lab/tap/y/frf.csv", frf);
  const InitProposal p = propose_campaign(lab);
  const InitFile* t = file_named(p, "tap/y/test.yaml");
  ASSERT_NE(t, nullptr);
  EXPECT_TRUE(has(t->content, "kind: tap ")) << t->content;
  EXPECT_TRUE(has(t->content, "axis: y ")) << t->content;
  EXPECT_TRUE(has(t->content, "response: displacement ")) << t->content;
  EXPECT_TRUE(has(t->content, "frf: {file: frf.csv}")) << t->content;
  EXPECT_TRUE(has(t->content, "200 frequencies, step 10 Hz")) << t->content;
  EXPECT_FALSE(has(t->content, "\nsample_rate_hz:")) << t->content;
  EXPECT_FALSE(has(t->content, "\ndata:")) << t->content;
  EXPECT_FALSE(has(t->content, "\nhits:")) << t->content;

  std::ostringstream out;
  ASSERT_EQ(run_init(lab, true, out), kExitOk);
  std::string listing;
  EXPECT_EQ(validate(lab, &listing), 0) << listing;
}

// Fx, Fy and a zero pulse: a dyno-slot test, the spindle speed from the pulse, the tool and the
// cut's values as TODOs that validate names.
TEST(Init, DynamometerColumnsGiveADynoSlotTestWithTheSpeedFromThePulse) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  std::string csv = "t,Fx (N),Fy (N),Zero (V)\n";
  const double fs = 20000.0;
  for (int i = 0; i < 20000; ++i) {
    const double t = i / fs;
    const bool pulse = (i % 2000) < 20;  // 600 rpm: one revolution every 2000 samples
    char row[160];
    std::snprintf(row, sizeof(row), "%.9g,%.6f,%.6f,%d\n", t, 50 * std::sin(2 * M_PI * 20 * t),
                  30 * std::cos(2 * M_PI * 20 * t), pulse ? 5 : 0);
    csv += row;
  }
  d.write("lab/dyno/f050/forces.csv", csv);
  const InitProposal p = propose_campaign(lab);
  ASSERT_EQ(p.tests, 1);
  const InitFile* t = file_named(p, "dyno/f050/test.yaml");
  ASSERT_NE(t, nullptr);
  const std::string& y = t->content;
  EXPECT_TRUE(has(y, "kind: dyno-slot ")) << y;
  EXPECT_TRUE(has(y, "sample_rate_hz: 20000 ")) << y;
  EXPECT_TRUE(has(y, "spindle_rpm: 600 ")) << y;
  EXPECT_TRUE(has(y, "# from the pulse 'Zero (V)': 9 rising edges, one every 0.1 s")) << y;
  EXPECT_TRUE(has(y, "# TODO feed_per_tooth_mm:")) << y;
  EXPECT_TRUE(has(y, "# TODO axial_depth_mm:")) << y;
  EXPECT_TRUE(has(y, "  Fx: {column: \"Fx (N)\"}")) << y;
  EXPECT_TRUE(has(y, "  Fy: {column: \"Fy (N)\"}")) << y;
  EXPECT_TRUE(has(y, "  zero: {column: \"Zero (V)\"}")) << y;
  EXPECT_TRUE(has(p.files[0].content, "# TODO tool: {teeth: N, radius_mm: R}: required"))
      << p.files[0].content;

  std::ostringstream out;
  ASSERT_EQ(run_init(lab, true, out), kExitOk);
  std::string listing;
  EXPECT_EQ(validate(lab, &listing), 1);
  EXPECT_TRUE(has(listing, "dyno/f050/test.yaml: key 'feed_per_tooth_mm' is missing")) << listing;
  EXPECT_TRUE(has(listing, "dyno/f050/test.yaml: key 'axial_depth_mm' is missing")) << listing;
  EXPECT_TRUE(has(listing, "campaign.yaml key 'tool'")) << listing;
}

// A .mat file: channels by variable, the sample rate from its time vector.
TEST(Init, MatFileGivesATapTestWithTheRateOfItsTimeVariable) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  fs::create_directories(lab / "tap-y");
  const int n = 5120;
  Eigen::MatrixXd t(n, 1), f(n, 1), a(n, 1);
  for (int i = 0; i < n; ++i) {
    t(i, 0) = i / 5120.0;
    f(i, 0) = i % 1024 < 2 ? 100.0 : 0.0;
    a(i, 0) = std::sin(0.3 * i);
  }
  mat::write_mat(lab / "tap-y/run1.mat", {{"t", t}, {"force", f}, {"acc_g", a}});
  const InitProposal p = propose_campaign(lab);
  const InitFile* tf = file_named(p, "tap-y/test.yaml");
  ASSERT_NE(tf, nullptr);
  const std::string& y = tf->content;
  EXPECT_TRUE(has(y, "kind: tap ")) << y;
  EXPECT_TRUE(has(y, "axis: y ")) << y;
  EXPECT_TRUE(has(y, "sample_rate_hz: 5120 ")) << y;
  EXPECT_TRUE(has(y, "# from the variable 't': 5120 samples")) << y;
  EXPECT_TRUE(has(y, "data: {file: run1.mat}")) << y;
  EXPECT_TRUE(has(y, "# channel force: the column 'force' (named like it)")) << y;
  EXPECT_TRUE(has(y, "  response: {column: \"acc_g\"}")) << y;
  EXPECT_TRUE(has(y, "response: acceleration ")) << y;

  std::ostringstream out;
  ASSERT_EQ(run_init(lab, true, out), kExitOk);
  std::string listing;
  EXPECT_EQ(validate(lab, &listing), 0) << listing;
}

// Deflection sensors in mm and a tachometer: a cut test, the sensors scaled to m, the speed from
// the tachometer, and the cut's own keys and campaign.yaml's tool as TODOs.
TEST(Init, DeflectionAndTachometerColumnsGiveACutTest) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  std::string csv = "time,tach (V),defl x (mm),defl y (mm)\n";
  for (int i = 0; i < 4000; ++i) {  // 10 kHz, 15000 rpm: one revolution every 40 samples
    char row[160];
    std::snprintf(row, sizeof(row), "%.9g,%d,%.6f,%.6f\n", i / 10000.0, i % 40 < 4 ? 5 : 0,
                  0.01 * std::sin(0.3 * i), 0.01 * std::cos(0.3 * i));
    csv += row;
  }
  d.write("lab/cuts/run1.csv", csv);
  const InitProposal p = propose_campaign(lab);
  const InitFile* t = file_named(p, "cuts/test.yaml");
  ASSERT_NE(t, nullptr);
  const std::string& y = t->content;
  EXPECT_TRUE(has(y, "kind: cut ")) << y;
  EXPECT_TRUE(has(y, "sample_rate_hz: 10000 ")) << y;
  EXPECT_TRUE(has(y, "spindle_rpm: 15000 ")) << y;
  EXPECT_TRUE(has(y, "  x: {column: \"defl x (mm)\", scale: 0.001}")) << y;
  EXPECT_TRUE(has(y, "  y: {column: \"defl y (mm)\", scale: 0.001}")) << y;
  EXPECT_TRUE(
      has(y, "# recognised as the deflection along x; the header says mm; the test needs m"))
      << y;
  EXPECT_TRUE(has(y, "  tach: {column: \"tach (V)\"}")) << y;
  for (const char* key : {"operation", "feed_per_tooth_mm", "radial_immersion_mm", "axial_depth_mm",
                          "cut_window_s"}) {
    EXPECT_TRUE(has(y, std::string("# TODO ") + key + ":")) << key << "\n" << y;
  }
  EXPECT_TRUE(has(p.files[0].content, "# TODO tool: {teeth: N, radius_mm: R}: required"));

  std::ostringstream out;
  ASSERT_EQ(run_init(lab, true, out), kExitOk);
  std::string listing;
  EXPECT_EQ(validate(lab, &listing), 1);
  EXPECT_TRUE(has(listing, "cuts/test.yaml: key 'operation' is missing")) << listing;
  EXPECT_TRUE(has(listing, "cuts/test.yaml: key 'cut_window_s' is missing")) << listing;
}

// A UFF file of two FRF records (function type 4) gives a tap test per record, the axis from
// each record's response direction and the ordinate from its units.
TEST(Init, UffFrfRecordsGiveATapTestEach) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  fs::create_directories(lab);
  std::vector<uff::Function58> records(2);
  for (int k = 0; k < 2; ++k) {
    auto& f = records[static_cast<std::size_t>(k)];
    f.id1 = k == 0 ? "H xx" : "H yy";
    f.function_type = uff::kFrf;
    f.response_node = 1;
    f.response_direction = k + 1;
    f.reference_node = 1;
    f.reference_direction = k + 1;
    f.x_start = 10.0;
    f.dx = 10.0;
    f.complex_ordinate = true;
    f.values = Eigen::VectorXcd::Constant(100, std::complex<double>(1e-3, -2e-3));
    f.x_label = "Frequency";
    f.x_unit = "Hz";
    f.y_label = "Acceleration";
    f.y_unit = "m/s^2";
    f.z_label = "Force";
    f.z_unit = "N";
  }
  uff::write_uff58(lab / "frfs.uff", records);
  const InitProposal p = propose_campaign(lab);
  EXPECT_EQ(p.tests, 2);
  const InitFile* a = file_named(p, "frfs-frf1/test.yaml");
  const InitFile* b = file_named(p, "frfs-frf2/test.yaml");
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  EXPECT_TRUE(has(a->content, "axis: x ")) << a->content;
  EXPECT_TRUE(has(b->content, "axis: y ")) << b->content;
  EXPECT_TRUE(has(a->content, "response: acceleration ")) << a->content;
  EXPECT_TRUE(has(a->content, "frf: {file: ../frfs.uff, record: 1}")) << a->content;
  EXPECT_TRUE(has(b->content, "frf: {file: ../frfs.uff, record: 2}")) << b->content;

  std::ostringstream out;
  ASSERT_EQ(run_init(lab, true, out), kExitOk);
  std::string listing;
  EXPECT_EQ(validate(lab, &listing), 0) << listing;
}

// A LabVIEW text export: the header block found (skip_lines, tab), the rate from its Delta_X,
// channels named like the kind's; the response's unit is not stated: a TODO.
TEST(Init, LabviewExportGivesSkipLinesAndTheRateFromDeltaX) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  std::string lvm =
      "LabVIEW Measurement\t\nWriter_Version\t2\nSeparator\tTab\nDelta_X\t3.906250E-5\n"
      "***End_of_Header***\t\nforce\tresponse\tComment\n";
  for (int i = 0; i < 200; ++i) {
    lvm += std::to_string(i % 50 == 0 ? 100.0 : 0.0) + "\t" + std::to_string(std::sin(0.2 * i)) +
           "\t\n";
  }
  d.write("lab/tap/x/hits.lvm", lvm);
  const InitProposal p = propose_campaign(lab);
  const InitFile* t = file_named(p, "tap/x/test.yaml");
  ASSERT_NE(t, nullptr);
  const std::string& y = t->content;
  EXPECT_TRUE(has(y, "kind: tap ")) << y;
  EXPECT_TRUE(has(y, "sample_rate_hz: 25600 ")) << y;
  EXPECT_TRUE(has(y, "# from the header block's Delta_X 3.90625e-05 s")) << y;
  EXPECT_TRUE(has(y, "data: {file: hits.lvm, delimiter: tab, skip_lines: 5}")) << y;
  EXPECT_TRUE(has(y, "# channel force: the column 'force' (named like it)")) << y;
  EXPECT_TRUE(has(y, "# TODO response: acceleration, velocity or displacement")) << y;
  EXPECT_FALSE(has(y, "\nchannels:")) << y;

  std::ostringstream out;
  ASSERT_EQ(run_init(lab, true, out), kExitOk);
  std::string listing;
  EXPECT_EQ(validate(lab, &listing), 1);
  EXPECT_TRUE(has(listing, "tap/x/test.yaml: key 'response' is missing")) << listing;
  EXPECT_TRUE(has(listing, "1 tests found, 0 usable, 1 unusable")) << listing;
}

// A name taken by a link to a folder outside: the test folder gets another name, and nothing is
// written outside the folder.
TEST(Init, NothingIsWrittenThroughALinkOutOfTheFolder) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  d.write("lab/hits-x.csv", tap_csv_decimal_comma());
  fs::create_directories(d.path() / "outside");
  fs::create_directory_symlink(d.path() / "outside", lab / "hits-x");
  std::ostringstream out;
  ASSERT_EQ(run_init(lab, true, out), kExitOk);
  EXPECT_TRUE(has(out.str(), "init: wrote 2 files: campaign.yaml, hits-x-test/test.yaml"))
      << out.str();
  EXPECT_TRUE(fs::is_empty(d.path() / "outside"));
  EXPECT_TRUE(has(file_text(lab / "hits-x-test/test.yaml"), "data: {file: ../hits-x.csv,"));
}

// Two files in the campaign root: a grinding record (cycle, power) and a spindle-sensor tap
// record (hammer and the six washer channels): a test folder each beside them.
TEST(Init, GrindingAndSifsTapColumns) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  std::string fast = "cycle,u_mm_s,power,Dw_mm\n";
  std::string taps = "t,hammer,x1,x2,y1,y2,z1,z2\n";
  for (int i = 0; i < 40; ++i) {
    fast += std::to_string(1 + i / 20) + ",0.01,500,0.001\n";
    taps += std::to_string(i / 12800.0) + ",0,1,2,3,4,5,6\n";
  }
  d.write("lab/fast.csv", fast);
  d.write("lab/tap-x.csv", taps);
  const InitProposal p = propose_campaign(lab);
  EXPECT_EQ(p.tests, 2);
  const InitFile* g = file_named(p, "fast/test.yaml");
  const InitFile* s = file_named(p, "tap-x/test.yaml");
  ASSERT_NE(g, nullptr);
  ASSERT_NE(s, nullptr);
  EXPECT_TRUE(has(g->content, "kind: grinding ")) << g->content;
  EXPECT_TRUE(has(g->content, "# TODO sample_rate_hz: the sample rate, Hz (no time column)"))
      << g->content;
  EXPECT_TRUE(has(g->content, "# TODO model:")) << g->content;
  EXPECT_TRUE(has(s->content, "kind: sifs-tap ")) << s->content;
  EXPECT_TRUE(has(s->content, "axis: x ")) << s->content;
  EXPECT_TRUE(has(s->content, "# TODO band_hz:")) << s->content;
  EXPECT_TRUE(has(s->content, "data: {file: ../tap-x.csv}")) << s->content;
}

TEST(Init, AFolderWithoutDataOrNotAFolder) {
  TempDir d;
  d.write("empty/readme.md", "notes\n");
  std::ostringstream out;
  EXPECT_EQ(run_init(d.path() / "empty", true, out), kExitInputError);
  EXPECT_TRUE(has(out.str(), "init: no data file")) << out.str();
  EXPECT_EQ(files_below(d.path() / "empty"), std::vector<std::string>{"readme.md"});
  EXPECT_THROW(propose_campaign(d.path() / "missing"), chatterlab::InputError);
}

// The command through the built binary: the proposal on stdout, nothing written without
// --write; --write writes, validate accepts, a second --write keeps the files.
TEST(InitBinary, ProposeWriteValidate) {
  TempDir d;
  const fs::path lab = d.path() / "lab";
  d.write("lab/hits-x.csv", tap_csv_decimal_comma());
  const auto run = [&](const std::string& args) {
    return chatterlab::testing::run_chatterlab(args, d.path());
  };
  const auto dry = run("init " + quoted(lab));
  EXPECT_EQ(dry.status, kExitOk) << dry.err;
  EXPECT_EQ(dry.err, "");
  EXPECT_TRUE(has(dry.out, "=== hits-x/test.yaml (new)\n")) << dry.out;
  EXPECT_TRUE(has(dry.out, "  force: {column: \"Force (N)\"}")) << dry.out;
  EXPECT_EQ(files_below(lab), std::vector<std::string>{"hits-x.csv"});

  const auto w = run("init " + quoted(lab) + " --write");
  EXPECT_EQ(w.status, kExitOk) << w.err;
  EXPECT_TRUE(has(w.out, "=== hits-x/test.yaml (written)\n")) << w.out;
  EXPECT_EQ(files_below(lab),
            (std::vector<std::string>{"campaign.yaml", "hits-x.csv", "hits-x/test.yaml"}));
  const std::string written = file_text(lab / "hits-x/test.yaml");

  const auto v = run("validate " + quoted(lab));
  EXPECT_EQ(v.status, kExitOk) << v.out << v.err;

  const auto again = run("init " + quoted(lab) + " --write");
  EXPECT_EQ(again.status, kExitOk) << again.err;
  EXPECT_TRUE(has(again.out, "init: skipped campaign.yaml")) << again.out;
  EXPECT_EQ(file_text(lab / "hits-x/test.yaml"), written);

  const auto bad = run("init " + quoted(lab) + " --out x");
  EXPECT_EQ(bad.status, kExitUsage);
  EXPECT_TRUE(has(bad.err, "option '--out' does not apply to init")) << bad.err;
  const auto missing = run("init " + quoted(d.path() / "nowhere"));
  EXPECT_EQ(missing.status, kExitInputError);
  EXPECT_TRUE(has(missing.err, "nowhere: no such folder")) << missing.err;
  const auto help = run("init --help");
  EXPECT_EQ(help.status, kExitOk);
  EXPECT_TRUE(has(help.out, "usage: chatterlab init <folder> [--write]")) << help.out;
}

}  // namespace
}  // namespace chatterlab::app
