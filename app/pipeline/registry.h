// The test kinds and group products the program knows, registered explicitly
// (register_builtin_kinds(), one line per kind; no static-initialisation tricks).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "app/pipeline/kind.h"

namespace chatterlab::app {

class KindRegistry {
 public:
  void add(std::unique_ptr<TestKind> kind);
  void add(std::unique_ptr<GroupProduct> group);

  // nullptr for an unknown kind name.
  const TestKind* find(const std::string& name) const;
  const GroupProduct* find_group(const std::string& name) const;
  // In registration order (the report's section order).
  const std::vector<std::unique_ptr<TestKind>>& kinds() const { return kinds_; }
  const std::vector<std::unique_ptr<GroupProduct>>& groups() const { return groups_; }
  // Kinds and group products interleaved in registration order: the report's section order.
  struct Entry {
    const TestKind* kind = nullptr;  // exactly one of the two is set
    const GroupProduct* group = nullptr;
  };
  const std::vector<Entry>& in_order() const { return order_; }
  // What value `name` is, from the kind or group that provides it ("" when none says).
  std::string describe_value(const std::string& name) const;
  // "tap, dyno-slot, cut": for messages.
  std::string names() const;

 private:
  std::vector<std::unique_ptr<TestKind>> kinds_;
  std::vector<std::unique_ptr<GroupProduct>> groups_;
  std::vector<Entry> order_;
};

// Adds every built-in kind and group product to `registry` (app/pipeline/builtin_kinds.cpp).
void register_builtin_kinds(KindRegistry& registry);

// The registry holding the built-in kinds, built on first use by register_builtin_kinds().
const KindRegistry& builtin_kinds();

}  // namespace chatterlab::app
