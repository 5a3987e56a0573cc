#include "app/pipeline/registry.h"

#include <stdexcept>

namespace chatterlab::app {

void KindRegistry::add(std::unique_ptr<TestKind> kind) {
  if (!kind || find(kind->name())) {
    throw std::logic_error("kind registry: a kind is null or registered twice");
  }
  order_.push_back({kind.get(), nullptr});
  kinds_.push_back(std::move(kind));
}

void KindRegistry::add(std::unique_ptr<GroupProduct> group) {
  if (!group || find_group(group->name())) {
    throw std::logic_error("kind registry: a group product is null or registered twice");
  }
  order_.push_back({nullptr, group.get()});
  groups_.push_back(std::move(group));
}

const TestKind* KindRegistry::find(const std::string& name) const {
  for (const auto& k : kinds_) {
    if (k->name() == name) return k.get();
  }
  return nullptr;
}

const GroupProduct* KindRegistry::find_group(const std::string& name) const {
  for (const auto& g : groups_) {
    if (g->name() == name) return g.get();
  }
  return nullptr;
}

std::string KindRegistry::describe_value(const std::string& name) const {
  for (const auto& k : kinds_) {
    if (auto d = k->describe_value(name); !d.empty()) return d;
  }
  for (const auto& g : groups_) {
    if (auto d = g->describe_value(name); !d.empty()) return d;
  }
  return "";
}

std::string KindRegistry::names() const {
  std::string s;
  for (const auto& k : kinds_) s += (s.empty() ? "" : ", ") + k->name();
  return s;
}

const KindRegistry& builtin_kinds() {
  static const KindRegistry registry = [] {
    KindRegistry r;
    register_builtin_kinds(r);
    return r;
  }();
  return registry;
}

}  // namespace chatterlab::app
