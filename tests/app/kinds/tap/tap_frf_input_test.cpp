// A tap test that gives a measured FRF instead of hits (test.yaml `frf:`): the FRF of the real
// pyFRF hammer campaign, written by the tap kind's own frf.csv / frf.uff writers, read back as
// an FRF input gives the modes of the time-record campaign; results.json has no hit keys and
// says frf_source: file; bad files and keys give messages naming the file and key.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "analysis/common/summary.h"
#include "app/core/campaign.h"
#include "app/core/yaml_reader.h"
#include "app/formats/frf_text.h"
#include "app/formats/uff58.h"
#include "app/kinds/tap/tap_kind.h"
#include "app/pipeline/campaign_values.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::expect_input_error;
using chatterlab::testing::TempDir;

// A tap TestSpec from test.yaml text in `folder` (its kind keys parsed by TapKind; the loader's
// common keys are not needed by an FRF-file test).
TestSpec frf_test(const TempDir& dir, const std::string& id, const std::string& yaml,
                  std::vector<std::string>* errors = nullptr) {
  dir.write(id + "/test.yaml", yaml);
  TestSpec t;
  t.id = id;
  t.folder = dir.path() / id;
  t.yaml_label = id + "/test.yaml";
  t.kind = "tap";
  YamlReader r(t.yaml_label);
  t.params = TapKind().parse(YAML::Load(yaml), r);
  if (errors) {
    *errors = r.errors();
  } else {
    EXPECT_TRUE(r.errors().empty()) << r.errors().front();
  }
  return t;
}

TestOutcome run(const TestSpec& t) {
  TestOutcome out;
  out.spec = &t;
  TapKind().run(t, CampaignValues{}, RunContext{}, out);
  return out;
}

class RealTapFrfInput : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    campaign_ =
        new CampaignSpec(load_campaign(std::string(CHATTERLAB_SHARED_DATA) + "/real-pyfrf-impact"));
    for (const auto& t : campaign_->tests) {
      if (t.id == "tap/x" && t.usable()) {
        record_ = new TestOutcome();
        record_->spec = &t;
        TapKind().run(t, CampaignValues{}, RunContext{}, *record_);
      }
    }
  }
  static void TearDownTestSuite() {
    delete record_;
    delete campaign_;
    record_ = nullptr;
    campaign_ = nullptr;
  }
  static CampaignSpec* campaign_;
  static TestOutcome* record_;
};
CampaignSpec* RealTapFrfInput::campaign_ = nullptr;
TestOutcome* RealTapFrfInput::record_ = nullptr;

void expect_same_modes(const TapOutcome& a, const TapOutcome& b) {
  ASSERT_TRUE(a.fit_ok) << a.fit_message;
  ASSERT_TRUE(b.fit_ok) << b.fit_message;
  ASSERT_EQ(a.modes.size(), b.modes.size());
  for (std::size_t i = 0; i < a.modes.size(); ++i) {
    EXPECT_NEAR(b.modes[i].fn_hz / a.modes[i].fn_hz, 1.0, 1e-6) << "mode " << i + 1;
    EXPECT_NEAR(b.modes[i].zeta / a.modes[i].zeta, 1.0, 1e-6) << "mode " << i + 1;
    EXPECT_NEAR(b.modes[i].k_N_m / a.modes[i].k_N_m, 1.0, 1e-6) << "mode " << i + 1;
  }
  EXPECT_NEAR(b.fit_nrmse_pct, a.fit_nrmse_pct, 1e-6);
}

TEST_F(RealTapFrfInput, CsvOfTheHammerFrfGivesTheSameModes) {
  ASSERT_NE(record_, nullptr) << "tap/x of real-pyfrf-impact not loaded";
  ASSERT_TRUE(record_->status.ok()) << record_->status.message;
  const TapOutcome& a = record_->result_of<TapOutcome>();
  ASSERT_FALSE(a.from_file);
  ASSERT_GE(a.modes.size(), 9u);

  TempDir dir;
  write_tap_frf_csv(a, "tap/x", dir.path() / "tap/x/frf.csv");
  const TestSpec t =
      frf_test(dir, "tap/x", "kind: tap\naxis: x\nresponse: displacement\nfrf: {file: frf.csv}\n");
  const TestOutcome out = run(t);
  ASSERT_TRUE(out.status.ok()) << out.status.message;
  const TapOutcome& b = out.result_of<TapOutcome>();
  EXPECT_TRUE(b.from_file);
  EXPECT_TRUE(b.has_coherence);
  EXPECT_EQ(b.frf_columns, "'f_hz', 're', 'im', 'coherence' by the header on line 4");
  ASSERT_EQ(b.f_hz.size(), a.f_hz.size());
  EXPECT_EQ((b.h1 - a.h1).cwiseAbs().maxCoeff(), 0.0);  // 17 digits: exact
  expect_same_modes(a, b);

  // results.json: the tap block without hit keys, frf_source file, files named.
  const nlohmann::json j = TapKind().results(out);
  EXPECT_EQ(j.at("frf_source"), "file");
  EXPECT_EQ(j.at("frf_input"), "tap/x/frf.csv");
  EXPECT_FALSE(j.contains("hits"));
  EXPECT_FALSE(j.contains("hits_used"));
  EXPECT_FALSE(j.contains("exp_window_tau_s"));
  EXPECT_EQ(j.at("modes").size(), a.modes.size());
  EXPECT_EQ(j.at("frf_csv"), "tap/x/frf.csv");
  EXPECT_EQ(j.at("frf_uff"), "tap/x/frf.uff");
  // The figure's files are named by the report (results_json `figures`), not by the kind.
  EXPECT_FALSE(j.contains("figure_data"));
  const nlohmann::json k = TapKind().results(*record_);
  EXPECT_EQ(k.at("frf_source"), "hits");
  EXPECT_EQ(k.at("hits_used"), 5);

  // The hammer mode the cut tests take is the same.
  CampaignValues va, vb;
  TapKind().publish(*record_, va);
  TapKind().publish(out, vb);
  ASSERT_NE(va.first<frf::Mode>(value::kHammerModeX), nullptr);
  ASSERT_NE(vb.first<frf::Mode>(value::kHammerModeX), nullptr);
  EXPECT_NEAR(vb.first<frf::Mode>(value::kHammerModeX)->fn_hz /
                  va.first<frf::Mode>(value::kHammerModeX)->fn_hz,
              1.0, 1e-6);
}

TEST_F(RealTapFrfInput, AccelerancePolarSemicolonExportGivesTheSameModes) {
  ASSERT_NE(record_, nullptr);
  const TapOutcome& a = record_->result_of<TapOutcome>();
  // The lab's own export: accelerance (m/s^2)/N as magnitude and phase in degrees, ';' and
  // decimal comma, a header block; no coherence column (taken as 1: same candidates here,
  // every peak of this record has coherence > 0.99 ... but not every bin, so compare loosely).
  TempDir dir;
  {
    std::filesystem::create_directories(dir.path() / "lab");
    std::ofstream o(dir.path() / "lab/export.csv");
    o << "Export of FRF 1X:1X\nUnits: (m/s^2)/N\nFrequency (Hz);Magnitude;Phase (deg)\n";
    char buf[128];
    for (Eigen::Index i = 0; i < a.f_hz.size(); ++i) {
      const double w = 2.0 * M_PI * a.f_hz[i];
      const std::complex<double> acc = -w * w * a.h1[i];
      std::snprintf(buf, sizeof buf, "%.17g;%.17g;%.17g\n", a.f_hz[i], std::abs(acc),
                    std::arg(acc) * 180.0 / M_PI);
      std::string row(buf);
      for (auto& c : row) c = c == '.' ? ',' : c;
      o << row;
    }
  }
  const TestSpec t =
      frf_test(dir, "lab", "kind: tap\naxis: x\nresponse: acceleration\nfrf: {file: export.csv}\n");
  const TestOutcome out = run(t);
  ASSERT_TRUE(out.status.ok()) << out.status.message;
  const TapOutcome& b = out.result_of<TapOutcome>();
  EXPECT_FALSE(b.has_coherence);
  EXPECT_LT((b.h1 - a.h1).cwiseAbs().maxCoeff(), 1e-12 * a.h1.cwiseAbs().maxCoeff());
  ASSERT_TRUE(b.fit_ok) << b.fit_message;
  // Its figure has no H2 and no coherence panel; its frf.csv no H2 and no coherence columns.
  const render::Figure fig = tap_frf_figure(b);
  EXPECT_NO_THROW(render::validate(fig));
  ASSERT_EQ(fig.panels.size(), 2u);
  EXPECT_EQ(fig.panels[0].series.size(), 2u);  // measured, fit
  EXPECT_EQ(fig.panels[1].x_label, "frequency [Hz]");
  write_tap_frf_csv(b, "lab", dir.path() / "out/frf.csv");
  {
    std::ifstream in(dir.path() / "out/frf.csv");
    std::string line;
    while (std::getline(in, line) && line.rfind("# ", 0) == 0) {
    }
    EXPECT_EQ(line, "f_hz,re,im,fit_re,fit_im");
  }
  // Every mode of the time-record fit is found from the export (coherence 1 may add some).
  for (const auto& m : a.modes) {
    double best = 1e9;
    for (const auto& n : b.modes) best = std::min(best, std::abs(n.fn_hz - m.fn_hz));
    EXPECT_LT(best, 0.5 * a.df_hz) << m.fn_hz << " Hz";
  }
}

TEST_F(RealTapFrfInput, UffOfTheHammerFrfGivesTheSameModes) {
  ASSERT_NE(record_, nullptr);
  const TapOutcome& a = record_->result_of<TapOutcome>();
  TempDir dir;
  write_tap_frf_uff(a, "tap/x", "x", dir.path() / "u/frf.uff");
  std::vector<std::string> errors;
  const TestSpec t0 =
      frf_test(dir, "u", "kind: tap\naxis: x\nresponse: displacement\nfrf: {file: frf.uff}\n");
  // Three FRF records (H1, H2, fit): which one must be said.
  expect_input_error(
      [&] { run_tap_test(t0, {}); },
      "u/test.yaml: key 'frf.record' absent, but u/frf.uff holds 3 FRF records: say which (1-3)");
  const TestSpec t = frf_test(
      dir, "u", "kind: tap\naxis: x\nresponse: displacement\nfrf: {file: frf.uff, record: 1}\n");
  const TestOutcome out = run(t);
  ASSERT_TRUE(out.status.ok()) << out.status.message;
  const TapOutcome& b = out.result_of<TapOutcome>();
  EXPECT_TRUE(b.has_coherence);  // the coherence record of the same nodes
  // ASCII UFF58 holds the ordinate to 13 significant digits but the abscissa start and step to
  // 6 (record 7, E13.5): this record's step 25600/L Hz is not a 6-digit number, so every
  // frequency moves by up to ~5e-6 relative, and the modes with it.
  ASSERT_TRUE(b.fit_ok) << b.fit_message;
  ASSERT_EQ(b.modes.size(), a.modes.size());
  for (std::size_t i = 0; i < a.modes.size(); ++i) {
    EXPECT_NEAR(b.modes[i].fn_hz / a.modes[i].fn_hz, 1.0, 1e-5) << "mode " << i + 1;
    EXPECT_NEAR(b.modes[i].zeta / a.modes[i].zeta, 1.0, 1e-3) << "mode " << i + 1;
  }
}

TEST(TapFrfInput, BadKeysAndFilesNameTheFileAndKey) {
  TempDir dir;
  std::vector<std::string> errors;
  frf_test(dir, "a",
           "kind: tap\naxis: x\nresponse: displacement\nhits: auto\ndata: {file: h.csv}\n"
           "frf: {file: frf.xlsx, delimiter: '|', decimal: ',', record: 0, colour: red}\n",
           &errors);
  EXPECT_EQ(errors, (std::vector<std::string>{
                        "a/test.yaml: key 'frf.file' 'frf.xlsx': unsupported FRF format (use text "
                        ".csv, .txt, .tsv, .dat, .asc, .frf or UFF58 .uff, .unv)",
                        "a/test.yaml: key 'frf.delimiter' '|': must be ',', ';', tab or whitespace",
                        "a/test.yaml: key 'frf.record' must be a whole number >= 1",
                        "a/test.yaml: key 'hits' not used with frf (a measured FRF has no hits)",
                        "a/test.yaml: key 'data' not used with frf: give a time record with hits "
                        "(data) or a measured FRF (frf), not both"}));

  const TestSpec missing =
      frf_test(dir, "b", "kind: tap\naxis: x\nresponse: displacement\nfrf: {file: nope.csv}\n");
  expect_input_error([&] { run_tap_test(missing, {}); },
                     "b/test.yaml: key 'frf.file' 'nope.csv': file not found");

  dir.write("c/frf.csv", "f_hz,re,im\n10,1e-6,0\n20,2e-6,0\n30,abc,0\n40,1e-6,0\n");
  const TestSpec bad =
      frf_test(dir, "c", "kind: tap\naxis: x\nresponse: displacement\nfrf: {file: frf.csv}\n");
  expect_input_error(
      [&] { run_tap_test(bad, {}); },
      "c/frf.csv line 4, column 2 (real): 'abc' is not a number (',' delimiter, "
      "decimal '.') [c/test.yaml key 'frf.file'; frf.delimiter, frf.decimal state the dialect]");
  const TestSpec rec = frf_test(
      dir, "c", "kind: tap\naxis: x\nresponse: displacement\nfrf: {file: frf.csv, record: 2}\n");
  expect_input_error([&] { run_tap_test(rec, {}); },
                     "c/test.yaml: key 'frf.record' is only for a UFF58 file (.uff, .unv)");

  dir.write("d/frf.uff", "    -1\n    58\n");
  const TestSpec uff =
      frf_test(dir, "d", "kind: tap\naxis: x\nresponse: displacement\nfrf: {file: frf.uff}\n");
  try {
    run_tap_test(uff, {});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "d/frf.uff: dataset 58 #1, record 1: missing (the dataset ends early) [d/test.yaml "
              "key 'frf.file']");
  }

  // No FRF record in a UFF58 file.
  uff::Function58 f;
  f.function_type = uff::kTimeResponse;
  f.dx = 0.001;
  f.real = Eigen::VectorXd::Ones(8);
  std::filesystem::create_directories(dir.path() / "e");
  uff::write_uff58(dir.path() / "e/frf.uff", {f});
  const TestSpec none =
      frf_test(dir, "e", "kind: tap\naxis: x\nresponse: displacement\nfrf: {file: frf.uff}\n");
  expect_input_error(
      [&] { run_tap_test(none, {}); },
      "e/frf.uff: no FRF record (dataset 58 function type 4) among its 1 dataset 58 record(s) "
      "[e/test.yaml key 'frf.file']");
}

}  // namespace
}  // namespace chatterlab::app
