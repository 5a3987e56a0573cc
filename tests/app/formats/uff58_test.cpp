// Universal File Format dataset 58/58b: the pyuff sample files (shared/data/uff-pyuff-samples,
// read only), write -> read round trips in both forms, and the messages of malformed files.
#include "app/formats/uff58.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "analysis/common/summary.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app::uff {
namespace {

using chatterlab::testing::TempDir;

const std::string kSamples = std::string(CHATTERLAB_SHARED_DATA) + "/uff-pyuff-samples";

// The value a text field printed with `fmt` reads back as: "exact to the printed precision".
double printed(double v, const char* fmt) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, v);
  return std::strtod(buf, nullptr);
}

std::string message_of(const std::filesystem::path& f) {
  try {
    read_uff58(f);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Uff58, PyuffAsciiAndBinarySamplesHoldTheSameMicrophoneRecord) {
  const auto a = read_uff58(kSamples + "/Sample_UFF58_ascii.uff");
  const auto b = read_uff58(kSamples + "/Sample_UFF58b_bin.uff");
  ASSERT_EQ(a.size(), 1u);
  ASSERT_EQ(b.size(), 1u);
  for (const auto* f : {&a[0], &b[0]}) {
    EXPECT_EQ(f->id1, "Mic 01.0Scalar");  // record 1 as the file holds it
    EXPECT_EQ(f->id3, "18-Apr-16 13:49:58");
    EXPECT_EQ(f->response_entity, "Mic 01");
    EXPECT_EQ(f->response_direction, 1);
    EXPECT_EQ(f->function_type, kTimeResponse);
    EXPECT_FALSE(f->complex_ordinate);
    EXPECT_EQ(f->samples(), 79292);
    EXPECT_EQ(f->x.size(), 0);  // even abscissa
    EXPECT_EQ(f->x_start, 0.0);
    EXPECT_EQ(f->dx, 1.52588e-05);  // the same text in both headers, so the same double
    EXPECT_EQ(f->x_label, "time");
    EXPECT_EQ(f->x_unit, "s");
    EXPECT_EQ(f->y_label, "Pressure");
    EXPECT_EQ(f->y_unit, "Pa");
    EXPECT_EQ(f->z_label, "");  // NONE
  }
  // The binary file holds IEEE single-precision values (record 7 type 2, 317,168 bytes); the
  // ASCII file prints 6 significant digits (E13.5). Printed the same way, 78,642 of the 79,292
  // binary samples give the ASCII text exactly; the other 650 differ by one unit in the sixth
  // digit (the writer of the ASCII file rounded from values other than these floats), so both
  // readers return every sample the file holds and the files agree to their printed precision.
  const Eigen::VectorXd& x = a[0].real;
  const Eigen::VectorXd& y = b[0].real;
  EXPECT_EQ(x[0], -1.47553e-02);
  int same_text = 0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (printed(y[i], "%.5E") == x[i]) ++same_text;
    const double unit = std::pow(10.0, std::floor(std::log10(std::abs(x[i]))) - 5);
    ASSERT_LE(std::abs(x[i] - y[i]), unit) << "sample " << i;
    ASSERT_EQ(static_cast<double>(static_cast<float>(y[i])), y[i]) << "sample " << i;
  }
  EXPECT_EQ(same_text, 78642);
}

TEST(Uff58, PyuffPsdDatasetIsAComplexUnevenSpectrum) {
  const auto f = read_uff58(kSamples + "/sample_dataset58_psd.uff");
  ASSERT_EQ(f.size(), 1u);
  const Function58& p = f[0];
  EXPECT_EQ(p.id1, "Power Spectral Density (PSD)");
  EXPECT_EQ(p.id4, "Channel 1");
  EXPECT_EQ(p.function_type, kPowerSpectralDensity);  // record 6 field 1 = 9
  EXPECT_EQ(p.response_entity, "Pilot 1");
  EXPECT_TRUE(p.complex_ordinate);  // record 7 type 5: complex single precision
  ASSERT_EQ(p.samples(), 3201);
  ASSERT_EQ(p.x.size(), 3201);  // uneven abscissa: x, re, im per point
  EXPECT_EQ(p.x[0], 0.0);
  EXPECT_EQ(p.x[3200], 3200.0);
  EXPECT_EQ(p.values[1], std::complex<double>(1.255863e-06, 0.0));
  EXPECT_EQ(p.values[3200], std::complex<double>(2.634827e-10, 0.0));
  EXPECT_EQ(p.x_unit, "Hz");
  EXPECT_EQ(p.y_unit, "g\xb2/Hz");  // Latin-1 superscript two, bytes kept
  EXPECT_EQ(p.sample_rate_hz(), 0.0);
}

Function58 time_record(const std::string& id, int n, double dx) {
  Function58 f;
  f.id1 = id;
  f.id3 = "01-Dec-26 10:00:00";
  f.response_entity = "node";
  f.response_node = 12;
  f.response_direction = -3;
  f.dx = dx;
  f.x_start = 0.5;
  f.real.resize(n);
  for (int i = 0; i < n; ++i) f.real[i] = std::sin(0.37 * i) * std::pow(10.0, i % 7 - 3) / 3.0;
  f.y_label = "Acceleration";
  f.y_unit = "m/s^2";
  return f;
}

Function58 frf_record(int n, bool uneven) {
  Function58 f;
  f.id1 = "H tip x / x";
  f.function_type = kFrf;
  f.response_entity = "tip";
  f.response_node = 1;
  f.response_direction = 1;
  f.reference_entity = "tip";
  f.reference_node = 1;
  f.reference_direction = 1;
  f.complex_ordinate = true;
  f.values.resize(n);
  for (int i = 0; i < n; ++i) {
    f.values[i] = {1e-6 / (1.0 + i) - 2.5e-7 * i, -std::exp(-0.1 * i) / 7.0};
  }
  if (uneven) {
    f.x.resize(n);
    for (int i = 0; i < n; ++i) f.x[i] = 10.0 * i * i + 0.123456789;
  } else {
    f.x_start = 0.0;
    f.dx = 0.78125;
  }
  f.x_label = "Frequency";
  f.x_unit = "Hz";
  f.y_label = "Displacement";
  f.y_unit = "m";
  f.z_label = "Force";
  f.z_unit = "N";
  return f;
}

void expect_same_header(const Function58& a, const Function58& b, bool binary) {
  EXPECT_EQ(a.id1, b.id1);
  EXPECT_EQ(a.id2, b.id2);
  EXPECT_EQ(a.id3, b.id3);
  EXPECT_EQ(a.function_type, b.function_type);
  EXPECT_EQ(a.response_entity, b.response_entity);
  EXPECT_EQ(a.response_node, b.response_node);
  EXPECT_EQ(a.response_direction, b.response_direction);
  EXPECT_EQ(a.reference_entity, b.reference_entity);
  EXPECT_EQ(a.reference_node, b.reference_node);
  EXPECT_EQ(a.reference_direction, b.reference_direction);
  EXPECT_EQ(a.complex_ordinate, b.complex_ordinate);
  ASSERT_EQ(a.samples(), b.samples());
  // Record 7 prints the abscissa start and step as E13.5 in both forms.
  EXPECT_EQ(b.x_start, printed(a.x_start, "%.5E"));
  EXPECT_EQ(b.dx, printed(a.dx, "%.5E"));
  EXPECT_EQ(a.x_label, b.x_label);
  EXPECT_EQ(a.x_unit, b.x_unit);
  EXPECT_EQ(a.y_label, b.y_label);
  EXPECT_EQ(a.y_unit, b.y_unit);
  EXPECT_EQ(a.z_label, b.z_label);
  EXPECT_EQ(a.z_unit, b.z_unit);
  ASSERT_EQ(a.x.size(), b.x.size());
  for (Eigen::Index i = 0; i < a.x.size(); ++i) {
    // An uneven abscissa: E13.5 in text (the format's layout), raw doubles in 58b.
    EXPECT_EQ(b.x[i], binary ? a.x[i] : printed(a.x[i], "%.5E")) << i;
  }
}

TEST(Uff58, WriteReadRoundTripsAsciiAndBinaryRealAndComplex) {
  TempDir d;
  const std::vector<Function58> in = {time_record("force", 1001, 1.0 / 25600),
                                      time_record("response", 1001, 1.0 / 25600),
                                      frf_record(257, false), frf_record(33, true)};
  for (const bool binary : {false, true}) {
    const auto file = d.path() / (binary ? "b.uff" : "a.uff");
    write_uff58(file, in, binary);
    const auto out = read_uff58(file);
    ASSERT_EQ(out.size(), in.size());
    for (std::size_t k = 0; k < in.size(); ++k) {
      SCOPED_TRACE((binary ? "58b, function " : "58, function ") + std::to_string(k));
      expect_same_header(in[k], out[k], binary);
      // Values: E20.12 in text, raw doubles (exact) in binary.
      const auto same = [&](double a, double b) { return b == (binary ? a : printed(a, "%.12E")); };
      for (Eigen::Index i = 0; i < in[k].samples(); ++i) {
        if (in[k].complex_ordinate) {
          ASSERT_TRUE(same(in[k].values[i].real(), out[k].values[i].real())) << i;
          ASSERT_TRUE(same(in[k].values[i].imag(), out[k].values[i].imag())) << i;
        } else {
          ASSERT_TRUE(same(in[k].real[i], out[k].real[i])) << i;
        }
      }
    }
  }
  // The FRF's denominator (record 10) and an empty text field written as NONE.
  const auto back = read_uff58(d.path() / "a.uff");
  EXPECT_EQ(back[2].z_label, "Force");
  EXPECT_EQ(back[2].z_unit, "N");
  EXPECT_EQ(back[0].z_unit, "");
  EXPECT_EQ(back[0].id2, "");
}

TEST(Uff58, OtherDatasetsAreSkipped) {
  TempDir d;
  const auto f = d.path() / "two.uff";
  write_uff58(f, {time_record("a", 5, 0.001)});
  std::ifstream in(f);
  std::stringstream s;
  s << in.rdbuf();
  const std::string dataset_151 =
      "    -1\n   151\nmodel\ndescription\n    -1\n";  // a header dataset of another kind
  d.write("two.uff", dataset_151 + s.str() + s.str());
  const auto out = read_uff58(f);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].id1, "a");
}

// A valid ASCII record with `r7` as record 7 and `data` as its values.
std::string ascii_record(const std::string& r7, const std::string& data) {
  return "    -1\n    58\nid\nNONE\nNONE\nNONE\nNONE\n"
         "    1         0    0         0 ch                 0   1 NONE               0   0\n" +
         r7 + "\n" +
         "        17    0    0    0 Time                 s                   \n"
         "         0    0    0    0 NONE                 NONE                \n"
         "         0    0    0    0 NONE                 NONE                \n"
         "         0    0    0    0 NONE                 NONE                \n" +
         data + "    -1\n";
}

TEST(Uff58, MalformedFilesNameTheFileAndTheDataset) {
  TempDir d;
  const std::string good =
      ascii_record("         2         3         1  0.00000E+00  1.00000E-03  0.00000E+00",
                   "  1.00000E+00 -2.00000E+00  3.00000E+00\n");
  const auto f1 = d.write("ok.uff", good);
  ASSERT_EQ(read_uff58(f1)[0].real[2], 3.0);

  const auto f2 = d.write(
      "type.uff",
      good + ascii_record("         3         3         1  0.00000E+00  1.00000E-03  0.00000E+00",
                          "  1.00000E+00 -2.00000E+00  3.00000E+00\n"));
  EXPECT_EQ(message_of(f2), f2.string() +
                                ": dataset 58 #2, record 7: ordinate data type 3: must be 2 or 4 "
                                "(real single or double), 5 or 6 (complex)");
  const auto f3 =
      d.write("short.uff",
              ascii_record("         2         4         1  0.00000E+00  1.00000E-03  0.00000E+00",
                           "  1.00000E+00 -2.00000E+00  3.00000E+00\n"));
  EXPECT_EQ(message_of(f3), f3.string() +
                                ": dataset 58 #1, record 12: 3 values, record 7 implies 4 (4 "
                                "points x 1 values)");
  const auto f4 =
      d.write("text.uff",
              ascii_record("         2         3         1  0.00000E+00  1.00000E-03  0.00000E+00",
                           "  1.00000E+00 -2.0000xE+00  3.00000E+00\n"));
  EXPECT_EQ(message_of(f4), f4.string() +
                                ": dataset 58 #1, record 12: '-2.0000xE+00' on data line 1 is not "
                                "a number");
  const auto f5 =
      d.write("dx.uff",
              ascii_record("         2         3         1  0.00000E+00  0.00000E+00  0.00000E+00",
                           "  1.00000E+00 -2.00000E+00  3.00000E+00\n"));
  EXPECT_EQ(message_of(f5), f5.string() +
                                ": dataset 58 #1, record 7: abscissa increment 0.00000E+00: must "
                                "be > 0 for an even abscissa");
  std::string unterminated = good.substr(0, good.size() - 7);
  const auto f6 = d.write("cut.uff", unterminated);
  EXPECT_EQ(message_of(f6), f6.string() +
                                ": dataset 58 #1, record 12: no \"-1\" line ends the dataset "
                                "(truncated file?)");
  const auto f7 = d.write("head.uff", "    -1\n    58\nid\nNONE\n");
  EXPECT_EQ(message_of(f7),
            f7.string() + ": dataset 58 #1, record 3: missing (the dataset ends early)");

  // 58b: a truncated data block and a byte ordering the format does not define.
  const auto b = d.path() / "b.uff";
  write_uff58(b, {time_record("x", 100, 0.001)}, true);
  std::ifstream in(b, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  const std::string bin = s.str();
  const auto f8 = d.write("cut_b.uff", bin.substr(0, bin.size() - 400));
  EXPECT_EQ(message_of(f8), f8.string() +
                                ": dataset 58 #1, record 12: the file ends inside the binary data "
                                "block (407 of 800 bytes)");
  std::string order = bin;
  order[19] = '3';  // "    58b     1": the byte-ordering field
  const auto f9 = d.write("order_b.uff", order);
  EXPECT_EQ(message_of(f9), f9.string() +
                                ": dataset 58 #1, 58b header: byte ordering 3: must be 1 (little "
                                "endian) or 2 (big endian)");
  EXPECT_EQ(message_of(d.path() / "none.uff"), (d.path() / "none.uff").string() + ": cannot open");
}

TEST(Uff58, BigEndianBinaryIsRead) {
  // The same record as doubles in big-endian order (byte ordering 2).
  TempDir d;
  const auto b = d.path() / "le.uff";
  const Function58 f = time_record("x", 10, 0.5);
  write_uff58(b, {f}, true);
  std::ifstream in(b, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  std::string bin = s.str();
  bin[19] = '2';
  const std::size_t data = bin.size() - 7 - 80;  // before "    -1\n"
  for (std::size_t i = 0; i < 10; ++i) {
    std::reverse(bin.begin() + static_cast<std::ptrdiff_t>(data + 8 * i),
                 bin.begin() + static_cast<std::ptrdiff_t>(data + 8 * i + 8));
  }
  const auto be = d.write("be.uff", bin);
  const auto out = read_uff58(be);
  ASSERT_EQ(out.size(), 1u);
  for (Eigen::Index i = 0; i < 10; ++i) EXPECT_EQ(out[0].real[i], f.real[i]);
}

}  // namespace
}  // namespace chatterlab::app::uff
