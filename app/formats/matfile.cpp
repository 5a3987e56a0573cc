#include "app/formats/matfile.h"

#include <hdf5.h>
#include <matio.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "analysis/common/summary.h"
#include "app/core/isolated.h"

namespace chatterlab::app::mat {
namespace {

// The HDF5 library under libmatio (v7.3) is built without thread safety, and the pipeline
// opens signal files from several threads: every libmatio call holds this lock.
std::recursive_mutex matio_mutex;

// libmatio prints its diagnostics to stderr; keep the last one for our message instead.
std::mutex log_mutex;
std::string last_log;

void keep_log(int /*level*/, char* message) {
  const std::lock_guard<std::mutex> lock(log_mutex);
  last_log = message ? message : "";
}

void init_log() {
  static std::once_flag once;
  std::call_once(once, [] { Mat_LogInitFunc("chatterlab", keep_log); });
}

std::string matio_said() {
  const std::lock_guard<std::mutex> lock(log_mutex);
  std::string s = last_log;
  last_log.clear();
  return s.empty() ? "" : " (libmatio: " + s + ")";
}

struct FileCloser {
  void operator()(mat_t* m) const { Mat_Close(m); }
};
struct VarFreer {
  void operator()(matvar_t* v) const { Mat_VarFree(v); }
};
using File = std::unique_ptr<mat_t, FileCloser>;
using Var = std::unique_ptr<matvar_t, VarFreer>;

// The element tags of a v5 file, walked before libmatio reads it ("Level 5 MAT-File Format":
// an 8-byte tag, type and byte count, or a small element with both in 4 bytes). libmatio
// allocates what a tag declares before reading it: a matrix whose dimensions sub-element
// declared 1.3 GB in a 1.8 kB file made it malloc 2.5 GB (fuzzing finding 7, docs/fuzzing.md).
// Every top-level element must fit in the file; in a matrix (miMATRIX, 14), the array flags,
// dimensions and name sub-elements must fit in the matrix; a compressed element (miCOMPRESSED,
// 15) is inflated far enough to check its matrix's tags the same way, its matrix declaring at
// most 1100 bytes per compressed byte (zlib's ratio stays below 1032:1).
class TagWalk {
 public:
  TagWalk(std::ifstream& in, std::uintmax_t size, bool swap) : in_(in), size_(size), swap_(swap) {}

  std::string problem() {
    std::uintmax_t p = 128;
    for (int element = 1; p <= size_ && size_ - p >= 8; ++element) {
      const auto bytes = read_at(p, 8);
      if (bytes.size() < 8) return "";
      std::uint32_t type = 0, count = 0;
      const bool small = tag(bytes.data(), &type, &count);
      if (small) {
        p += 8;
        continue;
      }
      const std::string where =
          "element " + std::to_string(element) + " (at byte " + std::to_string(p) + ")";
      if (count > size_ - p - 8) {
        return where + " declares " + std::to_string(count) + " bytes, beyond the end of the " +
               std::to_string(size_) + "-byte file (a damaged file)";
      }
      if (type == 14) {
        if (auto why = matrix(read_at(p + 8, std::min<std::uintmax_t>(count, kHeadBytes)), count);
            !why.empty()) {
          return where + ": " + why;
        }
      } else if (type == 15) {
        if (auto why = compressed(p + 8, count); !why.empty()) return where + ": " + why;
      }
      p += 8 + count;
      if (type != 15) p += (8 - count % 8) % 8;
    }
    return "";
  }

 private:
  static constexpr std::uintmax_t kHeadBytes = 1024;
  // The most dimensions a variable may have (MATLAB's own files: a handful; libmatio reads at
  // most 13 from a compressed variable): the dimensions and the name tag fit in kHeadBytes.
  static constexpr std::uintmax_t kMaxRank = 64;

  std::vector<unsigned char> read_at(std::uintmax_t offset, std::uintmax_t n) {
    std::vector<unsigned char> out(static_cast<std::size_t>(n));
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(offset));
    in_.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(n));
    out.resize(static_cast<std::size_t>(std::max<std::streamsize>(in_.gcount(), 0)));
    return out;
  }

  std::uint32_t u32(const unsigned char* b) const {
    return swap_ ? (std::uint32_t{b[0]} << 24 | std::uint32_t{b[1]} << 16 |
                    std::uint32_t{b[2]} << 8 | b[3])
                 : (std::uint32_t{b[3]} << 24 | std::uint32_t{b[2]} << 16 |
                    std::uint32_t{b[1]} << 8 | b[0]);
  }

  // True for a small data element (its byte count in the upper half of the first word).
  bool tag(const unsigned char* b, std::uint32_t* type, std::uint32_t* count) const {
    const std::uint32_t w = u32(b);
    if ((w >> 16) != 0) {
      *type = w & 0xffffu;
      *count = w >> 16;
      return true;
    }
    *type = w;
    *count = u32(b + 4);
    return false;
  }

  // `head`: the first bytes of a matrix's contents; `length`: the bytes the matrix declares.
  // Read as libmatio 1.5 reads it (mat5.c, Mat_VarReadNextInfo5): 16 bytes of array flags and
  // an 8-byte dimensions tag at fixed places, whatever their tags say; the dimensions when that
  // tag is miINT32 (5; count / 4 of them, allocated first, padded to 8 bytes); then the name,
  // allocated from its tag when that is a full miINT8 (1) tag. A walk that read the array flags
  // as a small element lost step with libmatio, which then allocated a 1.67 GB name (fuzzing
  // finding 9, docs/fuzzing.md).
  std::string matrix(const std::vector<unsigned char>& head, std::uintmax_t length) const {
    if (length < 24 || head.size() < 24) return "";  // libmatio's read fails: its own message
    const auto too_long = [&](const char* part, std::uint32_t count) {
      return std::string("its ") + part + " " + std::to_string(count) + " bytes, more than the " +
             std::to_string(length) + " bytes of the variable (a damaged file)";
    };
    std::uintmax_t q = 24;
    if (u32(head.data() + 16) == 5) {
      const std::uint32_t count = u32(head.data() + 20);
      if (count > length - 24) return too_long("dimensions declare", count);
      const std::uintmax_t rank = count / 4;
      if (rank > kMaxRank) {
        return "its dimensions declare rank " + std::to_string(rank) + ", more than " +
               std::to_string(kMaxRank) + " (a damaged file)";
      }
      q += 4 * (rank + rank % 2);
    }
    // libmatio reads the name's tag at q whatever the variable's length: past its end, that is
    // the next element's bytes, whose count it allocates and clears (a 206-byte file made it
    // malloc and memset 251 MB, 1.2 s a read; fuzzing finding 14, docs/fuzzing.md).
    if (q > length || length - q < 8) {
      return "its name's tag lies past the " + std::to_string(length) +
             " bytes of the variable (a damaged file)";
    }
    if (head.size() < q + 8) return "";  // the file ends first: libmatio's read fails
    if (u32(head.data() + q) == 1) {
      const std::uint32_t count = u32(head.data() + q + 4);
      if (count > length - q - 8) return too_long("name declares", count);
    }
    return "";
  }

  std::string compressed(std::uintmax_t offset, std::uintmax_t count) {
    std::vector<unsigned char> in = read_at(offset, std::min<std::uintmax_t>(count, 64 * 1024));
    std::vector<unsigned char> out(8 + kHeadBytes);
    z_stream z{};
    if (inflateInit(&z) != Z_OK) return "";
    z.next_in = in.data();
    z.avail_in = static_cast<uInt>(in.size());
    z.next_out = out.data();
    z.avail_out = static_cast<uInt>(out.size());
    inflate(&z, Z_SYNC_FLUSH);  // what inflates is checked; libmatio reports a broken stream
    out.resize(out.size() - z.avail_out);
    inflateEnd(&z);
    if (out.size() < 8) return "";
    std::uint32_t type = 0, length = 0;
    if (tag(out.data(), &type, &length) || type != 14) return "";
    if (length / 1100 > count) {
      return "its compressed variable declares " + std::to_string(length) + " bytes in " +
             std::to_string(count) + " compressed bytes (a damaged file)";
    }
    return matrix(std::vector<unsigned char>(out.begin() + 8, out.end()), length);
  }

  std::ifstream& in_;
  std::uintmax_t size_;
  bool swap_;
};

// Why the file's first 128 bytes are not the header of a v5 or v7.3 .mat file (empty when they
// are): descriptive text starting "MATLAB", version 0x0100 (v5) or 0x0200 (v7.3, an HDF5 file
// with this header as its user block), endian indicator "IM" or "MI" (the MAT-file format,
// "Level 5 MAT-File Format", header). libmatio would also try a headerless file as v4, and a
// damaged one made it allocate 2.5 GB before any check of ours could run (fuzzing finding 3,
// docs/fuzzing.md): only these two headers are handed to it. v4 files (MATLAB 4, before 1996)
// are refused.
std::string header_problem(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::array<unsigned char, 128> h{};
  if (!in.read(reinterpret_cast<char*>(h.data()), static_cast<std::streamsize>(h.size()))) {
    return "not a v5 or v7.3 .mat file (shorter than the 128-byte MAT-file header)";
  }
  const bool text = std::equal(h.begin(), h.begin() + 6, "MATLAB");
  const bool little = h[126] == 'I' && h[127] == 'M';
  const bool big = h[126] == 'M' && h[127] == 'I';
  const unsigned version = little ? (h[124] | (h[125] << 8)) : ((h[124] << 8) | h[125]);
  if (!text || !(little || big) || (version != 0x0100 && version != 0x0200)) {
    return "not a v5 or v7.3 .mat file (no MAT-file header; v4 files are not read)";
  }
  if (version == 0x0200) return "";  // v7.3: an HDF5 file, read by libhdf5
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) return "";
  // "IM" read as bytes means the file was written little-endian.
  return TagWalk(in, size, !little).problem();
}

// Opens a file whose header check_header (below) passed, in the reader process.
File open_read(const std::filesystem::path& file) {
  init_log();
  File m(Mat_Open(file.c_str(), MAT_ACC_RDONLY));
  if (!m) {
    throw InputError(file.string() + ": not a MATLAB .mat file libmatio can read (v5, v7.3)" +
                     matio_said());
  }
  return m;
}

bool numeric_class(matio_classes c) {
  switch (c) {
    case MAT_C_DOUBLE:
    case MAT_C_SINGLE:
    case MAT_C_INT8:
    case MAT_C_UINT8:
    case MAT_C_INT16:
    case MAT_C_UINT16:
    case MAT_C_INT32:
    case MAT_C_UINT32:
    case MAT_C_INT64:
    case MAT_C_UINT64:
      return true;
    default:
      return false;
  }
}

template <typename T>
double value_at(const void* data, std::size_t i) {
  return static_cast<double>(static_cast<const T*>(data)[i]);
}

double element(const matvar_t& v, std::size_t i) {
  switch (v.class_type) {
    case MAT_C_DOUBLE:
      return value_at<double>(v.data, i);
    case MAT_C_SINGLE:
      return value_at<float>(v.data, i);
    case MAT_C_INT8:
      return value_at<std::int8_t>(v.data, i);
    case MAT_C_UINT8:
      return value_at<std::uint8_t>(v.data, i);
    case MAT_C_INT16:
      return value_at<std::int16_t>(v.data, i);
    case MAT_C_UINT16:
      return value_at<std::uint16_t>(v.data, i);
    case MAT_C_INT32:
      return value_at<std::int32_t>(v.data, i);
    case MAT_C_UINT32:
      return value_at<std::uint32_t>(v.data, i);
    case MAT_C_INT64:
      return value_at<std::int64_t>(v.data, i);
    default:
      return value_at<std::uint64_t>(v.data, i);
  }
}

// Whether `v`'s dimensions hold at most `most` values: each dimension is divided out of what is
// left, so that no product overflows. `dims` is set to "R x C ..." for the messages. A variable
// with a zero dimension holds nothing and fits.
bool dims_fit(const matvar_t& v, std::uintmax_t most, std::string* dims) {
  const auto rank = static_cast<std::size_t>(v.rank);
  if (std::any_of(v.dims, v.dims + rank, [](std::size_t d) { return d == 0; })) return true;
  bool fits = true;
  for (std::size_t i = 0; i < rank; ++i) {
    fits = fits && v.dims[i] <= most;
    if (fits) most /= v.dims[i];
    *dims += (i ? " x " : "") + std::to_string(v.dims[i]);
  }
  return fits;
}

// Why a v5 variable's header declares more values than its file can hold ("" when it does not):
// uncompressed, every value takes at least one byte; compressed (zlib, MATLAB's only filter),
// at least 1/1100 of one (zlib's ratio stays below 1032:1). A damaged header (e.g. 1090519080 x
// 3481666 in a 1.3 kB file) is refused before its columns are listed or its data allocated.
// Every dimension counts (an N-D variable is allocated whole before it is found not to be a
// vector or matrix); other classes (sparse, char, struct, cell) are not numeric channels and are
// not checked. A v7.3 file's datasets are checked against what they store (StoredValues).
std::string declared_size_problem(mat_t* m, const matvar_t& v, const std::filesystem::path& file) {
  if (Mat_GetVersion(m) == MAT_FT_MAT73) return "";
  if (!numeric_class(v.class_type) || v.rank < 1 || !v.dims) return "";
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(file, ec);
  if (ec) return "";
  const std::uintmax_t per_byte = v.compression == MAT_COMPRESSION_NONE ? 1 : 1100;
  std::string dims;
  if (dims_fit(v, bytes * per_byte, &dims)) return "";
  return "variable '" + std::string(v.name ? v.name : "") + "' declares " + dims +
         " values, more than the " + std::to_string(bytes) + "-byte file can hold (a damaged file)";
}

// A v7.3 file opened with libhdf5 itself beside libmatio's handle (libhdf5 shares the one open
// file between the two), for what libmatio does not say of a numeric dataset: how many bytes it
// stores per value and in all. libmatio allocates and fills what a dataset declares, and libhdf5
// gives the fill value for what was never written, so a damaged or unfinished dataset costs what
// it declares, not what the file holds:
// - Its values may be 1 to 8 bytes wide (a complex value, a compound of two, 16 at most). A
//   4,320-byte file whose 2 x 40 doubles each took 691,350,586 bytes made libhdf5 allocate and
//   clear a conversion buffer of that size at every read (2 s under ASan; fuzzing finding 12,
//   docs/fuzzing.md).
// - Its values may take at most the bytes stored for it (never more than the file's size):
//   exactly, without a filter; 1,100 times as many with any filter (zlib, MATLAB's only one,
//   stays below 1032:1). A chunked dataset whose chunks were not all written (the missing ones
//   read as HDF5's fill value; MATLAB's matfile() leaves one when a variable is grown and not
//   filled; MATLAB reads the gaps as zeros) or whose header is damaged declares more. A
//   contiguous dataset's storage is allocated whole, written or not, and passes. Six fuzzed 4 kB
//   files declared 40 x 5,722,881 doubles with none stored: 1.8 GB allocated and filled at each
//   read (fuzzing finding 11).
// Such a dataset is left out of the listing, so that the file's other variables are read, and
// refused by name when read, before libmatio reads it. Not covered: libmatio reads a dataset
// marked MATLAB_empty (its dimensions stored as its values) whole while it lists the file,
// before this check; a damaged one is contained by the reader process only.
class StoredValues {
 public:
  StoredValues(const std::filesystem::path& file, bool v73) : v73_(v73) {
    if (!v73) return;
    std::error_code ec;
    file_bytes_ = std::filesystem::file_size(file, ec);
    if (ec) return;
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // our questions' errors are answers, not output
    file_ = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  }
  ~StoredValues() {
    if (file_ >= 0) H5Fclose(file_);
  }
  StoredValues(const StoredValues&) = delete;
  StoredValues& operator=(const StoredValues&) = delete;

  // Why the numeric dataset of `v` stores no values of its class, or fewer than it declares (""
  // when it does not, and for a v5 file). When libhdf5 cannot say what the dataset stores, its
  // declaration is bounded by the file's size as a compressed variable's is, 1,100 values a byte.
  std::string problem(const matvar_t& v) const {
    if (!v73_ || !v.name || !numeric_class(v.class_type) || v.rank < 1 || !v.dims) return "";
    const std::string name = v.name;
    std::size_t width = 0;
    bool compound = false, filtered = false, known = false;
    std::uintmax_t stored = 0;
    if (const hid_t set = file_ >= 0 ? H5Dopen2(file_, v.name, H5P_DEFAULT) : -1; set >= 0) {
      if (const hid_t type = H5Dget_type(set); type >= 0) {
        width = H5Tget_size(type);
        compound = H5Tget_class(type) == H5T_COMPOUND;
        H5Tclose(type);
      }
      if (const hid_t create = H5Dget_create_plist(set); create >= 0) {
        filtered = H5Pget_nfilters(create) > 0;
        H5Pclose(create);
      }
      // 0 bytes is also libhdf5's answer to an error: taken as an answer only when the
      // dataset's space is reported not allocated.
      stored = std::min<std::uintmax_t>(H5Dget_storage_size(set), file_bytes_);
      H5D_space_status_t status{};
      known = width > 0 && (stored > 0 || (H5Dget_space_status(set, &status) >= 0 &&
                                           status == H5D_SPACE_STATUS_NOT_ALLOCATED));
      H5Dclose(set);
    }
    std::string dims;
    if (!known) {
      if (dims_fit(v, file_bytes_ * 1100, &dims)) return "";
      return "variable '" + name + "' declares " + dims + " values, more than the " +
             std::to_string(file_bytes_) +
             "-byte file can hold (a damaged file, or a dataset never written in full)";
    }
    const std::size_t widest = compound ? 16 : 8;
    if (width > widest) {
      return "variable '" + name + "' stores values of " + std::to_string(width) +
             " bytes each, where " + (compound ? "a complex value" : "a value") +
             " of a MATLAB numeric class takes at most " + std::to_string(widest) +
             " (a damaged file)";
    }
    if (dims_fit(v, stored * (filtered ? 1100 : 1) / width, &dims)) return "";
    return "variable '" + name + "' declares " + dims + " values of " + std::to_string(width) +
           " bytes, more than the " + std::to_string(stored) + " bytes stored for it" +
           (filtered ? " (compressed)" : "") +
           " can hold (a damaged file, or a dataset never written in full)";
  }

 private:
  bool v73_ = false;
  hid_t file_ = -1;
  std::uintmax_t file_bytes_ = 0;
};

// The readers below run in a child process (see isolated() further down).
// A v5 variable declaring more than its file holds is a damaged file, refused whole; a v7.3
// dataset whose stored values are too wide or too few is left out of the list (the other
// variables may be good) and refused when read.
std::vector<Variable> numeric_variables_here(const std::filesystem::path& file) {
  File m = open_read(file);
  const StoredValues stored(file, Mat_GetVersion(m.get()) == MAT_FT_MAT73);
  std::vector<Variable> out;
  while (Var v{Mat_VarReadNextInfo(m.get())}) {
    if (!v->name || !numeric_class(v->class_type) || v->rank != 2) continue;
    if (const std::string why = declared_size_problem(m.get(), *v, file); !why.empty()) {
      throw InputError(file.string() + ": " + why);
    }
    if (!stored.problem(*v).empty()) continue;
    out.push_back({v->name, v->dims[0], v->dims[1], v->isComplex != 0});
  }
  return out;
}

Var read_numeric(mat_t* m, const std::filesystem::path& file, const std::string& name,
                 const StoredValues& stored) {
  const std::string where = file.string() + ": variable '" + name + "'";
  if (const Var info{Mat_VarReadInfo(m, name.c_str())}) {
    if (const std::string why = declared_size_problem(m, *info, file); !why.empty()) {
      throw InputError(file.string() + ": " + why);
    }
    if (const std::string why = stored.problem(*info); !why.empty()) {
      throw InputError(file.string() + ": " + why);
    }
  }
  Var v{Mat_VarRead(m, name.c_str())};
  if (!v) {
    std::string names;
    for (const auto& n : numeric_variables_here(file)) {
      names += (names.empty() ? "" : ", ") + n.name;
    }
    throw InputError(where + " is not in the file (numeric variables: " +
                     (names.empty() ? "none" : names) + ")" + matio_said());
  }
  // An empty matrix has no data (libmatio leaves it null in a v7.3 file) and reads as empty.
  if (!numeric_class(v->class_type) || v->rank != 2 ||
      (!v->data && v->dims[0] != 0 && v->dims[1] != 0)) {
    throw InputError(where + " is not a numeric vector or matrix" +
                     (v->rank != 2 ? " (" + std::to_string(v->rank) + "-D)" : std::string()));
  }
  if (v->isComplex) throw InputError(where + " is complex: a signal channel must be real");
  return v;
}

std::vector<Eigen::MatrixXd> read_matrices_here(const std::filesystem::path& file,
                                                const std::vector<std::string>& names) {
  File m = open_read(file);
  const StoredValues stored(file, Mat_GetVersion(m.get()) == MAT_FT_MAT73);
  std::vector<Eigen::MatrixXd> out;
  for (const auto& name : names) {
    const Var v = read_numeric(m.get(), file, name, stored);
    const std::size_t rows = v->dims[0], cols = v->dims[1];
    Eigen::MatrixXd& x =
        out.emplace_back(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    for (std::size_t i = 0; i < rows * cols; ++i) x.data()[i] = element(*v, i);  // column-major
  }
  return out;
}

Eigen::VectorXd read_vector_here(const std::filesystem::path& file, const std::string& name,
                                 std::optional<std::size_t> column) {
  File m = open_read(file);
  const StoredValues stored(file, Mat_GetVersion(m.get()) == MAT_FT_MAT73);
  const Var v = read_numeric(m.get(), file, name, stored);
  const std::string where = file.string() + ": variable '" + name + "'";
  const std::size_t rows = v->dims[0], cols = v->dims[1];
  const bool vec = rows == 1 || cols == 1;
  std::size_t first = 0, count = rows * cols;
  if (column) {
    if (*column >= cols) {
      throw InputError(where + ": column " + std::to_string(*column) +
                       " (0-based) is out of range: " + std::to_string(rows) + " x " +
                       std::to_string(cols));
    }
    first = *column * rows;  // column-major
    count = rows;
  } else if (!vec) {
    throw InputError(where + " is a " + std::to_string(rows) + " x " + std::to_string(cols) +
                     " matrix: name one of its columns");
  }
  Eigen::VectorXd out(static_cast<Eigen::Index>(count));
  for (std::size_t i = 0; i < count; ++i) {
    out[static_cast<Eigen::Index>(i)] = element(*v, first + i);
  }
  return out;
}

// libmatio and libhdf5 are not safe on damaged files: a mutated v7.3 file made libhdf5 1.10.8
// read past a freed buffer in H5O__attr_open_by_name (fuzzing finding 8, docs/fuzzing.md), and
// libmatio's v5 reader allocates what the tags of nested cells and structs declare. Every .mat
// file is therefore read in a child process (app/core/isolated.h): a crash, a hang or a
// corruption there skips that test with a message naming the file, and the campaign goes on.
// The header and the v5 tag walk (ours) run here first, for a clear message. A fork costs
// well under a millisecond in a Release build; SignalTable reads a file in two.
void check_header(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) throw InputError(file.string() + ": file not found");
  if (const std::string why = header_problem(file); !why.empty()) {
    throw InputError(file.string() + ": " + why);
  }
}

std::atomic<std::chrono::milliseconds::rep> reader_time_limit_ms{120000};
std::atomic<std::size_t> reader_reply_limit{IsolatedOptions{}.max_reply_bytes};

IsolatedOptions isolated(const std::filesystem::path& file) {
  IsolatedOptions o;
  o.what = file.string() + ": reading this .mat file";
  o.time_limit = std::chrono::milliseconds(reader_time_limit_ms.load());
  o.max_reply_bytes = reader_reply_limit.load();
  return o;
}

void put_matrix(ByteWriter& w, const Eigen::MatrixXd& m) {
  w.u64(static_cast<std::uint64_t>(m.rows()));
  w.u64(static_cast<std::uint64_t>(m.cols()));
  w.f64(m.data(), static_cast<std::size_t>(m.size()));
}

Eigen::MatrixXd get_matrix(ByteReader& r) {
  const auto rows = static_cast<Eigen::Index>(r.u64());
  const auto cols = static_cast<Eigen::Index>(r.u64());
  if (rows < 0 || cols < 0 ||
      (rows != 0 && static_cast<std::size_t>(cols) > r.left() / sizeof(double) / rows)) {
    throw InputError(r.what() + ": the reader process's reply is short");
  }
  Eigen::MatrixXd m(rows, cols);
  r.f64(m.data(), static_cast<std::size_t>(m.size()));
  return m;
}

// What a reader process is asked: the numeric variables, some variables whole, or one as a
// vector. Encoded as bytes, so that one kept reader process (set_reader_process_reuse) can take
// requests made after it started; a process forked per read runs the same serve().
enum class Op : std::uint64_t { kVariables = 1, kMatrices = 2, kVector = 3 };

struct Request {
  Op op = Op::kVariables;
  std::filesystem::path file;
  std::vector<std::string> names;
  std::optional<std::size_t> column;
};

std::string encode(const Request& q) {
  ByteWriter w;
  w.u64(static_cast<std::uint64_t>(q.op));
  w.str(q.file.string());
  w.u64(q.names.size());
  for (const auto& n : q.names) w.str(n);
  w.u64(q.column ? 1 : 0);
  w.u64(q.column.value_or(0));
  return w.take();
}

Request decode(const std::string& bytes) {
  ByteReader r(bytes, "a .mat reader request");
  Request q;
  q.op = static_cast<Op>(r.u64());
  q.file = r.str();
  for (std::uint64_t n = r.u64(), i = 0; i < n; ++i) q.names.push_back(r.str());
  const bool has_column = r.u64() != 0;
  const std::uint64_t column = r.u64();
  if (has_column) q.column = static_cast<std::size_t>(column);
  return q;
}

// Runs in the reader process: the request's answer as bytes.
std::string serve(const std::string& request) {
  matio_said();  // a kept reader process: no message of an earlier file's in this one's
  const Request q = decode(request);
  ByteWriter w;
  switch (q.op) {
    case Op::kVariables: {
      const auto vars = numeric_variables_here(q.file);
      w.u64(vars.size());
      for (const auto& v : vars) {
        w.str(v.name);
        w.u64(v.rows);
        w.u64(v.cols);
        w.u64(v.complex ? 1 : 0);
      }
      break;
    }
    case Op::kMatrices:
      for (const auto& m : read_matrices_here(q.file, q.names)) put_matrix(w, m);
      break;
    case Op::kVector:
      put_matrix(w, read_vector_here(q.file, q.names.at(0), q.column));
      break;
    default:
      throw std::logic_error("unknown .mat reader request");
  }
  return w.take();
}

// Reads per kept reader process (1: a fresh process per read) and that process.
std::size_t reads_per_process = 1;
std::unique_ptr<IsolatedWorker> kept_reader;

// After check_header, the request is answered in a reader process; `decode_reply` reads the
// answer back.
template <typename Decode>
auto through_reader(const Request& q, const Decode& decode_reply) {
  const std::lock_guard<std::recursive_mutex> lock(matio_mutex);
  check_header(q.file);
  const IsolatedOptions options = isolated(q.file);
  const std::string request = encode(q);
  std::string bytes;
  if (reads_per_process > 1) {
    if (!kept_reader) kept_reader = std::make_unique<IsolatedWorker>(serve, reads_per_process);
    bytes = kept_reader->call(request, options);
  } else {
    bytes = run_isolated([&] { return serve(request); }, options);
  }
  ByteReader r(bytes, options.what);
  return decode_reply(r);
}

}  // namespace

std::vector<Variable> numeric_variables(const std::filesystem::path& file) {
  return through_reader(Request{Op::kVariables, file, {}, std::nullopt}, [](ByteReader& r) {
    std::vector<Variable> out;
    for (std::uint64_t n = r.u64(), i = 0; i < n; ++i) {
      Variable v;
      v.name = r.str();
      v.rows = r.u64();
      v.cols = r.u64();
      v.complex = r.u64() != 0;
      out.push_back(std::move(v));
    }
    return out;
  });
}

std::vector<Eigen::MatrixXd> read_matrices(const std::filesystem::path& file,
                                           const std::vector<std::string>& names) {
  return through_reader(Request{Op::kMatrices, file, names, std::nullopt}, [&](ByteReader& r) {
    std::vector<Eigen::MatrixXd> out;
    for (std::size_t i = 0; i < names.size(); ++i) out.push_back(get_matrix(r));
    return out;
  });
}

Eigen::MatrixXd read_matrix(const std::filesystem::path& file, const std::string& name) {
  return std::move(read_matrices(file, {name}).front());
}

Eigen::VectorXd read_vector(const std::filesystem::path& file, const std::string& name,
                            std::optional<std::size_t> column) {
  return through_reader(Request{Op::kVector, file, {name}, column},
                        [](ByteReader& r) { return Eigen::VectorXd(get_matrix(r).col(0)); });
}

int kept_reader_process() {
  const std::lock_guard<std::recursive_mutex> lock(matio_mutex);
  return kept_reader ? kept_reader->pid() : -1;
}

void set_reader_process_reuse(std::size_t reads) {
  const std::lock_guard<std::recursive_mutex> lock(matio_mutex);
  reads_per_process = std::max<std::size_t>(reads, 1);
  kept_reader.reset();
}

void set_reader_time_limit(std::chrono::milliseconds limit) {
  reader_time_limit_ms = limit.count();
}

void set_reader_reply_limit(std::size_t bytes) { reader_reply_limit = bytes; }

bool v73_supported() {
  const std::lock_guard<std::recursive_mutex> lock(matio_mutex);
  init_log();
  const auto probe = std::filesystem::temp_directory_path() /
                     ("chatterlab-mat73-probe-" + std::to_string(::getpid()) + ".mat");
  mat_t* m = Mat_CreateVer(probe.c_str(), nullptr, MAT_FT_MAT73);
  const bool ok = m != nullptr;
  if (m) Mat_Close(m);
  std::error_code ec;
  std::filesystem::remove(probe, ec);
  matio_said();  // drop the log of a failed probe
  return ok;
}

void write_mat(const std::filesystem::path& file,
               const std::vector<std::pair<std::string, Eigen::MatrixXd>>& variables,
               Version version) {
  const std::lock_guard<std::recursive_mutex> lock(matio_mutex);
  init_log();
  const char* what = version == Version::kV73 ? "v7.3" : "v5";
  File m(
      Mat_CreateVer(file.c_str(), nullptr, version == Version::kV73 ? MAT_FT_MAT73 : MAT_FT_MAT5));
  if (!m) {
    throw InputError(file.string() + ": cannot create a " + what + " .mat file" + matio_said());
  }
  for (const auto& [name, value] : variables) {
    std::size_t dims[2] = {static_cast<std::size_t>(value.rows()),
                           static_cast<std::size_t>(value.cols())};
    Eigen::MatrixXd copy = value;  // column-major, as .mat stores it
    Var v{Mat_VarCreate(name.c_str(), MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, copy.data(),
                        MAT_F_DONT_COPY_DATA)};
    if (!v || Mat_VarWrite(m.get(), v.get(), MAT_COMPRESSION_NONE) != 0) {
      throw InputError(file.string() + ": cannot write variable '" + name + "'" + matio_said());
    }
    v->data = nullptr;  // owned by `copy`
  }
}

}  // namespace chatterlab::app::mat
