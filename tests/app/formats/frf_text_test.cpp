// FRF text files (app/formats/frf_text.h): the accepted layouts give the same FRF, the ordinate
// conversion, and every message names the file and the line.
#include "app/formats/frf_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <fstream>
#include <string>

#include "analysis/common/constants.h"
#include "render/temp_dir.h"
#include "tests/support/expect_input_error.h"

namespace chatterlab::app::frf_text {
namespace {

using chatterlab::testing::expect_input_error;

class FrfText : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto p = dir_.path() / name;
    std::ofstream(p) << text;
    return p;
  }
  render::TempDir dir_{"frf-text-test"};
};

// The reference: three rows at 10, 20, 30 Hz.
void expect_reference(const FrfTable& t) {
  ASSERT_EQ(t.f_hz.size(), 3);
  EXPECT_DOUBLE_EQ(t.f_hz[0], 10.0);
  EXPECT_DOUBLE_EQ(t.f_hz[2], 30.0);
  EXPECT_DOUBLE_EQ(t.df_hz, 10.0);
  EXPECT_NEAR(t.h[0].real(), 1.5e-6, 1e-18);
  EXPECT_NEAR(t.h[0].imag(), -2.5e-6, 1e-18);
  EXPECT_NEAR(t.h[2].real(), -0.5e-6, 1e-18);
  EXPECT_NEAR(t.h[2].imag(), 0.25e-6, 1e-18);
}

TEST_F(FrfText, PlainCsvWithHeader) {
  const auto p =
      write("frf.csv", "f_hz,re,im\n10,1.5e-6,-2.5e-6\n20,1e-6,-1e-6\n30,-0.5e-6,0.25e-6\n");
  const FrfTable t = read_frf_text(p, "tap/frf.csv");
  expect_reference(t);
  EXPECT_EQ(t.delimiter, ',');
  EXPECT_EQ(t.columns, "'f_hz', 're', 'im' by the header on line 1");
  EXPECT_EQ(t.coherence.size(), 0);
}

TEST_F(FrfText, SemicolonDecimalCommaUnitsInHeadersAndExtraColumns) {
  const auto p =
      write("frf.csv",
            "Messung 3;;;\n"
            "Frequenz (Hz);Koh.;Realteil [m/N];Imaginärteil [m/N]\n"
            "10,0;0,99;1,5e-6;-2,5e-6\n20,0;0,98;1e-6;-1e-6\n30,0;0,97;-0,5e-6;0,25e-6\n");
  // German names: frequenz, real..., imag... are recognised; "Koh." is not (no coherence).
  const FrfTable t = read_frf_text(p, "frf.csv");
  expect_reference(t);
  EXPECT_EQ(t.decimal, ',');
  EXPECT_EQ(t.delimiter, ';');
  EXPECT_EQ(t.coherence.size(), 0);
  EXPECT_TRUE(t.warnings.empty());

  const auto q =
      write("frf2.csv",
            "Frequency (Hz);Coherence;Real (m/N);Imag (m/N)\n"
            "10,0;0,99;1,5e-6;-2,5e-6\n20,0;0,98;1e-6;-1e-6\n30,0;0,97;-0,5e-6;0,25e-6\n");
  const FrfTable u = read_frf_text(q, "frf2.csv");
  expect_reference(u);
  ASSERT_EQ(u.coherence.size(), 3);
  EXPECT_DOUBLE_EQ(u.coherence[1], 0.98);
}

TEST_F(FrfText, WhitespaceExportWithHeaderBlock) {
  const auto p = write("frf.txt",
                       "FRF export\n"
                       "Point 1X : 1X   Units: m/N\n"
                       "Date 2024-05-02\n"
                       "\n"
                       "  Freq(Hz)    Real(m/N)     Imag(m/N)\n"
                       "  10.000   1.5000E-06  -2.5000E-06\n"
                       "  20.000   1.0000E-06  -1.0000E-06\r\n"
                       "  30.000  -5.0000E-07   2.5000E-07\n");
  const FrfTable t = read_frf_text(p, "frf.txt");
  expect_reference(t);
  EXPECT_EQ(t.delimiter, ' ');
  EXPECT_EQ(t.columns, "'Freq(Hz)', 'Real(m/N)', 'Imag(m/N)' by the header on line 5");

  // The same without a line of names (a header of a different width): by position.
  const auto q = write("frf2.txt",
                       "% title\nFrequency  Real part  Imaginary part\n10\t1.5e-6\t-2.5e-6\n"
                       "20\t1e-6\t-1e-6\n30\t-0.5e-6\t0.25e-6\n");
  const FrfTable u = read_frf_text(q, "frf2.txt");
  expect_reference(u);
  EXPECT_NE(u.columns.find("first three"), std::string::npos);
}

TEST_F(FrfText, MagnitudePhaseInDegreesRadiansAndDb) {
  const std::complex<double> h0(1.5e-6, -2.5e-6), h1(1e-6, -1e-6), h2(-0.5e-6, 0.25e-6);
  auto row = [](double f, std::complex<double> h, double mag_scale, double ph_scale) {
    return std::to_string(f) + "," + std::to_string(mag_scale * std::abs(h) * 1e6) + "e-6," +
           std::to_string(std::arg(h) * ph_scale) + "\n";
  };
  std::string deg = "frequency,magnitude,phase (deg)\n";
  deg += row(10, h0, 1, kRadToDeg) + row(20, h1, 1, kRadToDeg) + row(30, h2, 1, kRadToDeg);
  const FrfTable t = read_frf_text(write("deg.csv", deg), "deg.csv");
  EXPECT_NEAR(std::abs(t.h[0] - h0), 0, 1e-11);
  EXPECT_NEAR(std::abs(t.h[2] - h2), 0, 1e-11);

  std::string rad = "freq_hz,mag,phase_rad\n";
  rad += row(10, h0, 1, 1) + row(20, h1, 1, 1) + row(30, h2, 1, 1);
  const FrfTable r = read_frf_text(write("rad.csv", rad), "rad.csv");
  EXPECT_NEAR(std::abs(r.h[1] - h1), 0, 1e-11);

  const FrfTable d = read_frf_text(
      write("db.csv", "f,Magnitude (dB),Phase\n10,-120,0\n20,-100,90\n30,-80,180\n"), "db.csv");
  EXPECT_NEAR(d.h[0].real(), 1e-6, 1e-15);
  EXPECT_NEAR(d.h[1].imag(), 1e-5, 1e-14);
  EXPECT_NEAR(d.h[2].real(), -1e-4, 1e-13);
}

TEST_F(FrfText, ZeroHzRowDroppedAndKilohertz) {
  const FrfTable t = read_frf_text(
      write("k.csv",
            "f (kHz),re,im\n0,0,0\n0.01,1.5e-6,-2.5e-6\n0.02,1e-6,-1e-6\n0.03,-0.5e-6,0.25e-6\n"),
      "k.csv");
  expect_reference(t);
  ASSERT_EQ(t.warnings.size(), 1u);
  EXPECT_EQ(t.warnings[0], "k.csv line 2: the 0 Hz row is not used");
}

TEST_F(FrfText, StatedDialectIsObeyed) {
  const auto p = write("a.csv", "f;re;im\n10;1,5e-6;-2,5e-6\n20;1e-6;-1e-6\n30;-0,5e-6;0,25e-6\n");
  ReadOptions o;
  o.delimiter = ';';
  o.decimal = ',';
  expect_reference(read_frf_text(p, "a.csv", o));
  o.decimal = '.';
  expect_input_error([&] { read_frf_text(p, "a.csv", o); },
                     "a.csv line 4, column 2 (real): '-0,5e-6' is not a number (';' delimiter, "
                     "decimal '.')");
  expect_input_error([&] { read_frf_text(write("b.csv", "f;re;im\n1;2,5;3,5\n"), "b.csv", o); },
                     "b.csv: no data row of at least three numbers (frequency, real, imaginary) "
                     "in the stated dialect (';' delimiter, decimal '.')");
}

TEST_F(FrfText, ErrorsNameFileAndLine) {
  expect_input_error(
      [&] { read_frf_text(write("a.csv", "f_hz,re,im\n10,1,2\n20,x,2\n30,1,2\n"), "t/a.csv"); },
      "t/a.csv line 3, column 2 (real): 'x' is not a number (',' delimiter, decimal '.')");
  expect_input_error(
      [&] { read_frf_text(write("b.csv", "f_hz,re,im\n10,1,2\n20,1\n30,1,2\n"), "b.csv"); },
      "b.csv line 3: 2 fields, the first data row (line 2) has 3 (',' delimiter, decimal '.')");
  expect_input_error(
      [&] { read_frf_text(write("c.csv", "f_hz,re,im\n10,1,2\n30,1,2\n20,1,2\n"), "c.csv"); },
      "c.csv line 4: frequencies must increase (this row's is not above the previous row's)");
  expect_input_error(
      [&] {
        read_frf_text(write("d.csv", "f_hz,re,im\n10,1,2\n20,1,2\n40,1,2\n50,1,2\n"), "d.csv");
      },
      "d.csv line 3: frequency 20 Hz is off the even grid (10 Hz + k x 13.3333 Hz); FRF rows "
      "must be evenly spaced");
  expect_input_error(
      [&] { read_frf_text(write("e.csv", "f_hz,re,im\n10,1,2\n20,1,2\n"), "e.csv"); },
      "e.csv: 2 frequency row(s) above 0 Hz; an FRF needs at least 3");
  expect_input_error([&] { read_frf_text(write("f.csv", "force,response\n1,2\n"), "f.csv"); },
                     "f.csv: no data row of at least three numbers (frequency, real, imaginary)");
  expect_input_error(
      [&] {
        read_frf_text(write("g.csv", "f,re,im,coh\n10,1,2,0.9\n20,1,2,1.5\n30,1,2,1\n"), "g.csv");
      },
      "g.csv line 3, column 4 (coherence): 1.5 is outside [0, 1]");
  expect_input_error([&] { read_frf_text(dir_.path() / "none.csv", "none.csv"); },
                     "none.csv: file not found or not readable");
}

TEST_F(FrfText, ToReceptance) {
  Eigen::VectorXd f(1);
  f << 100.0;
  Eigen::VectorXcd h(1);
  h << std::complex<double>(2.0, 1.0);
  const double w = kTwoPi * 100.0;
  EXPECT_EQ(to_receptance(f, h, Ordinate::kReceptance)[0], h[0]);
  EXPECT_NEAR(std::abs(to_receptance(f, h, Ordinate::kAccelerance)[0] - h[0] / (-w * w)), 0, 1e-18);
  EXPECT_NEAR(
      std::abs(to_receptance(f, h, Ordinate::kMobility)[0] - h[0] / std::complex<double>(0, w)), 0,
      1e-18);
}

TEST_F(FrfText, WriteCsvRoundTripsExactly) {
  Eigen::VectorXd f(3), re(3), im(3), c(3);
  f << 1.0 / 3.0, 2.0 / 3.0, 1.0;
  re << 1e-7 / 3.0, std::nan(""), -2.0 / 7.0;
  im << 0.1, 0.2, 0.3;
  c << 1, 0.5, 0.25;
  const auto p = dir_.path() / "w.csv";
  write_csv(p, {"a comment"}, {{"f_hz", f}, {"re", re}, {"im", im}, {"coherence", c}});
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "# a comment");
  std::getline(in, line);
  EXPECT_EQ(line, "f_hz,re,im,coherence");
  std::getline(in, line);
  std::getline(in, line);
  EXPECT_EQ(line, "0.66666666666666663,,0.20000000000000001,0.5");
  re[1] = 5.0;
  write_csv(p, {}, {{"f_hz", f}, {"re", re}, {"im", im}, {"coherence", c}});
  const FrfTable t = read_frf_text(p, "w.csv");
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(t.f_hz[i], f[i]);
    EXPECT_EQ(t.h[i].real(), re[i]);
    EXPECT_EQ(t.h[i].imag(), im[i]);
    EXPECT_EQ(t.coherence[i], c[i]);
  }
}

}  // namespace
}  // namespace chatterlab::app::frf_text
