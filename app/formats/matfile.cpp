#include "app/formats/matfile.h"

#include <matio.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <fstream>
#include <memory>
#include <mutex>
#include <system_error>

#include "analysis/common/summary.h"

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
  return "";
}

File open_read(const std::filesystem::path& file) {
  init_log();
  if (!std::filesystem::exists(file)) throw InputError(file.string() + ": file not found");
  if (const std::string why = header_problem(file); !why.empty()) {
    throw InputError(file.string() + ": " + why);
  }
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

// Throws InputError when a v4/v5 variable's header declares more values than its file can
// hold: uncompressed, every value takes at least one byte; compressed (zlib), at least 1/1100
// of one. A damaged header (e.g. 1090519080 x 3481666 in a 1.3 kB file) is refused before
// its columns are listed or its data allocated. v7.3 (HDF5) datasets may be stored as a fill
// value and are not checked.
void check_declared_size(mat_t* m, const matvar_t& v, const std::filesystem::path& file) {
  if (Mat_GetVersion(m) == MAT_FT_MAT73 || v.rank != 2 || !v.dims) return;
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(file, ec);
  if (ec) return;
  const std::uintmax_t per_byte = v.compression == MAT_COMPRESSION_NONE ? 1 : 1100;
  const std::uintmax_t limit = bytes * per_byte;
  const std::uintmax_t rows = v.dims[0], cols = v.dims[1];
  if (rows != 0 && cols > limit / rows) {
    throw InputError(file.string() + ": variable '" + (v.name ? v.name : "") + "' declares " +
                     std::to_string(rows) + " x " + std::to_string(cols) +
                     " values, more than the " + std::to_string(bytes) +
                     "-byte file can hold (a damaged file)");
  }
}

}  // namespace

std::vector<Variable> numeric_variables(const std::filesystem::path& file) {
  const std::lock_guard<std::recursive_mutex> lock(matio_mutex);
  File m = open_read(file);
  std::vector<Variable> out;
  while (Var v{Mat_VarReadNextInfo(m.get())}) {
    if (!v->name || !numeric_class(v->class_type) || v->rank != 2) continue;
    check_declared_size(m.get(), *v, file);
    out.push_back({v->name, v->dims[0], v->dims[1], v->isComplex != 0});
  }
  return out;
}

namespace {

Var read_numeric(mat_t* m, const std::filesystem::path& file, const std::string& name) {
  const std::string where = file.string() + ": variable '" + name + "'";
  if (const Var info{Mat_VarReadInfo(m, name.c_str())}) check_declared_size(m, *info, file);
  Var v{Mat_VarRead(m, name.c_str())};
  if (!v) {
    std::string names;
    for (const auto& n : numeric_variables(file)) names += (names.empty() ? "" : ", ") + n.name;
    throw InputError(where + " is not in the file (numeric variables: " +
                     (names.empty() ? "none" : names) + ")" + matio_said());
  }
  if (!numeric_class(v->class_type) || v->rank != 2 || !v->data) {
    throw InputError(where + " is not a numeric vector or matrix" +
                     (v->rank != 2 ? " (" + std::to_string(v->rank) + "-D)" : std::string()));
  }
  if (v->isComplex) throw InputError(where + " is complex: a signal channel must be real");
  return v;
}

}  // namespace

Eigen::MatrixXd read_matrix(const std::filesystem::path& file, const std::string& name) {
  const std::lock_guard<std::recursive_mutex> lock(matio_mutex);
  File m = open_read(file);
  const Var v = read_numeric(m.get(), file, name);
  const std::size_t rows = v->dims[0], cols = v->dims[1];
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  for (std::size_t i = 0; i < rows * cols; ++i) out.data()[i] = element(*v, i);  // column-major
  return out;
}

Eigen::VectorXd read_vector(const std::filesystem::path& file, const std::string& name,
                            std::optional<std::size_t> column) {
  const std::lock_guard<std::recursive_mutex> lock(matio_mutex);
  File m = open_read(file);
  const Var v = read_numeric(m.get(), file, name);
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
