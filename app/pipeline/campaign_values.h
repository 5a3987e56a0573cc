// Values that tests and group products provide to others, by name (each provider kind declares
// its names and their types in its own header, e.g. value::kHammerModeX in tap_kind.h): the
// hammer-test mode of each axis, the dynamometer cutting coefficients, a dynamometer or spindle FRF
// model, a sensor calibration, identified values. A value may have several providers (two tap tests
// of one axis); readers take them in provider order (test id order), so results do not depend on
// which thread finished first. A provider whose step failed is recorded too, so a consumer
// can say why the value is missing.
#pragma once

#include <any>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "analysis/common/check.h"

namespace chatterlab::app {

class CampaignValues {
 public:
  struct Entry {
    std::string provider;    // test id or "group:<name>"
    bool has_value = false;  // false: the provider failed (why)
    std::string why;         // the provider's failure when !ok
    std::any value;
  };

  // Thread-safe: providers of one level of the campaign publish concurrently.
  template <class T>
  void put(const std::string& name, const std::string& provider, T v) {
    std::lock_guard<std::mutex> lock(*mutex_);
    insert(name, Entry{provider, true, "", std::any(std::move(v))});
  }
  void fail(const std::string& name, const std::string& provider, const std::string& why) {
    std::lock_guard<std::mutex> lock(*mutex_);
    insert(name, Entry{provider, false, why, {}});
  }

  // The first provider's value (by provider id), nullptr when no provider succeeded.
  template <class T>
  const T* first(const std::string& name, std::string* provider = nullptr) const {
    const auto it = entries_.find(name);
    if (it == entries_.end()) return nullptr;
    for (const auto& e : it->second) {
      if (!e.has_value) continue;
      if (provider) *provider = e.provider;
      return checked_cast<T>(name, e);
    }
    return nullptr;
  }
  // Every provider's value in provider order, with the provider ids.
  template <class T>
  std::vector<std::pair<std::string, const T*>> all(const std::string& name) const {
    std::vector<std::pair<std::string, const T*>> out;
    const auto it = entries_.find(name);
    if (it == entries_.end()) return out;
    for (const auto& e : it->second) {
      if (e.has_value) out.emplace_back(e.provider, checked_cast<T>(name, e));
    }
    return out;
  }
  // Whether `provider` recorded `name` (a value or a failure).
  bool has_entry(const std::string& name, const std::string& provider) const;
  // Why `name` has no value: "needs <description> from <provider>, which was skipped: <why>"
  // for the first failed provider, or "needs <description>, which no test of the campaign
  // provides". Empty when a provider succeeded. `description` says what the value is ("the
  // hammer-test mode of x"); empty: the name in quotes.
  std::string why_missing(const std::string& name, const std::string& description = "") const;

 private:
  // A reader asking for another type than the provider put is a broken invariant (the value
  // would silently look missing).
  template <class T>
  static const T* checked_cast(const std::string& name, const Entry& e) {
    const T* v = std::any_cast<T>(&e.value);
    CHATTERLAB_CHECK(v != nullptr, "value '" + name + "' from " + e.provider +
                                       " read as another type than it was provided");
    return v;
  }
  void insert(const std::string& name, Entry e);
  std::map<std::string, std::vector<Entry>> entries_;
  std::unique_ptr<std::mutex> mutex_ = std::make_unique<std::mutex>();  // movable values
};

}  // namespace chatterlab::app
