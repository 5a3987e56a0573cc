// Signal files of EXPERIMENT_FORMAT.md section 1: delimited text (CSV) with a header of channel
// names, in the dialect `data:` states (delimiter, decimal comma, lines before the header), raw
// little-endian .f32/.f64 with channels interleaved, Universal File Format dataset 58/58b time
// records (.uff, .unv) or MATLAB .mat variables (v5, v7.3). Raw files are memory-mapped and
// calibrated lazily, one channel at a time, so 10^8-value files never live as text.
//
// Channel names, which `channels.<name>.column` picks by text or 0-based index:
// - text: the header cells (quotes removed; a LabVIEW "Comment" last column is left out);
// - .uff/.unv: one channel per dataset 58 time record (function type 0 or 1, real, even
//   abscissa), named by its record 1 (id1) text, in file order; a record whose id1 is empty or
//   repeats an earlier one is named "record <k>" (k its 0-based channel index);
// - .mat: one channel per real numeric vector variable (named as the variable) and per column
//   of a real numeric matrix ("M(:,1)", "M(:,2)", ... MATLAB's 1-based notation), in file
//   order; variables named t or time, scalars, complex and N-D arrays are left out, and so are
//   vectors whose length is not the record's (the length most channels share, the longest on
//   a tie).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "app/core/campaign.h"

namespace chatterlab::app {

class MappedFile;

// File extensions read as delimited text (CSV dialects); .f32/.f64 are raw.
bool is_text_signal_file(const std::filesystem::path& file);

// Every extension SignalTable::open reads: text, raw, .uff/.unv and .mat (case-insensitive).
bool is_signal_file(const std::filesystem::path& file);

// The most channels a signal file may offer: columns of a text file, names of a raw file, time
// records of a UFF file, vector variables and matrix columns of a .mat file. The largest
// acquisition systems of a machining lab record a few hundred; a damaged file declaring more
// (a .mat matrix of 11 million two-row columns fits in 20 kB compressed) is refused before
// its channels are listed.
inline constexpr std::size_t kMaxChannels = 4096;

class SignalTable {
 public:
  // Opens `data.file`. Throws InputError naming the file for: missing file, a raw file whose
  // size is not a multiple of (channels x value size), a CSV with a ragged row or a
  // non-numeric cell, NaN or infinite samples, an empty record. `label` prefixes messages.
  // When a text file does not parse in the dialect of `data` but does in another, the message
  // ends with the keys to set ("the file looks like ...: set data.delimiter ...").
  // data.sample_rate_hz (test.yaml's; 0: not checked) must agree with the rate a file states
  // (a UFF record's abscissa step) to 1e-5 relative, the 6 digits record 7 prints dx with.
  static SignalTable open(const DataSpec& data, const std::string& label);

  SignalTable(SignalTable&&) noexcept;
  SignalTable& operator=(SignalTable&&) noexcept;
  ~SignalTable();

  std::size_t samples() const { return samples_; }
  const std::string& label() const { return label_; }
  const std::vector<std::string>& names() const { return names_; }
  bool has(const std::string& name) const;

  // The column feeding channel `name`: `cal.record` (.uff/.unv), `cal.variable` (.mat, with
  // `cal.column` for a matrix column) or `cal.column` when set, else the column whose header is
  // `name`. Throws InputError naming the file and the key (channels.<name>.column, .record,
  // .variable) for a header text that is not in the header, an index out of range, a record or
  // variable the file does not hold as a channel, or when no column is named `name`.
  std::size_t column_of(const std::string& name, const ChannelSpec& cal = {}) const;

  // physical = scale * raw + offset of the column feeding `name` (column_of).
  Eigen::VectorXd channel(const std::string& name, const ChannelSpec& cal = {}) const;

  // The dialect the text file was read in (the detected delimiter when data.delimiter was
  // absent); 0 for raw files.
  char delimiter() const { return delimiter_; }

  // The sample rate the file states (1 / dx of UFF time records), 0 when it states none.
  double file_sample_rate_hz() const { return file_rate_hz_; }

 private:
  SignalTable() = default;
  int index_of(const std::string& name) const;
  void read_text(const DataSpec& data);
  void read_uff(const DataSpec& data);
  void read_mat(const DataSpec& data);

  std::string label_;
  std::vector<std::string> names_;
  std::size_t samples_ = 0;
  // Exactly one of these holds the samples.
  std::unique_ptr<MappedFile> mapped_;  // raw interleaved
  int value_bytes_ = 0;
  std::vector<std::vector<double>> columns_;  // parsed CSV, UFF records, .mat variables
  char delimiter_ = 0;
  double file_rate_hz_ = 0.0;
  std::vector<int> uff_records_;  // .uff: each channel's 1-based dataset 58 record in the file
  bool mat_ = false;
  std::string left_out_;  // "; left out: ..." for .mat variables that are not channels
};

// The problems of a test's `required` channels in `table`, one message each, empty when every
// channel resolves: a bad channels.<name>.column, or a channel the file does not name, as
// "<file>: channel 'force' is required for <what> (channels: ...)", followed by the mapping to
// set when the header has a column no required channel uses (a header with a unit such as
// "Force (N)" is proposed for channel force, but never taken without channels.force.column).
std::vector<std::string> missing_channels(const SignalTable& table,
                                          const std::vector<std::string>& required,
                                          const std::map<std::string, ChannelSpec>& channels,
                                          const std::string& what);

// test.yaml `channels.<name>` entries that calibrate nothing: <name> is neither a channel of
// `table` nor one of `required`, and the entry maps no column, record or variable to it (a
// misspelt channel name). One message each, naming `yaml_label`, the key and the closest
// channel name of the file or the test. The test is not usable with them (a silently ignored
// calibration gives wrong numbers).
std::vector<std::string> unmatched_channel_keys(const SignalTable& table,
                                                const std::vector<std::string>& required,
                                                const std::map<std::string, ChannelSpec>& channels,
                                                const std::string& yaml_label);

// Writes channels as CSV (header row of names) or raw .f32/.f64 (by the file's extension).
// Used by `synth`; throws InputError on I/O failure.
void write_signals(const std::filesystem::path& file, const std::vector<std::string>& names,
                   const std::vector<const Eigen::VectorXd*>& columns);

}  // namespace chatterlab::app
