#include "app/nightly/cache_keys.h"

#include <algorithm>
#include <functional>
#include <set>
#include <stdexcept>

#include "app/core/hashing.h"
#include "app/core/input_boundary.h"
#include "app/pipeline/kind.h"

namespace chatterlab::app {
namespace {

std::string node_name(const TestSpec& t) { return t.id.empty() ? "." : t.id; }

// A file's hash, or "missing" when it is absent, unreadable or outside the campaign.
std::string file_hash(const CampaignSpec& c, const fs::path& p) {
  if (p.empty() || !regular_file_inside(c.root, p)) return "missing";
  try {
    return sha256_file(p);
  } catch (const std::exception&) {
    return "missing";
  }
}

struct Node {
  std::string own;                 // the node's own inputs, as text
  std::vector<std::string> needs;  // value names, sorted
};

}  // namespace

CampaignKeys campaign_keys(const CampaignSpec& c, const std::string& program,
                           const KindRegistry& kinds) {
  const std::string shared = "program " + program + "\ncampaign.yaml " +
                             file_hash(c, c.root / "campaign.yaml") + "\ntruth.yaml " +
                             (c.has_truth ? file_hash(c, c.truth_file) : "none") + "\n";
  std::map<std::string, Node> nodes;
  std::map<std::string, std::set<std::string>> providers;  // value -> node names
  for (const auto& t : c.tests) {
    Node n;
    n.own = "test " + node_name(t) + "\nkind " + t.kind + "\ntest.yaml " +
            file_hash(c, t.folder / "test.yaml") + "\ndata " + file_hash(c, t.data.file) + "\n";
    if (const TestKind* kind = kinds.find(t.kind)) {
      if (t.usable()) {
        for (const auto& f : kind->input_files(t)) {
          n.own +=
              "file " + fs::relative(f, c.root).generic_string() + " " + file_hash(c, f) + "\n";
        }
        for (const auto& need : kind->needs(t)) n.needs.push_back(need.value);
      }
      for (const auto& v : kind->provides(t)) providers[v].insert(node_name(t));
    }
    std::sort(n.needs.begin(), n.needs.end());
    nodes[node_name(t)] = std::move(n);
  }
  for (const auto& g : kinds.groups()) {
    if (!g->applies(c)) continue;
    const std::string name = "group:" + g->name();
    Node n;
    n.own = name + "\n";
    for (const auto& need : g->needs(c)) n.needs.push_back(need.value);
    std::sort(n.needs.begin(), n.needs.end());
    for (const auto& v : g->provides(c)) providers[v].insert(name);
    nodes[name] = std::move(n);
  }

  std::map<std::string, std::string> keys;
  std::map<std::string, std::set<std::string>> uses;  // node -> the nodes it takes values from
  std::set<std::string> visiting;
  std::function<const std::string&(const std::string&)> key_of =
      [&](const std::string& name) -> const std::string& {
    if (const auto it = keys.find(name); it != keys.end()) return it->second;
    if (!visiting.insert(name).second) {
      throw std::logic_error("cache keys: the kinds' needs and provides form a cycle at " + name);
    }
    const Node& n = nodes.at(name);
    std::string text = shared + n.own;
    for (const auto& v : n.needs) {
      text += "need " + v + " <-";
      if (const auto p = providers.find(v); p != providers.end()) {
        for (const auto& from : p->second) {
          if (from == name) continue;
          text += " " + from + "=" + key_of(from);
          uses[name].insert(from);
        }
      }
      text += "\n";
    }
    visiting.erase(name);
    return keys[name] = sha256_text(text);
  };

  CampaignKeys out;
  for (const auto& t : c.tests) out.tests[node_name(t)] = key_of(node_name(t));
  for (const auto& [name, n] : nodes) {
    if (name.rfind("group:", 0) == 0) out.groups[name] = key_of(name);
  }
  // Dependents: the tests whose keys hold a test's key, through groups as well.
  for (const auto& t : c.tests) {
    std::set<std::string> found;
    std::vector<std::string> stack{node_name(t)};
    while (!stack.empty()) {
      const std::string from = stack.back();
      stack.pop_back();
      for (const auto& [user, sources] : uses) {
        if (sources.count(from) && found.insert(user).second) stack.push_back(user);
      }
    }
    std::vector<std::string>& d = out.dependents[node_name(t)];
    for (const auto& f : found) {
      if (f.rfind("group:", 0) != 0) d.push_back(f);
    }
  }
  return out;
}

}  // namespace chatterlab::app
