// Typed access to YAML nodes that records every problem with the file and key it concerns
// (EXPERIMENT_FORMAT.md: a clear message naming the file and key).
#pragma once

#include <yaml-cpp/yaml.h>

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace chatterlab::app {

class YamlReader {
 public:
  explicit YamlReader(std::string file_label) : file_(std::move(file_label)) {}

  // Numbers are finite: .inf, .nan or a value beyond the double range (1e400) is an error.
  // Required keys: a missing key or a wrong type is an error; the default is returned.
  double required_double(const YAML::Node& map, const std::string& key,
                         const std::string& path = "");
  std::string required_string(const YAML::Node& map, const std::string& key,
                              const std::string& path = "");
  // Optional keys: absent -> nullopt; wrong type -> error and nullopt.
  std::optional<double> optional_double(const YAML::Node& map, const std::string& key,
                                        const std::string& path = "");
  std::optional<std::string> optional_string(const YAML::Node& map, const std::string& key,
                                             const std::string& path = "");
  // Whole numbers in [min, max] (both stated in the message): a fraction, a non-number, a
  // non-finite number or a value outside the range is an error and gives nullopt.
  std::optional<long> optional_int(const YAML::Node& map, const std::string& key,
                                   const std::string& path, long min, long max);
  std::optional<long> required_int(const YAML::Node& map, const std::string& key,
                                   const std::string& path, long min, long max);
  // A number or a two-element list [a, b]; one number gives {a, a}.
  std::optional<std::pair<double, double>> optional_number_or_pair(const YAML::Node& map,
                                                                   const std::string& key,
                                                                   const std::string& path = "");
  std::optional<std::pair<double, double>> optional_pair(const YAML::Node& map,
                                                         const std::string& key,
                                                         const std::string& path = "");
  std::vector<std::string> string_list(const YAML::Node& map, const std::string& key, bool required,
                                       const std::string& path = "");

  // Warn about keys not in `known`, suggesting the closest known key (a misspelt key).
  void check_keys(const YAML::Node& map, const std::set<std::string>& known,
                  const std::string& path = "");

  void error(const std::string& key_path, const std::string& what);
  void warn(const std::string& key_path, const std::string& what);

  const std::vector<std::string>& errors() const { return errors_; }
  // Throws InputError with every error, one per line, when there is any (a spec or settings
  // file that is read whole or not at all), then every warning ("warning: ..."), which would
  // not be printed otherwise.
  void throw_if_errors() const;
  const std::vector<std::string>& warnings() const { return warnings_; }
  const std::string& file() const { return file_; }

 private:
  std::string key_path(const std::string& path, const std::string& key) const;
  std::string missing_message(const YAML::Node& map, const std::string& key) const;
  // A finite number in *out, or an error naming what is expected (`expected`, e.g. "a number").
  bool number(const YAML::Node& n, const std::string& key_path, const std::string& expected,
              double* out);
  std::optional<long> whole_in_range(const YAML::Node& n, const std::string& key_path, long min,
                                     long max);

  std::string file_;
  std::vector<std::string> errors_;
  std::vector<std::string> warnings_;
};

// Edit distance between two short strings (used to suggest a misspelt key).
int edit_distance(const std::string& a, const std::string& b);

// Whether a and b are within `edits` edits (lengths compared first, so cheap for long strings).
bool within_edits(const std::string& a, const std::string& b, int edits);

// A key written for `wanted`: within two edits, or `wanted` without (or with an extra) unit
// suffix such as "_hz" or "_mm" (one is a prefix of the other, at least 4 characters).
bool looks_like(const std::string& written, const std::string& wanted);

}  // namespace chatterlab::app
