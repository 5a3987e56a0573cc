// Signal files of EXPERIMENT_FORMAT.md section 1: CSV with a header of channel names, or raw
// little-endian .f32/.f64 with channels interleaved. Raw files are memory-mapped and
// calibrated lazily, one channel at a time, so 10^8-value files never live as text.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/core/campaign.h"

namespace chatterlab::app {

class MappedFile;

class SignalTable {
 public:
  // Opens `data.file`. Throws InputError naming the file for: missing file, a raw file whose
  // size is not a multiple of (channels x value size), a CSV with a ragged row or a
  // non-numeric cell, NaN or infinite samples, an empty record. `label` prefixes messages.
  static SignalTable open(const DataSpec& data, const std::string& label);

  SignalTable(SignalTable&&) noexcept;
  SignalTable& operator=(SignalTable&&) noexcept;
  ~SignalTable();

  std::size_t samples() const { return samples_; }
  const std::vector<std::string>& names() const { return names_; }
  bool has(const std::string& name) const;

  // physical = scale * raw + offset. Throws InputError when the channel does not exist.
  Eigen::VectorXd channel(const std::string& name, const ChannelSpec& cal = {}) const;

 private:
  SignalTable() = default;
  int index_of(const std::string& name) const;

  std::string label_;
  std::vector<std::string> names_;
  std::size_t samples_ = 0;
  // Exactly one of these holds the samples.
  std::unique_ptr<MappedFile> mapped_;  // raw interleaved
  int value_bytes_ = 0;
  std::vector<std::vector<double>> columns_;  // parsed CSV
};

// Writes channels as CSV (header row of names) or raw .f32/.f64 (by the file's extension).
// Used by `synth`; throws InputError on I/O failure.
void write_signals(const std::filesystem::path& file, const std::vector<std::string>& names,
                   const std::vector<const Eigen::VectorXd*>& columns);

}  // namespace chatterlab::app
