// An input matfile_fuzz found (fuzz/, docs/fuzzing.md): a v5 variable whose header declares
// more values than the file holds must end in an InputError, not in listing millions of
// columns or allocating petabytes.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "analysis/common/summary.h"
#include "app/core/isolated.h"
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

// The InputError of numeric_variables (call 0) or of read_vector of M's first column (call 1);
// empty when there is none.
std::string error_of(const std::filesystem::path& file, int call) {
  try {
    if (call == 0) {
      numeric_variables(file);
    } else {
      read_vector(file, "M", 0);
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A copy in `dir`, named `name`, of tests/data/matfile/<data> (the tests read copies, so that
// their messages name a path of their own).
std::filesystem::path copy_of_test_file(const TempDir& dir, const char* data, const char* name) {
  const auto file = dir.path() / name;
  std::filesystem::copy_file(std::filesystem::path(CHATTERLAB_TEST_DATA) / "matfile" / data, file);
  return file;
}

std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(MatfileFuzzRegression, DeclaredSizeBeyondTheFileIsRefused) {
  const TempDir dir;
  const auto file = dir.path() / "damaged.mat";
  write_mat(file, {{"M", Eigen::MatrixXd::Ones(3, 2)}});
  std::string bytes = file_bytes(file);
  // The dimensions subelement: miINT32 (5), 8 bytes, then 3 and 2.
  const std::string dims = int32_pair(5, 8) + int32_pair(3, 2);
  const auto at = bytes.find(dims);
  ASSERT_NE(at, std::string::npos);
  // What the fuzzer found: 1090519080 x 3481666 in a 1.3 kB file.
  bytes.replace(at + 8, 8, int32_pair(1090519080, 3481666));
  std::ofstream(file, std::ios::binary) << bytes;

  for (int call = 0; call < 2; ++call) {
    const std::string m = error_of(file, call);
    EXPECT_NE(m.find("variable 'M' declares 1090519080 x 3481666 values"), std::string::npos)
        << "call " << call << ": " << m;
  }
}

// Finding 3: a file without a v5/v7.3 header (the fuzzer's began `2c 00 00 00 00 00 00 00 2e 30
// 20 4d 41 54`) went to libmatio as a v4 file and made it allocate 2.5 GB. Such files are now
// refused before libmatio sees them: a real v4 file (1x1 double 'x', 20-byte header), that
// file's damaged twin, a v5 header of an unknown version, a file shorter than a header; a
// genuine v5 file with a damaged first byte of text is refused too (the text must start
// "MATLAB").
TEST(MatfileFuzzRegression, FilesWithoutAV5OrV73HeaderAreRefusedBeforeLibmatio) {
  const TempDir dir;
  const std::string refused =
      ": not a v5 or v7.3 .mat file (no MAT-file header; v4 files are not read)";
  auto expect_refused = [&](const std::string& name, const std::string& bytes,
                            const std::string& why) {
    const auto file = dir.path() / name;
    std::ofstream(file, std::ios::binary) << bytes;
    try {
      numeric_variables(file);
      ADD_FAILURE() << name << ": no InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), file.string() + why) << name;
    }
  };
  double one = 1.0;
  std::string v4 = int32_pair(0, 1) + int32_pair(1, 0) + int32_pair(2, 0).substr(0, 4) +
                   std::string("x\0", 2) + std::string(8, '\0');
  std::memcpy(v4.data() + v4.size() - 8, &one, 8);
  expect_refused("v4.mat", v4 + std::string(128, '\0'), refused);
  std::string damaged = v4 + std::string(180, '\0');
  damaged[0] = 0x2c;
  expect_refused("damaged-v4.mat", damaged, refused);
  expect_refused("short.mat", "MATLAB 5.0 MAT-file",
                 ": not a v5 or v7.3 .mat file (shorter than the 128-byte MAT-file header)");

  const auto good = dir.path() / "good.mat";
  write_mat(good, {{"M", Eigen::MatrixXd::Ones(3, 2)}});
  const std::string bytes = file_bytes(good);
  ASSERT_EQ(bytes.compare(0, 6, "MATLAB"), 0);
  ASSERT_EQ(numeric_variables(good).size(), 1u);
  std::string version = bytes;
  version[124] = 0x00;  // little-endian 0x0300: no such version
  version[125] = 0x03;
  expect_refused("version.mat", version, refused);
  std::string text = bytes;
  text[0] = 'X';
  expect_refused("text.mat", text, refused);
}

// Finding 7: a v5 file whose matrix's dimensions tag declared 0x4c54414d bytes ("MATL" pasted
// over it) made libmatio allocate 2.5 GB. Element tags are now walked before libmatio: a
// sub-element larger than its matrix, and a matrix larger than the file, are refused naming
// the element; the undamaged file still reads.
TEST(MatfileFuzzRegression, TagsDeclaringMoreThanTheirElementAreRefusedBeforeLibmatio) {
  const TempDir dir;
  const auto good = dir.path() / "good.mat";
  write_mat(good, {{"M", Eigen::MatrixXd::Ones(3, 2)}});
  const std::string bytes = file_bytes(good);
  ASSERT_EQ(numeric_variables(good).size(), 1u);
  std::int32_t matrix_bytes = 0;
  std::memcpy(&matrix_bytes, bytes.data() + 132, 4);  // the first element's tag, at byte 128
  const auto expect = [&](const std::string& name, const std::string& damaged,
                          const std::string& why) {
    const auto file = dir.path() / name;
    std::ofstream(file, std::ios::binary) << damaged;
    for (int call = 0; call < 2; ++call) {
      EXPECT_EQ(error_of(file, call), file.string() + ": " + why) << name << ", call " << call;
    }
  };
  std::string dims = bytes;
  const auto at = dims.find(int32_pair(5, 8) + int32_pair(3, 2));
  ASSERT_NE(at, std::string::npos);
  dims.replace(at, 8, int32_pair(5, 0x4c54414d));
  expect("dims.mat", dims,
         "element 1 (at byte 128): its dimensions declare 1280590157 bytes, more than the " +
             std::to_string(matrix_bytes) + " bytes of the variable (a damaged file)");
  std::string element = bytes;
  element.replace(128, 8, int32_pair(14, 0x7fffffff));
  expect("element.mat", element,
         "element 1 (at byte 128) declares 2147483647 bytes, beyond the end of the " +
             std::to_string(bytes.size()) + "-byte file (a damaged file)");
}

// .mat files are read in a child process (fuzzing findings 8 and 9): the values and the
// messages are those of an in-process read.
TEST(MatfileV73, ReadInAChildProcessGivesTheValuesAndMessages) {
  if (!v73_supported())
    GTEST_SKIP() << "this libmatio cannot create v7.3 files (built without HDF5)";
  const TempDir dir;
  const auto file = dir.path() / "v73.mat";
  Eigen::MatrixXd m(3, 2);
  m << 1.5, -2.0, 3.25, 1e-300, 7.0, -0.0;
  const Eigen::RowVectorXd v = Eigen::RowVectorXd::LinSpaced(4, 0.0, 3.0);
  write_mat(file, {{"M", m}, {"v", v}}, Version::kV73);
  const auto vars = numeric_variables(file);
  ASSERT_EQ(vars.size(), 2u);
  EXPECT_EQ(vars[0].name, "M");
  EXPECT_EQ(vars[0].rows, 3u);
  EXPECT_EQ(vars[0].cols, 2u);
  EXPECT_FALSE(vars[0].complex);
  EXPECT_EQ(vars[1].name, "v");
  EXPECT_TRUE(vars[1].vector());
  EXPECT_EQ(read_matrix(file, "M"), m);  // bit for bit: doubles pass through the pipe
  EXPECT_EQ(read_vector(file, "M", 1), m.col(1));
  EXPECT_EQ(read_vector(file, "v"), v.transpose());
  try {
    read_vector(file, "nope");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(
        std::string(e.what()).find(file.string() + ": variable 'nope' is not in the file (numeric "
                                                   "variables: M, v)"),
        0u)
        << e.what();
  }
  try {
    read_vector(file, "M", 2);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              file.string() + ": variable 'M': column 2 (0-based) is out of range: 3 x 2");
  }
}

// Finding 8: a mutated v7.3 file (4,320 bytes, kept as tests/data/matfile/ and in the fuzz
// corpus) made libhdf5 1.10.8 read 136 bytes past a freed 320-byte block inside
// H5O__attr_open_by_name while libmatio listed the variables. Whatever libhdf5 does with it,
// this process goes on: the variables are listed as none (what a Release build's child
// returns: the damaged attribute is skipped) or an InputError names the file (what the child's
// death under ASan gives), and reading a variable is an InputError naming the file.
TEST(MatfileFuzzRegression, AV73FileThatOverflowedLibhdf5EndsInAnInputError) {
  const TempDir dir;
  const auto file = copy_of_test_file(dir, "finding8_hdf5_heap_overflow.mat", "finding8.mat");
  for (int call = 0; call < 2; ++call) {
    try {
      if (call == 0) {
        EXPECT_TRUE(numeric_variables(file).empty());
      } else {
        read_vector(file, "x");
        ADD_FAILURE() << "no InputError reading a variable";
      }
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find(file.string() + ": "), 0u) << e.what();
      std::printf("call %d: %s\n", call, e.what());
    }
  }
}

// Finding 9: a v5 file (1,302 bytes) whose second variable's array-flags tag reads as a small
// element. The tag walk then read the rest out of step with libmatio, which reads the flags
// and the dimensions tag at fixed places, and libmatio allocated the 1.67 GB its name tag
// declared. The walk now reads the matrix as libmatio does.
TEST(MatfileFuzzRegression, NameTagBeyondItsVariableIsRefusedBeforeLibmatio) {
  const TempDir dir;
  const auto file = copy_of_test_file(dir, "finding9_name_tag.mat", "finding9.mat");
  try {
    numeric_variables(file);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              file.string() +
                  ": element 2 (at byte 504): its name declares 1668218885 bytes, more than the "
                  "376 bytes of the variable (a damaged file)");
  }
}

// Fuzzing finding 14 (docs/fuzzing.md): a 206-byte v5 file whose first variable is 28 bytes
// long, too short for the name's tag after its array flags and dimensions. libmatio reads that
// tag anyway, from the next element's bytes, and allocated and cleared the 251 MB they declare:
// 1.2 s a read in a Release build, the reader time limit in the fuzz target (6.9 s an input).
TEST(MatfileFuzzRegression, AVariableTooShortForItsNameIsRefusedBeforeLibmatio) {
  const TempDir dir;
  const auto file = copy_of_test_file(dir, "finding14_name_past_variable.mat", "finding14.mat");
  try {
    numeric_variables(file);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), file.string() +
                                         ": element 1 (at byte 128): its name's tag lies past "
                                         "the 28 bytes of the variable (a damaged file)");
  }
}

// set_reader_time_limit: a .mat read is killed after the limit. A FIFO cannot stand in (the
// header check refuses it first), so the limit is shown to reach the reader process by a
// limit of zero, which no read meets.
TEST(MatfileV73, ReaderTimeLimitReachesTheReaderProcess) {
  const TempDir dir;
  const auto file = dir.path() / "v5.mat";
  write_mat(file, {{"v", Eigen::RowVector3d(1, 2, 3)}});
  set_reader_time_limit(std::chrono::milliseconds(0));
  const std::string e = error_of(file, 0);
  set_reader_time_limit(std::chrono::seconds(120));
  EXPECT_EQ(e, file.string() +
                   ": reading this .mat file: not finished after 0 s; stopped (a "
                   "damaged file?)");
  EXPECT_EQ(numeric_variables(file).size(), 1u);
}

// set_reader_reply_limit: a read whose reply passes the limit is stopped (the fuzz target's
// guard against a damaged file declaring a huge array; 256 MiB there). A 1,000-sample vector
// is 8,000 bytes of reply (plus 16 of dimensions): refused under 4,096 bytes, read at the
// default.
TEST(MatfileV73, ReaderReplyLimitStopsALargeReply) {
  const TempDir dir;
  const auto file = dir.path() / "v5.mat";
  write_mat(file, {{"v", Eigen::VectorXd::LinSpaced(1000, 0.0, 1.0)}});
  set_reader_reply_limit(4096);
  std::string e;
  try {
    read_vector(file, "v");
  } catch (const InputError& x) {
    e = x.what();
  }
  set_reader_reply_limit(IsolatedOptions{}.max_reply_bytes);
  EXPECT_EQ(e, file.string() +
                   ": reading this .mat file: the reader process's reply passed 4096 bytes; "
                   "stopped (a damaged file declaring a huge array?)");
  EXPECT_EQ(read_vector(file, "v").size(), 1000);
}

// The message for reading `name` of `file` as a vector ("" when it reads).
std::string vector_error(const std::filesystem::path& file, const std::string& name) {
  try {
    read_vector(file, name);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The fuzz target's kept reader process (set_reader_process_reuse): the same values and
// messages as a process per read, and a damaged file that ends the process (finding 8's, which
// libhdf5 may crash on) does not spoil the reads after it.

TEST(MatfileReaderReuse, AKeptReaderProcessReadsAsAProcessPerReadDoes) {
  struct Restore {
    ~Restore() { set_reader_process_reuse(1); }
  } restore;
  const TempDir dir;
  const auto good = dir.path() / "good.mat";
  Eigen::MatrixXd m(3, 2);
  m << 1.5, -2, 3, 4e-9, 5, 6;
  write_mat(good, {{"M", m}, {"v", Eigen::MatrixXd::Constant(1, 4, 0.25)}});
  const auto damaged = copy_of_test_file(dir, "finding8_hdf5_heap_overflow.mat", "finding8.mat");

  // A process per read: the reference.
  EXPECT_EQ(kept_reader_process(), -1);
  const auto per_read_vars = numeric_variables(good);
  const Eigen::VectorXd per_read_column = read_vector(good, "M", 1);
  // Refused in the reader process (libmatio finds no such variable), not by the header check.
  const std::string per_read_missing = vector_error(good, "nope");
  ASSERT_NE(per_read_missing.find("'nope' is not in the file"), std::string::npos)
      << per_read_missing;
  const std::string per_read_damaged = vector_error(damaged, "x");
  EXPECT_EQ(kept_reader_process(), -1);

  set_reader_process_reuse(1000);
  int reader = -1;
  for (int round = 0; round < 3; ++round) {
    const auto vars = numeric_variables(good);
    // Every good read of a round goes to one kept process.
    if (round == 0) reader = kept_reader_process();
    EXPECT_GT(reader, 0);
    EXPECT_NE(reader, ::getpid());
    ASSERT_EQ(vars.size(), per_read_vars.size());
    for (std::size_t i = 0; i < vars.size(); ++i) {
      EXPECT_EQ(vars[i].name, per_read_vars[i].name);
      EXPECT_EQ(vars[i].rows, per_read_vars[i].rows);
      EXPECT_EQ(vars[i].cols, per_read_vars[i].cols);
    }
    EXPECT_EQ(read_vector(good, "M", 1), per_read_column);  // exact: the same bytes
    EXPECT_EQ(read_matrix(good, "M"), m);
    EXPECT_EQ(vector_error(good, "nope"), per_read_missing);
    EXPECT_EQ(kept_reader_process(), reader);
    // Finding 8's file: libhdf5 reads freed memory on it, so whether the reader process ends
    // or refuses the file may depend on what the process held before. The file is named
    // either way, and a refusal is the one a process per read gives.
    const std::string damaged_error = vector_error(damaged, "x");
    EXPECT_EQ(damaged_error.find(damaged.string() + ": "), 0u) << damaged_error;
    if (per_read_damaged.find("reader process") == std::string::npos &&
        damaged_error.find("reader process") == std::string::npos) {
      EXPECT_EQ(damaged_error, per_read_damaged);
    }
    if (kept_reader_process() != reader) {
      reader = -1;  // it ended; the next round's first read starts another
      EXPECT_EQ(numeric_variables(good).size(), per_read_vars.size());
      reader = kept_reader_process();
    }
  }
  set_reader_process_reuse(1);
  EXPECT_EQ(kept_reader_process(), -1);
  EXPECT_EQ(read_vector(good, "M", 1), per_read_column);
}

// Fuzzing finding 11 (docs/fuzzing.md): a 4,320-byte v7.3 file from the fuzz corpus (a mutation
// of the v7.3 seed) whose dataset declares 40 x 5,722,881 values with none written: libmatio
// allocated and filled all of it, 4 s a read under ASan, and inputs like it held matfile_fuzz to
// 25 executions a second. The dataset also stores its values 15,112 bytes wide, which refuses
// it first now (finding 12): it is left out of the listing and refused when read, before
// libmatio allocates it. MatfileV73.ADatasetNotWrittenInFull... tests the bound on what a
// dataset stores.
TEST(MatfileFuzzRegression, AV73DatasetDeclaringMoreThanItsFileHoldsIsRefused) {
  if (!v73_supported()) GTEST_SKIP() << "this libmatio cannot read v7.3 files (built without HDF5)";
  const TempDir dir;
  const auto file = copy_of_test_file(dir, "fill_value_v73.mat", "fill_value.mat");
  for (const auto& v : numeric_variables(file)) EXPECT_NE(v.name, "forcc");
  std::string read;
  try {
    read_vector(file, "forcc", 0);
  } catch (const InputError& e) {
    read = e.what();
  }
  EXPECT_EQ(read, file.string() +
                      ": variable 'forcc' stores values of 15112 bytes each, where a value of a "
                      "MATLAB numeric class takes at most 8 (a damaged file)");
}

// Adds to a v7.3 file a double dataset `name` of rows x cols (MATLAB's order; HDF5's is the
// reverse), chunked by columns of at most 1,024 values, of which only the first `written_rows`
// rows of each column are written, from `data` (none by default): the rest holds no storage, its
// values only the fill value. libmatio cannot write one; MATLAB's matfile() leaves one when a
// variable is grown and not filled. The MATLAB_class attribute is the one libmatio writes.
// `type` is the values' type in the file and in `data`: HDF5's native double unless given (its
// owner closes it). With `deflate`, the chunks are compressed as MATLAB compresses them (zlib).
void add_dataset(const std::filesystem::path& file, const char* name, hsize_t rows, hsize_t cols,
                 hid_t type = H5T_NATIVE_DOUBLE, const void* data = nullptr,
                 hsize_t written_rows = 0, bool deflate = false) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hsize_t dims[2] = {cols, rows};
  const hsize_t chunk[2] = {1, std::min<hsize_t>(rows, 1024)};
  const hid_t space = H5Screate_simple(2, dims, nullptr);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  ASSERT_GE(H5Pset_chunk(dcpl, 2, chunk), 0);
  if (deflate) {
    ASSERT_GE(H5Pset_deflate(dcpl, 9), 0);
  }
  const hid_t d = H5Dcreate2(f, name, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  ASSERT_GE(d, 0);
  if (data && written_rows > 0) {
    const hsize_t start[2] = {0, 0}, count[2] = {cols, written_rows};
    ASSERT_GE(H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr), 0);
    const hsize_t values = cols * written_rows;
    const hid_t memory = H5Screate_simple(1, &values, nullptr);
    ASSERT_GE(H5Dwrite(d, type, memory, space, H5P_DEFAULT, data), 0);
    H5Sclose(memory);
  }
  const hid_t text = H5Tcopy(H5T_C_S1);
  H5Tset_size(text, 6);
  const hid_t scalar = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(d, "MATLAB_class", text, scalar, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(H5Awrite(a, text, "double"), 0);
  H5Aclose(a);
  H5Sclose(scalar);
  H5Tclose(text);
  H5Dclose(d);
  H5Pclose(dcpl);
  H5Sclose(space);
  H5Fclose(f);
}

// The bound on what a v7.3 dataset stores, on a made file. Beside a good vector (contiguous,
// written by libmatio): 'big' declares 100,000,000 values (800 MB) and stores none; 'half'
// declares 2,048 and stores the first of its two chunks of 1,024 (8,192 bytes of 16,384);
// 'full' declares 2,048 and stores both; 'zeros' declares 100,000 zeros and stores them
// compressed, far fewer bytes than their 800,000 (zlib, as MATLAB writes large variables). The
// listing holds 'full', the good vector and 'zeros', which read; 'big' and 'half' are refused by
// name when read, before libmatio allocates them.
TEST(MatfileV73, ADatasetNotWrittenInFullIsLeftOutAndRefusedWhenRead) {
  if (!v73_supported())
    GTEST_SKIP() << "this libmatio cannot create v7.3 files (built without HDF5)";
  const TempDir dir;
  const auto file = dir.path() / "grown.mat";
  const Eigen::VectorXd good = Eigen::VectorXd::LinSpaced(500, -1.0, 1.0);
  const Eigen::VectorXd ramp = Eigen::VectorXd::LinSpaced(2048, 0.0, 2047.0);
  write_mat(file, {{"good", good}}, Version::kV73);
  add_dataset(file, "big", 100000000, 1);
  add_dataset(file, "half", 2048, 1, H5T_NATIVE_DOUBLE, ramp.data(), 1024);
  add_dataset(file, "full", 2048, 1, H5T_NATIVE_DOUBLE, ramp.data(), 2048);
  const Eigen::VectorXd zeros = Eigen::VectorXd::Zero(100000);
  add_dataset(file, "zeros", 100000, 1, H5T_NATIVE_DOUBLE, zeros.data(), 100000, true);
  ASSERT_LT(std::filesystem::file_size(file), 100000u) << "the zeros must be stored compressed";

  const auto vars = numeric_variables(file);
  ASSERT_EQ(vars.size(), 3u);
  EXPECT_EQ(vars[0].name, "full");
  EXPECT_EQ(vars[1].name, "good");
  EXPECT_EQ(vars[2].name, "zeros");
  EXPECT_EQ(read_vector(file, "good"), good);
  EXPECT_EQ(read_vector(file, "full"), ramp);
  EXPECT_EQ(read_vector(file, "zeros"), zeros);
  EXPECT_EQ(vector_error(file, "big"),
            file.string() +
                ": variable 'big' declares 100000000 x 1 values of 8 bytes, more than the 0 "
                "bytes stored for it can hold (a damaged file, or a dataset never written in "
                "full)");
  EXPECT_EQ(vector_error(file, "half"),
            file.string() +
                ": variable 'half' declares 2048 x 1 values of 8 bytes, more than the 8192 "
                "bytes stored for it can hold (a damaged file, or a dataset never written in "
                "full)");
}

// Fuzzing finding 12 (docs/fuzzing.md): a 4,320-byte v7.3 file whose datasets 'M' (2 x 40) and
// 'force' (1 x 40) store floats of 691,350,586 and 15,112 bytes each. The value count passed
// the declared-size bound; libhdf5 allocated and cleared a conversion buffer of one value's size
// at every read (2 s each under ASan, so that an input took 8 s and matfile_fuzz fell from 500
// to 40 executions a second). Both are now left out of the listing and refused when read, by
// their stored size, before libhdf5 reads a value.
TEST(MatfileFuzzRegression, AV73DatasetStoringValuesWiderThanItsClassIsRefused) {
  if (!v73_supported()) GTEST_SKIP() << "this libmatio cannot read v7.3 files (built without HDF5)";
  const TempDir dir;
  const auto file = copy_of_test_file(dir, "wide_values_v73.mat", "wide.mat");
  EXPECT_TRUE(numeric_variables(file).empty());
  EXPECT_EQ(vector_error(file, "M"), file.string() +
                                         ": variable 'M' stores values of 691350586 bytes each, "
                                         "where a value of a MATLAB numeric class takes at most 8 "
                                         "(a damaged file)");
  EXPECT_EQ(vector_error(file, "force"),
            file.string() +
                ": variable 'force' stores values of 15112 bytes each, "
                "where a value of a MATLAB numeric class takes at most "
                "8 (a damaged file)");
}

// The same rule on a made file: beside a good vector, a complex one (a compound of two doubles,
// 16 bytes, as MATLAB stores one) is listed as complex, and a dataset of 3 x 2 doubles stored
// 4,096 bytes wide, all six written (24,576 bytes stored, so that only the width refuses it), is
// left out and refused by name.
TEST(MatfileV73, ADatasetOfWideValuesIsLeftOutAndRefusedWhenRead) {
  if (!v73_supported())
    GTEST_SKIP() << "this libmatio cannot create v7.3 files (built without HDF5)";
  const TempDir dir;
  const auto file = dir.path() / "wide.mat";
  const Eigen::VectorXd good = Eigen::VectorXd::LinSpaced(500, -1.0, 1.0);
  write_mat(file, {{"good", good}}, Version::kV73);
  const hid_t wide = H5Tcopy(H5T_IEEE_F64LE);
  ASSERT_GE(H5Tset_size(wide, 4096), 0);
  const std::vector<unsigned char> wide_zeros(6 * 4096, 0);  // six 0.0 in the wide type
  add_dataset(file, "wide", 3, 2, wide, wide_zeros.data(), 3);
  H5Tclose(wide);
  const hid_t complex = H5Tcreate(H5T_COMPOUND, 16);
  H5Tinsert(complex, "real", 0, H5T_NATIVE_DOUBLE);
  H5Tinsert(complex, "imag", 8, H5T_NATIVE_DOUBLE);
  const std::vector<double> z = {1, -1, 2, -2, 3, -3, 4, -4};  // real, imag of 4 values
  add_dataset(file, "z", 4, 1, complex, z.data(), 4);
  H5Tclose(complex);

  const auto vars = numeric_variables(file);
  ASSERT_EQ(vars.size(), 2u);
  EXPECT_EQ(vars[0].name, "good");
  EXPECT_FALSE(vars[0].complex);
  EXPECT_EQ(vars[1].name, "z");
  EXPECT_TRUE(vars[1].complex);
  EXPECT_EQ(vars[1].rows, 4u);
  EXPECT_EQ(read_vector(file, "good"), good);
  EXPECT_EQ(vector_error(file, "z"),
            file.string() + ": variable 'z' is complex: a signal channel must be real");
  EXPECT_EQ(vector_error(file, "wide"), file.string() +
                                            ": variable 'wide' stores values of 4096 bytes each, "
                                            "where a value of a MATLAB numeric class takes at most "
                                            "8 (a damaged file)");
}

// Fuzzing finding 13 (docs/fuzzing.md): a v5 matrix of 0 x 5 doubles, whose last column the
// fuzz target read, came back from the reader process as no values from a null pointer
// (undefined in memcpy; UBSan ended the target). A column of a matrix with no rows is an empty
// vector, in a v5 file and a v7.3 one.
TEST(MatfileFuzzRegression, AColumnOfAMatrixWithNoRowsIsEmpty) {
  const TempDir dir;
  for (const Version version : {Version::kV5, Version::kV73}) {
    if (version == Version::kV73 && !v73_supported()) continue;
    const auto file = dir.path() / (version == Version::kV5 ? "v5.mat" : "v73.mat");
    write_mat(file, {{"M", Eigen::MatrixXd(0, 5)}}, version);
    SCOPED_TRACE(file.filename().string());
    EXPECT_EQ(read_vector(file, "M", 4).size(), 0);
  }
}

}  // namespace
}  // namespace chatterlab::app::mat
