#include "app/pipeline/pipeline.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "analysis/common/stopwatch.h"
#include "app/core/archive.h"
#include "app/core/hashing.h"
#include "app/core/input_boundary.h"
#include "app/core/parallel.h"
#include "app/core/signals.h"
#include "app/core/utf8.h"

namespace chatterlab::app {
namespace {

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

// One test or group product of the campaign's graph.
struct Node {
  std::string name;  // test id ("." for the root) or "group:<name>"
  std::size_t test = kNone;
  const TestKind* kind = nullptr;
  const GroupProduct* group = nullptr;
  std::vector<Need> needs;
  std::vector<std::string> provides;
  int level = 0;
};

std::string node_name(const TestSpec& t) { return t.id.empty() ? "." : t.id; }

std::vector<Node> build_graph(const CampaignSpec& c, const KindRegistry& kinds) {
  std::vector<Node> nodes;
  for (std::size_t i = 0; i < c.tests.size(); ++i) {
    const TestSpec& t = c.tests[i];
    const TestKind* kind = kinds.find(t.kind);
    if (!t.usable() || !kind) continue;
    nodes.push_back({node_name(t), i, kind, nullptr, kind->needs(t), kind->provides(t), 0});
  }
  for (const auto& g : kinds.groups()) {
    if (!g->applies(c)) continue;
    nodes.push_back(
        {"group:" + g->name(), kNone, nullptr, g.get(), g->needs(c), g->provides(c), 0});
  }
  // Level = 1 + the deepest provider's level: repeated relaxation over a small graph; a level
  // beyond the node count means a cycle, which the registry's kinds must never form.
  std::multimap<std::string, std::size_t> providers;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for (const auto& v : nodes[i].provides) providers.emplace(v, i);
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (auto& n : nodes) {
      for (const auto& need : n.needs) {
        const auto [lo, hi] = providers.equal_range(need.value);
        for (auto it = lo; it != hi; ++it) {
          const int want = nodes[it->second].level + 1;
          if (n.level < want) {
            n.level = want;
            changed = true;
          }
        }
      }
      if (n.level > static_cast<int>(nodes.size())) {
        throw std::logic_error("pipeline: the kinds' needs and provides form a cycle at " + n.name);
      }
    }
  }
  return nodes;
}

// Runs `step`, turning exceptions into the outcome's status: InputError is bad input (skipped
// with its message), anything else an internal error.
template <class Outcome, class Step>
void guarded(Outcome& out, Step&& step) {
  try {
    step();
  } catch (const InputError& e) {
    out.status.fail(e.what());
    out.failure = Failure::kInput;
  } catch (const std::exception& e) {
    out.status.fail(std::string("internal error: ") + e.what());
    out.failure = Failure::kInternal;
  }
  if (!out.status.ok() && out.failure == Failure::kNone) out.failure = Failure::kInput;
}

// The first required value that is missing, as the skip reason; empty when all are there.
std::string missing_input(const std::vector<Need>& needs, const CampaignValues& values,
                          const KindRegistry& kinds) {
  for (const auto& n : needs) {
    if (!n.required) continue;
    const std::string why = values.why_missing(n.value, kinds.describe_value(n.value));
    if (!why.empty()) return why;
  }
  return "";
}

// Every value a node declared but did not publish is recorded as failed with the reason, so
// that its consumers can say why it is missing.
void record_unprovided(const Node& n, const StepSummary& status, CampaignValues& values) {
  for (const auto& v : n.provides) {
    if (values.has_entry(v, n.name)) continue;
    values.fail(v, n.name, status.ok() ? "it gave no value" : status.message);
  }
}

// One node: skipped with the reason when a required value is missing, else its step and,
// when that succeeded, its publication; exceptions become the outcome's status (guarded).
template <class Outcome, class Run, class Publish>
void run_node(const Node& n, Outcome& out, CampaignResults& r, Run&& run, Publish&& publish) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string missing = missing_input(n.needs, r.values, *r.kinds);
  if (!missing.empty()) {
    out.status.fail(missing);
    out.failure = Failure::kInput;
  } else {
    guarded(out, run);
  }
  if (out.status.ok()) guarded(out, publish);
  record_unprovided(n, out.status, r.values);
  out.runtime_s = seconds_since(t0);
}

// What the per-test cache keeps of a node besides its kind's bytes.
struct CachedNode {
  StepSummary status;
  std::vector<std::string> warnings;
  double runtime_s = 0;
  std::vector<std::string> members;  // a group's
  std::string bytes;                 // the kind's
};
template <class Ar>
void fields(Ar& ar, CachedNode& c) {
  ar(c.status, c.warnings, c.runtime_s, c.members, c.bytes);
}

// Runs a node, or restores it when the cache holds it (the kind's result read back, then
// published as after a run); a node computed now that succeeded is kept in the cache.
template <class Kind, class Out, class Run, class Restore>
void run_or_restore(const Node& n, const Kind& kind, Out& out, CampaignResults& r, Run&& run,
                    Restore&& restore) {
  ResultCache* cache = r.options.cache;
  const bool cacheable = cache != nullptr && kind.cacheable();
  const auto publish = [&] { kind.publish(out, r.values); };
  if (cacheable) {
    if (const std::optional<std::string> stored = cache->find(n.name)) {
      try {
        CachedNode c;
        from_bytes(*stored, c);
        restore(c.bytes);
        out.status = c.status;
        out.warnings = c.warnings;
        out.runtime_s = c.runtime_s;
        if constexpr (std::is_same_v<Out, GroupOutcome>) out.members = c.members;
        out.restored = true;
      } catch (const InputError&) {  // damaged: computed instead
        out.result.reset();
      }
      if (out.restored) {
        guarded(out, publish);
        record_unprovided(n, out.status, r.values);
        return;
      }
    }
  }
  run_node(n, out, r, run, publish);
  if (cacheable && out.status.ok()) {
    CachedNode c;
    c.status = out.status;
    c.warnings = out.warnings;
    c.runtime_s = out.runtime_s;
    if constexpr (std::is_same_v<Out, GroupOutcome>) c.members = out.members;
    try {
      c.bytes = kind.save(out);
      cache->keep(n.name, to_bytes(c));
    } catch (const std::exception&) {  // not kept: computed again next time
    }
  }
}

void add_inputs(CampaignResults& r) {
  auto add_input = [&](const fs::path& p) {
    // Only regular files inside the campaign are read (app/core/input_boundary.h): never a
    // file a key leads outside to, a FIFO (an open would block) or a device.
    if (!regular_file_inside(r.campaign.root, p)) return;
    InputFile f;
    try {
      // Shown in the report and results.json, which are UTF-8 (a folder named in Latin-1).
      f.relative_path = utf8_replaced(fs::relative(p, r.campaign.root).generic_string());
      f.bytes = fs::file_size(p);
      f.sha256 = sha256_file(p);
    } catch (const std::exception&) {  // unreadable (permissions): not hashed, the run goes on
      return;
    }
    r.inputs.push_back(std::move(f));
  };
  add_input(r.campaign.root / "campaign.yaml");
  if (r.campaign.has_truth) add_input(r.campaign.truth_file);
  for (const auto& t : r.campaign.tests) {
    add_input(t.folder / "test.yaml");
    if (!t.data.file.empty()) add_input(t.data.file);
    if (const TestKind* kind = r.kinds->find(t.kind); kind != nullptr && t.usable()) {
      for (const auto& f : kind->input_files(t)) add_input(f);
    }
  }
}

}  // namespace

const GroupOutcome* CampaignResults::group(const std::string& name) const {
  for (const auto& g : groups) {
    if (g.name == name) return &g;
  }
  return nullptr;
}

int CampaignResults::internal_errors() const {
  int n = 0;
  for (const auto& t : tests) n += t.failure == Failure::kInternal;
  for (const auto& g : groups) n += g.failure == Failure::kInternal;
  return n;
}

std::vector<std::vector<std::string>> schedule(const CampaignSpec& campaign,
                                               const KindRegistry& kinds) {
  const std::vector<Node> nodes = build_graph(campaign, kinds);
  std::vector<std::vector<std::string>> levels;
  for (const auto& n : nodes) {
    if (levels.size() <= static_cast<std::size_t>(n.level)) levels.resize(n.level + 1);
    levels[n.level].push_back(n.name);
  }
  return levels;
}

CampaignResults run_campaign(CampaignSpec campaign, const PipelineOptions& options,
                             const KindRegistry& kinds) {
  const auto t0 = std::chrono::steady_clock::now();
  CampaignResults r;
  r.campaign = std::move(campaign);
  r.kinds = &kinds;
  r.options = options;
  for (auto& t : r.campaign.tests) check_signals(t, kinds);
  r.tests.resize(r.campaign.tests.size());
  for (std::size_t i = 0; i < r.tests.size(); ++i) {
    const TestSpec& t = r.campaign.tests[i];
    TestOutcome& out = r.tests[i];
    out.spec = &t;
    out.warnings = t.warnings;
    if (!t.usable()) {
      std::string why;
      for (const auto& e : t.errors) why += (why.empty() ? "" : "; ") + e;
      out.status.fail(why);
      out.failure = Failure::kInput;
      if (const TestKind* kind = kinds.find(t.kind)) {
        for (const auto& v : kind->provides(t)) r.values.fail(v, node_name(t), why);
      }
    }
  }

  std::vector<Node> nodes;
  try {
    nodes = build_graph(r.campaign, kinds);
  } catch (const std::logic_error& e) {
    for (auto& out : r.tests) {
      if (out.status.ok() || out.failure != Failure::kNone) continue;
      out.status.fail(std::string("internal error: ") + e.what());
      out.failure = Failure::kInternal;
    }
  }
  for (const auto& n : nodes) {
    if (!n.group) continue;
    r.groups.emplace_back();
    r.groups.back().name = n.group->name();
  }
  int depth = 0;
  for (const auto& n : nodes) depth = std::max(depth, n.level + 1);
  r.levels.resize(static_cast<std::size_t>(depth));
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = options.jobs > 0 ? options.jobs : hw;
  // Progress: one call per finished test or group, serialized. The tests that do not run
  // (unusable, or no graph) count as finished first.
  std::vector<bool> runs(r.tests.size(), false);
  for (const auto& n : nodes) {
    if (n.test != kNone) runs[n.test] = true;
  }
  const std::size_t total =
      nodes.size() + static_cast<std::size_t>(std::count(runs.begin(), runs.end(), false));
  std::mutex progress_mutex;
  std::size_t finished = 0;
  const auto report_finished = [&](const std::string& name, bool group, const Outcome& out) {
    if (!options.on_finished) return;
    std::lock_guard<std::mutex> lock(progress_mutex);
    NodeFinished f;
    f.name = name;
    f.group = group;
    f.ok = out.status.ok();
    f.failure = out.failure;
    f.message = out.status.ok() ? std::string() : out.status.message;
    f.runtime_s = out.runtime_s;
    f.elapsed_s = seconds_since(t0);
    f.done = ++finished;
    f.total = total;
    try {
      options.on_finished(f);
    } catch (...) {  // progress never stops the campaign
    }
  };
  for (std::size_t i = 0; i < r.tests.size(); ++i) {
    if (!runs[i]) report_finished(node_name(r.campaign.tests[i]), false, r.tests[i]);
  }
  for (int level = 0; level < depth; ++level) {
    std::vector<const Node*> now;
    for (const auto& n : nodes) {
      if (n.level == level) now.push_back(&n);
    }
    for (const Node* n : now) r.levels[static_cast<std::size_t>(level)].push_back(n->name);
    // The threads left over when a level has fewer nodes than threads go to the nodes' own
    // inner parallelism (the cut tests' estimator variants).
    const int inner = std::max(1, threads / std::max(1, static_cast<int>(now.size())));
    parallel_for(now.size(), options.jobs, [&](std::size_t k) {
      const Node& n = *now[k];
      const RunContext ctx{&r.campaign, inner};
      if (n.group) {
        GroupOutcome& out = *std::find_if(r.groups.begin(), r.groups.end(),
                                          [&](const auto& g) { return g.name == n.group->name(); });
        run_or_restore(
            n, *n.group, out, r, [&] { n.group->run(r.values, ctx, out); },
            [&](const std::string& bytes) { n.group->restore(bytes, out); });
        report_finished(n.name, n.group != nullptr, out);
      } else {
        TestOutcome& out = r.tests[n.test];
        run_or_restore(
            n, *n.kind, out, r, [&] { n.kind->run(r.campaign.tests[n.test], r.values, ctx, out); },
            [&](const std::string& bytes) {
              n.kind->restore(r.campaign.tests[n.test], bytes, out);
            });
        report_finished(n.name, n.group != nullptr, out);
      }
    });
  }
  add_inputs(r);
  r.runtime_s = seconds_since(t0);
  return r;
}

void check_signals(TestSpec& t, const KindRegistry& kinds) {
  const TestKind* kind = kinds.find(t.kind);
  if (!t.usable() || !kind) return;
  const std::string label = t.data_label();
  try {
    for (auto& e : kind->check_files(t)) t.errors.push_back(std::move(e));
    // A test without a data file has none to open: a tap test from a measured FRF (test.yaml
    // `frf:`, read by check_files; the loader requires data of every other test).
    if (t.data.relative_file.empty() && t.kind == "tap") return;
    const SignalTable table = SignalTable::open(t.data, label);
    for (auto& e :
         missing_channels(table, kind->required_channels(t), t.channels, "a " + t.kind + " test")) {
      t.errors.push_back(std::move(e));
    }
    // A calibration under a misspelt channel name is an error, not silently ignored.
    for (auto& e :
         unmatched_channel_keys(table, kind->required_channels(t), t.channels, t.yaml_label)) {
      t.errors.push_back(std::move(e));
    }
    const double duration = static_cast<double>(table.samples()) / t.sample_rate_hz;
    for (auto& e : kind->check_record(t, duration)) t.errors.push_back(std::move(e));
  } catch (const InputError& e) {
    t.errors.push_back(e.what());
  } catch (const std::exception& e) {
    // A reader's failure that is no input message (std::bad_alloc on a damaged file): this
    // test's problem, as it would be in its step, never the end of the campaign.
    t.errors.push_back(label + ": internal error while checking the test's files: " + e.what());
  }
}

}  // namespace chatterlab::app
