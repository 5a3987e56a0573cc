#include "app/pipeline/campaign_values.h"

#include <algorithm>

namespace chatterlab::app {

void CampaignValues::insert(const std::string& name, Entry e) {
  auto& list = entries_[name];
  const auto at =
      std::upper_bound(list.begin(), list.end(), e.provider,
                       [](const std::string& p, const Entry& x) { return p < x.provider; });
  list.insert(at, std::move(e));
}

bool CampaignValues::has_entry(const std::string& name, const std::string& provider) const {
  std::lock_guard<std::mutex> lock(*mutex_);
  const auto it = entries_.find(name);
  if (it == entries_.end()) return false;
  return std::any_of(it->second.begin(), it->second.end(),
                     [&](const Entry& e) { return e.provider == provider; });
}

std::string CampaignValues::why_missing(const std::string& name,
                                        const std::string& description) const {
  const auto it = entries_.find(name);
  const std::string what = description.empty() ? "'" + name + "'" : description;
  if (it == entries_.end() || it->second.empty()) {
    return "needs " + what + ", which no test of the campaign provides";
  }
  for (const auto& e : it->second) {
    if (e.has_value) return "";
  }
  const Entry& e = it->second.front();
  return "needs " + what + " from " + e.provider + ", which was skipped: " + e.why;
}

}  // namespace chatterlab::app
