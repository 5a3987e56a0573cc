// An input matfile_fuzz found (fuzz/, docs/fuzzing.md): a v5 variable whose header declares
// more values than the file holds must end in an InputError, not in listing millions of
// columns or allocating petabytes.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "analysis/common/summary.h"
#include "app/formats/matfile.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app::mat {
namespace {

using chatterlab::testing::TempDir;

std::string int32_pair(std::int32_t a, std::int32_t b) {
  std::string s(8, '\0');
  std::memcpy(s.data(), &a, 4);  // v5 files written here are little-endian (x86, arm64)
  std::memcpy(s.data() + 4, &b, 4);
  return s;
}

TEST(MatfileFuzzRegression, DeclaredSizeBeyondTheFileIsRefused) {
  const TempDir dir;
  const auto file = dir.path() / "damaged.mat";
  write_mat(file, {{"M", Eigen::MatrixXd::Ones(3, 2)}});
  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    bytes = s.str();
  }
  // The dimensions subelement: miINT32 (5), 8 bytes, then 3 and 2.
  const std::string dims = int32_pair(5, 8) + int32_pair(3, 2);
  const auto at = bytes.find(dims);
  ASSERT_NE(at, std::string::npos);
  // What the fuzzer found: 1090519080 x 3481666 in a 1.3 kB file.
  bytes.replace(at + 8, 8, int32_pair(1090519080, 3481666));
  std::ofstream(file, std::ios::binary) << bytes;

  for (int call = 0; call < 2; ++call) {
    try {
      if (call == 0) {
        numeric_variables(file);
      } else {
        read_vector(file, "M", 0);
      }
      ADD_FAILURE() << "no InputError (call " << call << ")";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("variable 'M' declares 1090519080 x 3481666 values"), std::string::npos)
          << m;
    }
  }
}

}  // namespace
}  // namespace chatterlab::app::mat
