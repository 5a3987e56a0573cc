#include "app/nightly/test_cache.h"

#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "analysis/common/summary.h"

namespace chatterlab::app {

std::string compress_bytes(const std::string& bytes) {
  uLongf size = compressBound(static_cast<uLong>(bytes.size()));
  std::string out(sizeof(std::uint64_t) + size, '\0');
  const std::uint64_t n = bytes.size();
  std::memcpy(out.data(), &n, sizeof n);
  // Level 1: the doubles of a result hardly compress; the text and zeros do, quickly.
  const int rc =
      compress2(reinterpret_cast<Bytef*>(out.data() + sizeof n), &size,
                reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uLong>(bytes.size()), 1);
  if (rc != Z_OK) throw std::runtime_error("zlib compress2 failed (" + std::to_string(rc) + ")");
  out.resize(sizeof n + size);
  return out;
}

std::string decompress_bytes(const std::string& compressed) {
  std::uint64_t n = 0;
  if (compressed.size() < sizeof n) throw InputError("a cached result is damaged (too short)");
  std::memcpy(&n, compressed.data(), sizeof n);
  // zlib expands at most about 1032:1.
  if (n > 1032 * static_cast<std::uint64_t>(compressed.size()) + 64) {
    throw InputError("a cached result is damaged (impossible length)");
  }
  std::string out(static_cast<std::size_t>(n), '\0');
  uLongf size = static_cast<uLongf>(n);
  const int rc = uncompress(reinterpret_cast<Bytef*>(out.data()), &size,
                            reinterpret_cast<const Bytef*>(compressed.data() + sizeof n),
                            static_cast<uLong>(compressed.size() - sizeof n));
  if (rc != Z_OK || size != n) throw InputError("a cached result is damaged (zlib)");
  return out;
}

SiteResultCache::SiteResultCache(std::map<std::string, std::string> keys,
                                 std::map<std::string, Stored> stored)
    : keys_(std::move(keys)), stored_(std::move(stored)) {}

std::optional<std::string> SiteResultCache::find(const std::string& name) const {
  const auto k = keys_.find(name);
  const auto s = stored_.find(name);
  if (k == keys_.end() || s == stored_.end() || s->second.key != k->second ||
      s->second.compressed.empty()) {
    return std::nullopt;
  }
  std::string bytes;
  try {
    bytes = decompress_bytes(s->second.compressed);
  } catch (const InputError&) {
    return std::nullopt;  // damaged: computed
  }
  std::lock_guard<std::mutex> lock(mutex_);
  restored_.insert(name);
  return bytes;
}

void SiteResultCache::keep(const std::string& name, std::string bytes) {
  std::string c = compress_bytes(bytes);
  std::lock_guard<std::mutex> lock(mutex_);
  kept_[name] = std::move(c);
}

std::vector<std::string> SiteResultCache::restored() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {restored_.begin(), restored_.end()};
}

std::optional<std::string> SiteResultCache::compressed_to_store(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (const auto k = kept_.find(name); k != kept_.end()) return k->second;
  if (const auto s = stored_.find(name); restored_.count(name) && s != stored_.end()) {
    return s->second.compressed;
  }
  return std::nullopt;
}

void SiteResultCache::adopt(std::map<std::string, std::string> kept,
                            const std::vector<std::string>& restored) {
  std::lock_guard<std::mutex> lock(mutex_);
  kept_ = std::move(kept);
  restored_ = {restored.begin(), restored.end()};
}

std::string read_file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in && !in.eof()) throw InputError(file.string() + ": cannot be read");
  if (!in.is_open()) throw InputError(file.string() + ": cannot be opened");
  return bytes.str();
}

}  // namespace chatterlab::app
