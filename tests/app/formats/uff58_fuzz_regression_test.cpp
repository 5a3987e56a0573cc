// Inputs the fuzz targets (fuzz/, docs/fuzzing.md) found or that target their findings: each
// must end in an InputError naming the record, never in a huge allocation or a crash.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "analysis/common/summary.h"
#include "app/formats/uff58.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app::uff {
namespace {

using chatterlab::testing::TempDir;

std::string text_of(const std::filesystem::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string message_of(const std::filesystem::path& f) {
  try {
    read_uff58(f);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// A 48-point time record whose record 7 number of points is replaced by `count`.
std::filesystem::path record_claiming(const TempDir& dir, const std::string& name, bool binary,
                                      const std::string& count) {
  Function58 f;
  f.id1 = "force";
  f.dx = 1e-3;
  f.real = Eigen::VectorXd::LinSpaced(48, 0.0, 1.0);
  const auto file = dir.path() / name;
  write_uff58(file, {f}, binary);
  std::string text = text_of(file);
  const std::string r7 = "         4        48         1";
  const auto at = text.find(r7);
  EXPECT_NE(at, std::string::npos);
  if (at == std::string::npos) return file;
  std::string field = count;
  field.insert(0, field.size() < 10 ? 10 - field.size() : 0, ' ');
  text.replace(at, r7.size(), "         4" + field + "         1");
  std::ofstream(file, std::ios::binary) << text;
  return file;
}

TEST(Uff58FuzzRegression, AsciiCountBeyondTheFileIsRefusedBeforeAllocating) {
  // Found by uff58_fuzz: a 3.6 kB file claiming 999999999 points reserved 8 GB.
  const TempDir dir;
  const auto file = record_claiming(dir, "big.uff", false, "999999999");
  const std::string m = message_of(file);
  EXPECT_NE(m.find("record 7"), std::string::npos) << m;
  EXPECT_NE(m.find("number of points 999999999"), std::string::npos) << m;
  EXPECT_NE(m.find("more than the file's"), std::string::npos) << m;
}

TEST(Uff58FuzzRegression, BinaryCountWhoseByteSizeWrapsIsRefused) {
  // 2^61 points of doubles are 2^64 bytes, 0 after wrapping: never compared as a size.
  const TempDir dir;
  const auto file = record_claiming(dir, "wrap.uff", true, "2305843009213693952");
  const std::string m = message_of(file);
  EXPECT_NE(m.find("record 7"), std::string::npos) << m;
}

}  // namespace
}  // namespace chatterlab::app::uff
