// The per-test cache of a nightly site (docs/nightly.md#the-per-test-cache): for each test and
// group of a campaign, the bytes of its kind's result (app/core/archive.h) as the last run left
// them, under the cache key they were computed with. A run gives the pipeline a
// SiteResultCache; a node whose key is unchanged is restored from it, the others are computed
// and their bytes kept for the database.
#pragma once

#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "app/pipeline/pipeline.h"

namespace chatterlab::app {

// zlib, with the length in front. decompress_bytes throws InputError on damaged bytes.
std::string compress_bytes(const std::string& bytes);
std::string decompress_bytes(const std::string& compressed);

class SiteResultCache : public ResultCache {
 public:
  struct Stored {
    std::string key;
    std::string compressed;
  };
  // `keys`: this run's cache key of each node (test ids, "group:<name>"); `stored`: what the
  // site holds for the campaign.
  SiteResultCache(std::map<std::string, std::string> keys, std::map<std::string, Stored> stored);

  std::optional<std::string> find(const std::string& name) const override;
  void keep(const std::string& name, std::string bytes) override;

  // The nodes restored in this run, sorted.
  std::vector<std::string> restored() const;
  // What the database keeps for `name` after the run: the bytes computed now, else the stored
  // ones when they were restored; nothing for a node that did not succeed or is not cacheable.
  std::optional<std::string> compressed_to_store(const std::string& name) const;
  // The bytes computed in this run, compressed (a Slurm task hands them to its reduce job).
  const std::map<std::string, std::string>& kept() const { return kept_; }
  // Takes the bytes and the restored list a Slurm task recorded.
  void adopt(std::map<std::string, std::string> kept, const std::vector<std::string>& restored);

 private:
  std::map<std::string, std::string> keys_;
  std::map<std::string, Stored> stored_;
  mutable std::mutex mutex_;
  mutable std::set<std::string> restored_;
  std::map<std::string, std::string> kept_;
};

template <class Ar>
void fields(Ar& ar, SiteResultCache::Stored& s) {
  ar(s.key, s.compressed);
}

// What a Slurm task hands its reduce job for the per-test cache (<site>/slurm/run-N/out/
// <name>.cache): the nodes it computed (compressed bytes) and those it restored.
struct TaskCache {
  std::map<std::string, std::string> kept;
  std::vector<std::string> restored;
};
template <class Ar>
void fields(Ar& ar, TaskCache& c) {
  ar(c.kept, c.restored);
}

// A whole file as bytes. @throws InputError naming it when it cannot be read
std::string read_file_bytes(const std::filesystem::path& file);

}  // namespace chatterlab::app
