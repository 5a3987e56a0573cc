// FRF text files (docs/your-data.md, "FRF files"): one row per frequency, the complex FRF as
// real and imaginary parts, or as magnitude and phase when the header names them. Accepted:
//  - delimited text with a header row: `,` (decimal point), `;` or tab (decimal point or comma),
//    or whitespace-separated columns; the delimiter and the decimal mark are detected from the
//    first data row unless stated;
//  - any number of lines before the data (a title block, a line of column names with units
//    such as "Freq (Hz)  Real (m/N)  Imag (m/N)"), and comment lines starting with # or %;
//  - columns found by their header text (case and a unit in () or [] ignored):
//      frequency: f, f_hz, freq..., frequency...  (unit Hz; kHz and rad/s are converted)
//      real / imaginary: re, real..., im, imag...  (the first of each, in column order)
//      magnitude / phase: mag..., abs..., amp..., phase..., ph, angle, arg  (phase in degrees
//        unless the header says rad; magnitude in dB when the header says dB)
//      coherence: coh...  (optional)
//    and other columns ignored; without a header line that names them, the first three
//    columns are frequency, real, imaginary.
// Frequencies must increase in even steps (a quarter step of tolerance, for rounded exports);
// a 0 Hz row is dropped with a warning. Errors name the file and the line.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace chatterlab::app::frf_text {

// The ordinate of an FRF, per newton of force: receptance (m/N), mobility ((m/s)/N) or
// accelerance ((m/s^2)/N).
enum class Ordinate { kReceptance, kMobility, kAccelerance };

struct ReadOptions {
  char delimiter = 0;  // ',', ';', '\t' or ' ' (runs of whitespace); 0: detected
  char decimal = 0;    // '.' or ','; 0: detected
};

struct FrfTable {
  Eigen::VectorXd f_hz;       // increasing, evenly spaced, > 0
  Eigen::VectorXcd h;         // the ordinate as the file holds it
  Eigen::VectorXd coherence;  // empty when the file has no coherence column
  double df_hz = 0.0;         // the mean step
  char delimiter = 0;         // as read
  char decimal = '.';
  std::string columns;  // how the columns were taken, e.g. "f_hz, re, im by header (line 3)"
  std::vector<std::string> warnings;
};

// Reads an FRF text file. `label` names the file in messages ("tap/x/frf.csv").
// @throws InputError "<label> line <n>: ..." for a row or header it cannot read, and
//         "<label>: ..." for a missing file or one without data rows
FrfTable read_frf_text(const std::filesystem::path& file, const std::string& label,
                       const ReadOptions& options = {});

// The receptance (m/N) of an ordinate at f_hz (> 0): mobility / (j w), accelerance / (-w^2).
Eigen::VectorXcd to_receptance(const Eigen::VectorXd& f_hz, const Eigen::VectorXcd& h,
                               Ordinate ordinate);

// A named column of a CSV table.
struct Column {
  std::string name;
  Eigen::VectorXd values;
};

// Writes `columns` (equal lengths) as a comma-separated table: the comment lines first, each
// prefixed by "# ", then a header row of the names, then one row per value with 17 significant
// digits (a round trip is exact); NaN as an empty field. @throws InputError naming the file
void write_csv(const std::filesystem::path& file, const std::vector<std::string>& comments,
               const std::vector<Column>& columns);

}  // namespace chatterlab::app::frf_text
