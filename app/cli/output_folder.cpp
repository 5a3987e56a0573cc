#include "app/cli/output_folder.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "analysis/common/summary.h"

namespace chatterlab::app {
namespace fs = std::filesystem;

namespace {

const char* const kManifestHeader =
    "# chatterlab: the files the last run wrote in this folder, removed by the next run into it";

// A relative path that stays inside the folder ("a/b.svg", not "/x", "../x" or "a/../../x").
bool stays_inside(const std::string& relative) {
  if (relative.empty()) return false;
  const fs::path p = fs::path(relative).lexically_normal();
  if (p.empty() || p.is_absolute() || p.has_root_name() || p.has_root_directory()) return false;
  for (const auto& part : p) {
    if (part == "..") return false;
  }
  return p != ".";
}

// Every string value of a JSON document (the paths an old results.json names).
void strings_of(const nlohmann::json& j, std::vector<std::string>& out) {
  if (j.is_string()) {
    out.push_back(j.get<std::string>());
  } else if (j.is_structured()) {
    for (const auto& v : j) strings_of(v, out);
  }
}

// The files a run wrote, for a chatterlab folder without a manifest (written by a version
// before manifests): the fixed names, figures/, and what results.json names.
std::vector<std::string> legacy_files(const fs::path& dir) {
  std::vector<std::string> files = {"index.html", "report.pdf", "report.css", "results.json"};
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(dir / "figures", ec))) {
    for (const auto& f : files_below(dir / "figures")) files.push_back("figures/" + f);
  }
  try {
    std::ifstream in(dir / "results.json");
    std::vector<std::string> values;
    strings_of(nlohmann::json::parse(in), values);
    for (const auto& v : values) {
      if (v.size() < 256 && stays_inside(v) && fs::is_regular_file(dir / v, ec)) {
        files.push_back(fs::path(v).lexically_normal().generic_string());
      }
    }
  } catch (const std::exception&) {
  }
  return files;
}

}  // namespace

std::vector<std::string> files_below(const fs::path& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const auto st = it->symlink_status(ec);
    if (ec) break;
    if (fs::is_regular_file(st) || fs::is_symlink(st)) {
      out.push_back(fs::relative(it->path(), dir, ec).generic_string());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

OutputFolder OutputFolder::open(const fs::path& dir) {
  OutputFolder f;
  f.dir_ = dir.filename().empty() && dir.has_parent_path() ? dir.parent_path() : dir;
  std::error_code ec;
  const auto st = fs::status(f.dir_, ec);
  if (!fs::exists(st)) return f;
  if (!fs::is_directory(st)) {
    throw InputError("--out " + dir.string() + ": exists and is not a folder");
  }
  f.had_manifest_ = fs::is_regular_file(fs::symlink_status(f.dir_ / kManifestName, ec));
  if (f.had_manifest_ || is_chatterlab_results(f.dir_ / "results.json")) return f;
  if (fs::directory_iterator(f.dir_, ec) != fs::directory_iterator()) {
    throw InputError("--out " + dir.string() +
                     ": the folder is not empty and is not a chatterlab output folder (it has "
                     "neither " +
                     kManifestName +
                     " nor a chatterlab results.json); chatterlab writes only into a new, "
                     "empty or chatterlab folder and removes nothing here: choose another "
                     "--out");
  }
  return f;
}

int OutputFolder::clear_previous() {
  cleared_ = true;
  std::error_code ec;
  if (!fs::is_directory(dir_, ec)) return 0;
  std::vector<std::string> listed;
  if (had_manifest_) {
    std::ifstream in(dir_ / kManifestName);
    for (std::string line; std::getline(in, line);) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.empty() || line[0] == '#') continue;
      listed.push_back(line);
    }
  } else if (is_chatterlab_results(dir_ / "results.json")) {
    listed = legacy_files(dir_);
  }
  const fs::path root = fs::weakly_canonical(fs::absolute(dir_), ec);
  const auto inside_root = [&](const fs::path& p) {
    std::error_code e;
    const fs::path c = fs::weakly_canonical(p, e);
    if (e) return false;
    const auto rel = c.lexically_relative(root);
    return !rel.empty() && *rel.begin() != "..";
  };
  int removed = 0;
  std::set<fs::path> parents;
  for (const auto& rel : listed) {
    if (!stays_inside(rel) || rel == kManifestName) continue;
    const fs::path p = dir_ / fs::path(rel).lexically_normal();
    // The folder holding it must resolve inside the output folder (no linked folder on the
    // way out); the entry itself is removed as it is (a link, not its target).
    if (p.parent_path() != dir_ && !inside_root(p.parent_path())) continue;
    const auto st = fs::symlink_status(p, ec);
    if (!fs::is_regular_file(st) && !fs::is_symlink(st)) continue;
    if (fs::remove(p, ec)) {
      ++removed;
      for (fs::path q = p.parent_path(); q != dir_ && q.native().size() > dir_.native().size();
           q = q.parent_path()) {
        parents.insert(q);
      }
    }
  }
  // Folders the removal emptied, deepest first (a folder never listed stays when not empty).
  std::vector<fs::path> folders(parents.begin(), parents.end());
  std::sort(folders.begin(), folders.end(), [](const fs::path& a, const fs::path& b) {
    return std::distance(a.begin(), a.end()) > std::distance(b.begin(), b.end());
  });
  for (const auto& q : folders) {
    const auto st = fs::symlink_status(q, ec);
    if (fs::is_directory(st) && fs::is_empty(q, ec) && !ec) fs::remove(q, ec);
  }
  fs::remove(dir_ / kManifestName, ec);
  for (const auto& rel : files_below(dir_)) {
    const fs::path p = dir_ / rel;
    const auto t = fs::last_write_time(p, ec);
    const auto size = fs::is_regular_file(fs::symlink_status(p, ec)) ? fs::file_size(p, ec) : 0;
    kept_[rel] = {t, size};
  }
  return removed;
}

void OutputFolder::write_manifest() const {
  std::error_code ec;
  if (!cleared_ || !fs::is_directory(dir_, ec)) return;
  std::ofstream out(dir_ / kManifestName);
  out << kManifestHeader << "\n";
  for (const auto& rel : files_below(dir_)) {
    if (rel == kManifestName) continue;
    const auto it = kept_.find(rel);
    if (it != kept_.end()) {
      const fs::path p = dir_ / rel;
      const auto t = fs::last_write_time(p, ec);
      const auto size = fs::is_regular_file(fs::symlink_status(p, ec)) ? fs::file_size(p, ec) : 0;
      if (t == it->second.first && size == it->second.second) continue;  // not ours
    }
    out << rel << "\n";
  }
}

bool is_chatterlab_results(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return false;
  try {
    std::ifstream in(file);
    const auto j = nlohmann::json::parse(in);
    return j.is_object() && j.contains("format") && j["format"].is_string() &&
           j["format"].get<std::string>().rfind("chatterlab-", 0) == 0;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace chatterlab::app
