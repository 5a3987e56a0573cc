#include "app/cli/output_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "analysis/common/summary.h"

#ifndef RENAME_EXCHANGE
#define RENAME_EXCHANGE (1 << 1)  // <linux/fs.h>
#endif

namespace chatterlab::app {
namespace fs = std::filesystem;

namespace {

const char* const kManifestHeader =
    "# chatterlab: the files the last run wrote in this folder, replaced by the next run into it";

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

std::string errno_text(int e) { return std::strerror(e); }

// Exchanges two paths atomically (Linux renameat2); false with errno when it cannot.
bool exchange(const fs::path& a, const fs::path& b) {
#ifdef SYS_renameat2
  return ::syscall(SYS_renameat2, AT_FDCWD, a.c_str(), AT_FDCWD, b.c_str(), RENAME_EXCHANGE) == 0;
#else
  errno = ENOSYS;
  return false;
#endif
}

std::string random_suffix() {
  std::random_device rd;
  char buf[16];
  std::snprintf(buf, sizeof buf, "%08x", static_cast<unsigned>(rd()));
  return buf;
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
      out.push_back(it->path().lexically_relative(dir).generic_string());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Flushes a file or folder to the disk (fsync); false with errno when it cannot.
bool flush_to_disk(const fs::path& p, bool folder) {
  const int fd = ::open(p.c_str(), (folder ? O_DIRECTORY : 0) | O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  const int e = errno;
  ::close(fd);
  errno = e;
  return ok;
}

// Every regular file below `dir`, then every folder from the deepest up to `dir` itself, flushed
// to the disk: the new output is on the disk before it replaces the previous one, so that a
// power cut after the exchange cannot leave a report of empty files.
void flush_tree(const fs::path& dir, const std::string& shown) {
  std::vector<fs::path> folders{dir};
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const auto st = it->symlink_status(ec);
    if (ec) break;
    if (fs::is_directory(st)) {
      folders.push_back(it->path());
    } else if (fs::is_regular_file(st) && !flush_to_disk(it->path(), false)) {
      throw InputError(shown + ": cannot flush " + it->path().string() +
                       " to the disk: " + std::strerror(errno) + "; nothing replaced");
    }
  }
  if (ec) throw InputError(shown + ": cannot list " + dir.string() + ": " + ec.message());
  for (auto f = folders.rbegin(); f != folders.rend(); ++f) {
    if (!flush_to_disk(*f, true)) {
      throw InputError(shown + ": cannot flush " + f->string() +
                       " to the disk: " + std::strerror(errno) + "; nothing replaced");
    }
  }
}

// The folder holding `p` flushed (its new entry on the disk); best effort, after the rename.
void flush_parent(const fs::path& p) {
  flush_to_disk(p.parent_path().empty() ? fs::path(".") : p.parent_path(), true);
}

std::vector<std::string> chatterlab_files(const fs::path& dir) {
  std::vector<std::string> listed;
  std::error_code ec;
  if (fs::is_regular_file(fs::symlink_status(dir / kManifestName, ec))) {
    std::ifstream in(dir / kManifestName);
    for (std::string line; std::getline(in, line);) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.empty() || line[0] == '#') continue;
      listed.push_back(line);
    }
  } else if (is_chatterlab_results(dir / "results.json")) {
    listed = legacy_files(dir);
  }
  std::vector<std::string> out;
  for (const auto& rel : listed) {
    if (stays_inside(rel)) out.push_back(fs::path(rel).lexically_normal().generic_string());
  }
  out.push_back(kManifestName);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

OutputFolder::OutputFolder(const fs::path& out) {
  dir_ = out.lexically_normal();
  if (dir_.filename().empty() && dir_.has_parent_path()) dir_ = dir_.parent_path();
  name_ = dir_.filename().string();
  const std::string shown = "--out " + out.string();
  std::error_code ec;
  {
    const fs::path cwd = fs::current_path(ec);
    const fs::path o = fs::weakly_canonical(fs::absolute(dir_), ec);
    const fs::path r = cwd.lexically_relative(o);
    if (name_.empty() || name_ == "." || name_ == ".." || dir_ == dir_.root_path() ||
        (!ec && !r.empty() && *r.begin() != "..")) {
      throw InputError(shown +
                       ": is the current folder or holds it; the output replaces the whole "
                       "folder: give a folder below the current one or elsewhere");
    }
  }
  const auto lst = fs::symlink_status(dir_, ec);
  if (fs::is_symlink(lst)) {
    throw InputError(shown +
                     ": is a symbolic link; chatterlab never writes through a link: give the "
                     "folder it points to, or another --out");
  }
  if (fs::exists(lst) && !fs::is_directory(lst)) {
    throw InputError(shown + ": exists and is not a folder");
  }
  const fs::path parent = dir_.parent_path();
  if (!parent.empty()) {
    fs::create_directories(parent, ec);
    if (ec) throw InputError(shown + ": cannot create " + parent.string() + ": " + ec.message());
  }
  // The lock first: the checks below read a folder that another run could be replacing.
  const fs::path lock = parent / ("." + name_ + ".chatterlab-lock");
  lock_fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0666);
  if (lock_fd_ < 0) {
    throw InputError(shown + ": cannot open the lock file " + lock.string() + ": " +
                     errno_text(errno));
  }
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const int e = errno;
    ::close(lock_fd_);
    lock_fd_ = -1;
    if (e == EWOULDBLOCK) {
      throw InputError(shown + ": another chatterlab run is writing this folder (it holds " +
                       lock.string() + "); wait until it ends");
    }
    throw InputError(shown + ": cannot lock " + lock.string() + ": " + errno_text(e));
  }
  try {
    if (fs::is_directory(fs::symlink_status(dir_, ec)) &&
        !fs::is_regular_file(fs::symlink_status(dir_ / kManifestName, ec)) &&
        !is_chatterlab_results(dir_ / "results.json") &&
        fs::directory_iterator(dir_, ec) != fs::directory_iterator()) {
      throw InputError(shown +
                       ": the folder is not empty and is not a chatterlab output folder (it has "
                       "neither " +
                       kManifestName +
                       " nor a chatterlab results.json); chatterlab writes only into a new, "
                       "empty or chatterlab folder and removes nothing here: choose another "
                       "--out");
    }
    // Temporary folders of runs that were killed (the lock is ours: none is running).
    const std::string tmp_prefix = "." + name_ + ".chatterlab-tmp-";
    const fs::path scan = parent.empty() ? fs::path(".") : parent;
    std::vector<fs::path> stale;
    for (fs::directory_iterator it(scan, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string n = it->path().filename().string();
      if (n.rfind(tmp_prefix, 0) == 0 && fs::is_directory(it->symlink_status(ec))) {
        stale.push_back(parent / n);
      }
    }
    for (const auto& s : stale) fs::remove_all(s, ec);
    for (int attempt = 0;; ++attempt) {
      const fs::path w = parent / (tmp_prefix + std::to_string(::getpid()) + "-" + random_suffix());
      if (::mkdir(w.c_str(), 0777) == 0) {
        work_ = w;
        break;
      }
      if (errno != EEXIST || attempt > 100) {
        throw InputError(shown + ": cannot create the temporary folder " + w.string() + ": " +
                         errno_text(errno));
      }
    }
    // The new folder gets the permissions of the one it replaces.
    struct stat st {};
    if (::lstat(dir_.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
      ::chmod(work_.c_str(), st.st_mode & 07777);
    }
  } catch (...) {
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw;
  }
}

OutputFolder::~OutputFolder() {
  std::error_code ec;
  if (!committed_ && !work_.empty()) fs::remove_all(work_, ec);
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

int OutputFolder::commit() {
  const std::string shown = "--out " + dir_.string();
  std::error_code ec;
  // The manifest: everything the run wrote.
  std::string manifest = std::string(kManifestHeader) + "\n";
  for (const auto& rel : files_below(work_)) {
    if (rel != kManifestName) manifest += rel + "\n";
  }
  write_file_checked(work_ / kManifestName, manifest);

  // The previous folder's files that are not the program's: carried into the new one.
  int carried = 0;
  const auto lst = fs::symlink_status(dir_, ec);
  if (fs::is_symlink(lst)) {
    throw InputError(shown + ": became a symbolic link during the run; nothing replaced");
  }
  const bool previous = fs::is_directory(lst);
  if (previous) {
    const std::vector<std::string> ours = chatterlab_files(dir_);
    for (const auto& rel : files_below(dir_)) {
      if (std::binary_search(ours.begin(), ours.end(), rel)) continue;
      const fs::path from = dir_ / rel, to = work_ / rel;
      if (fs::exists(fs::symlink_status(to, ec))) continue;  // the new output's file wins
      fs::create_directories(to.parent_path(), ec);
      if (!ec) {
        if (fs::is_symlink(fs::symlink_status(from, ec))) {
          fs::copy_symlink(from, to, ec);
        } else {
          fs::create_hard_link(from, to, ec);
          if (ec) fs::copy_file(from, to, ec);
        }
      }
      if (ec) {
        throw InputError(shown + ": cannot keep your file " + rel + " in the new output (" +
                         ec.message() + "); nothing replaced");
      }
      ++carried;
    }
    flush_tree(work_, shown);
    if (exchange(work_, dir_)) {
      committed_ = true;
      flush_parent(dir_);
      fs::remove_all(work_, ec);  // now the previous output
      return carried;
    }
    if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP) {
      throw InputError(shown + ": cannot replace it with " + work_.string() + ": " +
                       errno_text(errno));
    }
    // No RENAME_EXCHANGE on this file system: the previous output is moved aside first (a run
    // killed between the two renames leaves --out absent and the previous output beside it).
    const fs::path aside = work_.string() + "-previous";
    if (::rename(dir_.c_str(), aside.c_str()) != 0) {
      throw InputError(shown + ": cannot move it aside: " + errno_text(errno));
    }
    if (::rename(work_.c_str(), dir_.c_str()) != 0) {
      const int e = errno;
      ::rename(aside.c_str(), dir_.c_str());
      throw InputError(shown + ": cannot replace it: " + errno_text(e));
    }
    committed_ = true;
    flush_parent(dir_);
    fs::remove_all(aside, ec);
    return carried;
  }
  flush_tree(work_, shown);
  if (::rename(work_.c_str(), dir_.c_str()) != 0) {
    throw InputError(shown + ": cannot move " + work_.string() +
                     " into place: " + errno_text(errno));
  }
  committed_ = true;
  flush_parent(dir_);
  return carried;
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
