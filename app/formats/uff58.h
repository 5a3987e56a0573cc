// Universal File Format dataset 58 (function at nodal DOF): the exchange format of modal and
// machining-dynamics packages for time records, spectra and FRFs, in its ASCII form and the
// binary form 58b (header lines in ASCII, data block as raw little- or big-endian values).
// Reference: the SDRC/Siemens "Universal Dataset Number 58" description (records 1-11).
#pragma once

#include <Eigen/Core>
#include <complex>
#include <filesystem>
#include <string>
#include <vector>

namespace chatterlab::app::uff {

// Record 6 field 1 (function type) values used here; others are read and kept as numbers.
constexpr int kTimeResponse = 1;
constexpr int kAutoSpectrum = 2;
constexpr int kCrossSpectrum = 3;
constexpr int kFrf = 4;
constexpr int kCoherence = 6;
constexpr int kPowerSpectralDensity = 9;
constexpr int kSpectrum = 12;

struct Function58 {
  // Records 1-5: five free-text id lines (record 1 is usually the function's name).
  std::string id1, id2, id3, id4, id5;
  int function_type = kTimeResponse;  // record 6 field 1
  int load_case = 0;
  std::string response_entity;  // record 6 fields 5-7: name, node, direction (+-1..+-6)
  int response_node = 0, response_direction = 0;
  std::string reference_entity;  // fields 8-10
  int reference_node = 0, reference_direction = 0;
  // Abscissa: evenly spaced from x_start by dx when x is empty; else x holds every value.
  double x_start = 0.0, dx = 0.0;
  Eigen::VectorXd x;
  // Ordinate: real or complex (record 7 field 1: 2, 4 real; 5, 6 complex). Exactly one of the
  // two is set, with `samples` values.
  bool complex_ordinate = false;
  Eigen::VectorXd real;
  Eigen::VectorXcd values;
  Eigen::Index samples() const { return complex_ordinate ? values.size() : real.size(); }
  // Records 8-11 axis labels and units (e.g. "Time" "s", "Pressure" "Pa").
  std::string x_label = "Time", x_unit = "s";
  std::string y_label, y_unit;  // numerator
  std::string z_label, z_unit;  // denominator (FRF: the force), may be empty
  double sample_rate_hz() const { return dx > 0 ? 1.0 / dx : 0.0; }
};

// Every dataset 58/58b of the file, in file order; other datasets are skipped. Throws
// InputError naming the file and the dataset's ordinal ("<file>: dataset 58 #2, record 7: ...")
// for a malformed block.
std::vector<Function58> read_uff58(const std::filesystem::path& file);

// Writes the functions as ASCII dataset 58 (binary = false) or 58b (little-endian doubles).
// Throws InputError naming the file when it cannot be written.
void write_uff58(const std::filesystem::path& file, const std::vector<Function58>& functions,
                 bool binary = false);

}  // namespace chatterlab::app::uff
