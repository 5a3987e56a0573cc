// MATLAB .mat files (v5 and v7.3, the latter HDF5-based) through libmatio: the numeric
// variables of a file and one of them as a vector, for signal channels stored by MATLAB,
// Simcenter, LabVIEW or scipy.io.savemat. Files are read in a child process (a damaged one
// can crash libhdf5 or make libmatio allocate gigabytes: docs/fuzzing.md, findings 8 and 9).
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace chatterlab::app::mat {

// One numeric variable (double, single, integer or logical; 2-D) of a .mat file.
struct Variable {
  std::string name;
  std::size_t rows = 0, cols = 0;
  bool complex = false;
  bool vector() const { return (rows == 1 || cols == 1) && rows * cols > 1; }
  bool scalar() const { return rows == 1 && cols == 1; }
};

// The numeric 2-D variables in file order; structs, cells, strings, sparse and N-D arrays are
// left out. Throws InputError naming the file when it cannot be opened as a .mat file.
std::vector<Variable> numeric_variables(const std::filesystem::path& file);

// Variable `name` as a vector: a row or column vector whole, or column `column` (0-based) of a
// matrix (required for a matrix). Throws InputError naming the file and the variable when it is
// missing, not numeric, complex, N-D, or the column is out of range.
Eigen::VectorXd read_vector(const std::filesystem::path& file, const std::string& name,
                            std::optional<std::size_t> column = std::nullopt);

// Variable `name` whole (rows x cols), under the same checks as read_vector.
Eigen::MatrixXd read_matrix(const std::filesystem::path& file, const std::string& name);

// Variables `names` whole, in one opening of the file (one reader process).
std::vector<Eigen::MatrixXd> read_matrices(const std::filesystem::path& file,
                                           const std::vector<std::string>& names);

// How long a reader process may take before it is killed and the read is an InputError
// (default 120 s). The fuzz target sets it below libFuzzer's own time limit, so that a library
// caught in a loop is a contained failure there too.
void set_reader_time_limit(std::chrono::milliseconds limit);

// How many bytes a reader process may send back before it is killed and the read is an
// InputError (default 4 GiB, IsolatedOptions::max_reply_bytes). The fuzz target lowers it, so
// that a damaged file declaring a huge array does not take the target past libFuzzer's memory
// limit.
void set_reader_reply_limit(std::size_t bytes);

// How many reads one reader process serves (default 1: a fresh process for every read, as the
// program reads). The fuzz target, which reads thousands of files a second, keeps one process
// for 1,000 reads (IsolatedWorker, app/core/isolated.h): a crash there is still an InputError
// naming the file, and the next read starts another process.
void set_reader_process_reuse(std::size_t reads);

// The kept reader process's id; -1 when each read forks its own process, or before the first
// read (for tests).
int kept_reader_process();

enum class Version { kV5, kV73 };

// Whether this libmatio writes (and reads) v7.3 files: it was built with HDF5.
bool v73_supported();

// Writes double matrices as variables (uncompressed). Throws InputError naming the file when
// it cannot be created (v7.3 without HDF5 support included) or a variable cannot be written.
void write_mat(const std::filesystem::path& file,
               const std::vector<std::pair<std::string, Eigen::MatrixXd>>& variables,
               Version version = Version::kV5);

}  // namespace chatterlab::app::mat
