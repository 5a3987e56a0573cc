// The one way a YAML file of the program's input is read (campaign.yaml, test.yaml, truth.yaml,
// a simulation spec, a synth spec): size-limited, parsed, and refused as a whole when a key is
// not a plain scalar name, a mapping has a key twice, or the nesting is too deep
// (docs/format/campaign.md, "What the reader refuses").
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace chatterlab::app {

// A YAML file of the format is a few kB: a larger file is refused before it is read.
constexpr std::uintmax_t kYamlMaxFileBytes = 1024 * 1024;
// Mappings and lists nested deeper than this (the root is level 0) are refused.
constexpr int kYamlMaxDepth = 64;
// Nodes visited when checking a tree (aliases counted each time they are reached): more is an
// alias expansion no spec of the format needs.
constexpr long kYamlMaxNodes = 1000000;

// Reads and checks `file`. On success, returns the root node (any type) and appends nothing.
// On any problem, returns an undefined node (`!node` is true) and appends to *errors one or
// more messages, each beginning with "<label>: " and naming the key path and line where there
// is one. Never throws for the file's content.
YAML::Node load_yaml_file(const std::filesystem::path& file, const std::string& label,
                          std::vector<std::string>* errors);

// The same checks for YAML text already in memory (the size limit applies to the text).
YAML::Node load_yaml_text(const std::string& text, const std::string& label,
                          std::vector<std::string>* errors);

// load_yaml_file that throws InputError (the messages joined by "; ") instead of collecting.
YAML::Node load_yaml_file_or_throw(const std::filesystem::path& file, const std::string& label);

// The problems of an already parsed tree (non-scalar keys, duplicate keys, depth), appended to
// *errors; true when there were none.
bool check_yaml_tree(const YAML::Node& root, const std::string& label,
                     std::vector<std::string>* errors);

// A mapping key usable as a name: a scalar, not null, not empty.
bool is_name_key(const YAML::Node& key);

}  // namespace chatterlab::app
