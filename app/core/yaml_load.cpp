#include "app/core/yaml_load.h"

#include <fstream>
#include <map>
#include <sstream>

#include "analysis/common/summary.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;

// Messages kept for one file: the first problems are enough to fix it.
constexpr size_t kMaxMessages = 20;

std::string line_of(const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  return m.is_null() ? std::string("?") : std::to_string(m.line + 1);
}

std::string kind_of(const YAML::Node& n) {
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a mapping";
  if (n.IsNull()) return "null";
  if (n.IsScalar() && n.Scalar().empty()) return "empty";
  return "'" + n.Scalar() + "'";
}

std::string where(const std::string& path) {
  return path.empty() ? "at the top level" : "under '" + path + "'";
}

class TreeCheck {
 public:
  TreeCheck(std::string label, std::vector<std::string>* errors)
      : label_(std::move(label)), errors_(errors) {}

  void walk(const YAML::Node& n, const std::string& path, int depth) {
    if (stop_) return;
    if (++visited_ > kYamlMaxNodes) {
      add("more than " + std::to_string(kYamlMaxNodes) +
          " nodes once aliases are expanded (a YAML spec of the format has a few hundred)");
      stop_ = true;
      return;
    }
    if (!n.IsMap() && !n.IsSequence()) return;
    if (depth > kYamlMaxDepth) {
      add((path.empty() ? std::string("the document") : "key '" + path + "'") + " (line " +
          line_of(n) + ") nests deeper than " + std::to_string(kYamlMaxDepth) +
          " levels of mappings and lists");
      stop_ = true;
      return;
    }
    if (n.IsSequence()) {
      size_t i = 0;
      for (const auto& e : n) walk(e, path + "[" + std::to_string(i++) + "]", depth + 1);
      return;
    }
    std::map<std::string, std::string> seen;  // key -> line of its first occurrence
    for (const auto& kv : n) {
      if (stop_) return;
      const YAML::Node& key = kv.first;
      if (!is_name_key(key)) {
        add("a key " + where(path) + " (line " + line_of(key) + ") is " + kind_of(key) +
            ", not a name: every key must be a plain scalar such as 'scale'");
        continue;
      }
      const std::string& k = key.Scalar();
      const std::string child = path.empty() ? k : path + "." + k;
      const auto [it, fresh] = seen.emplace(k, line_of(key));
      if (!fresh) {
        add("key '" + child + "' appears twice in one mapping (lines " + it->second + " and " +
            line_of(key) + "): a duplicate key is refused, remove one");
      }
      walk(kv.second, child, depth + 1);
    }
  }

 private:
  void add(const std::string& what) {
    if (count_++ < kMaxMessages) {
      errors_->push_back(label_ + ": " + what);
    } else if (count_ == kMaxMessages + 1) {
      errors_->push_back(label_ + ": further problems not listed");
    }
  }

  std::string label_;
  std::vector<std::string>* errors_;
  long visited_ = 0;
  size_t count_ = 0;
  bool stop_ = false;
};

}  // namespace

bool is_name_key(const YAML::Node& key) { return key.IsScalar() && !key.Scalar().empty(); }

bool check_yaml_tree(const YAML::Node& root, const std::string& label,
                     std::vector<std::string>* errors) {
  const size_t before = errors->size();
  TreeCheck(label, errors).walk(root, "", 0);
  return errors->size() == before;
}

YAML::Node load_yaml_text(const std::string& text, const std::string& label,
                          std::vector<std::string>* errors) {
  if (text.size() > kYamlMaxFileBytes) {
    errors->push_back(label + ": " + std::to_string(text.size()) + " bytes, more than the " +
                      std::to_string(kYamlMaxFileBytes) + " bytes (1 MiB) a YAML file may have");
    return YAML::Node(YAML::NodeType::Undefined);
  }
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    errors->push_back(label + ": not valid YAML (" + e.what() + ")");
    return YAML::Node(YAML::NodeType::Undefined);
  }
  if (!check_yaml_tree(root, label, errors)) return YAML::Node(YAML::NodeType::Undefined);
  return root;
}

YAML::Node load_yaml_file(const fs::path& file, const std::string& label,
                          std::vector<std::string>* errors) {
  const YAML::Node none(YAML::NodeType::Undefined);
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (ec || !fs::exists(st)) {
    errors->push_back(label + ": file not found");
    return none;
  }
  if (!fs::is_regular_file(st)) {
    errors->push_back(label + ": not a regular file");
    return none;
  }
  const std::uintmax_t size = fs::file_size(file, ec);
  if (!ec && size > kYamlMaxFileBytes) {
    errors->push_back(label + ": " + std::to_string(size) + " bytes, more than the " +
                      std::to_string(kYamlMaxFileBytes) +
                      " bytes (1 MiB) a YAML file may have; not read");
    return none;
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    errors->push_back(label + ": cannot be opened for reading");
    return none;
  }
  // Read in blocks, at most one block past the limit: a file growing after the size check is
  // still refused (load_yaml_text checks the length), and a small file costs a small buffer
  // (a buffer of the limit's size took most of the time of loading a campaign).
  std::string text;
  text.reserve(ec ? 0 : static_cast<size_t>(size) + 1);
  char block[16384];
  while (text.size() <= kYamlMaxFileBytes && in.read(block, sizeof block).gcount() > 0) {
    text.append(block, static_cast<size_t>(in.gcount()));
  }
  if (in.bad()) {
    errors->push_back(label + ": read error");
    return none;
  }
  return load_yaml_text(text, label, errors);
}

YAML::Node load_yaml_file_or_throw(const fs::path& file, const std::string& label) {
  std::vector<std::string> errors;
  YAML::Node n = load_yaml_file(file, label, &errors);
  if (!errors.empty()) {
    std::string msg;
    for (const auto& e : errors) msg += (msg.empty() ? "" : "; ") + e;
    throw InputError(msg);
  }
  return n;
}

}  // namespace chatterlab::app
