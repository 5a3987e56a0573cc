// The pipeline over kinds registered in a test registry: run order from needs and provides,
// skips with the failed provider named, input and internal errors kept apart, values read in
// provider order, and parallel_for carrying exceptions back.
#include "app/pipeline/pipeline.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "app/core/parallel.h"
#include "app/core/yaml_reader.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using testing::TempDir;

struct SourceSpec : KindSpec {
  std::string fail;  // "", "input" or "internal"
  double value = 0;
  int delay_ms = 0;
};

struct NumberResult : KindResult {
  double value = 0;
};

// Provides "v" (its `value` key); fails on request.
class SourceKind : public TestKind {
 public:
  std::string name() const override { return "source"; }
  std::vector<std::string> keys() const override { return {"fail", "value", "delay_ms"}; }
  std::shared_ptr<const KindSpec> parse(const YAML::Node& root, YamlReader& r) const override {
    auto s = std::make_shared<SourceSpec>();
    s->fail = r.optional_string(root, "fail").value_or("");
    s->value = r.optional_double(root, "value").value_or(0.0);
    s->delay_ms = static_cast<int>(r.optional_double(root, "delay_ms").value_or(0.0));
    return s;
  }
  std::vector<std::string> required_channels(const TestSpec&) const override { return {"a"}; }
  std::vector<std::string> provides(const TestSpec&) const override { return {"v"}; }
  void run(const TestSpec& t, const CampaignValues&, const RunContext&,
           TestOutcome& out) const override {
    const auto& s = t.kind_spec<SourceSpec>();
    std::this_thread::sleep_for(std::chrono::milliseconds(s.delay_ms));
    if (s.fail == "input") throw InputError(t.yaml_label + ": value: bad on purpose");
    if (s.fail == "internal") throw std::runtime_error("broken invariant on purpose");
    auto r = std::make_unique<NumberResult>();
    r->value = s.value;
    out.result = std::move(r);
    out.status.succeed();
  }
  void publish(const TestOutcome& out, CampaignValues& values) const override {
    values.put("v", out.spec->id, out.result_as<NumberResult>()->value);
  }
};

// Needs one value (required or not): its result is the first provider's value (NaN when none).
class SinkKind : public TestKind {
 public:
  SinkKind(std::string name, bool required, std::string reads = "v")
      : name_(std::move(name)), required_(required), reads_(std::move(reads)) {}
  std::string name() const override { return name_; }
  std::vector<std::string> keys() const override { return {}; }
  std::shared_ptr<const KindSpec> parse(const YAML::Node&, YamlReader&) const override {
    return std::make_shared<KindSpec>();
  }
  std::vector<std::string> required_channels(const TestSpec&) const override { return {"a"}; }
  std::vector<Need> needs(const TestSpec&) const override { return {{reads_, required_}}; }
  void run(const TestSpec&, const CampaignValues& in, const RunContext&,
           TestOutcome& out) const override {
    auto r = std::make_unique<NumberResult>();
    const double* v = in.first<double>(reads_);
    r->value = v ? *v : std::nan("");
    out.result = std::move(r);
    out.status.succeed();
  }

 private:
  std::string name_;
  bool required_;
  std::string reads_;
};

// The sum of every "v", provided as "w".
class SumGroup : public GroupProduct {
 public:
  std::string name() const override { return "sum"; }
  bool applies(const CampaignSpec& c) const override {
    for (const auto& t : c.tests) {
      if (t.kind == "source") return true;
    }
    return false;
  }
  std::vector<Need> needs(const CampaignSpec&) const override { return {{"v", false}}; }
  std::vector<std::string> provides(const CampaignSpec&) const override { return {"w"}; }
  void run(const CampaignValues& in, const RunContext&, GroupOutcome& out) const override {
    auto r = std::make_unique<NumberResult>();
    for (const auto& [id, v] : in.all<double>("v")) {
      out.members.push_back(id);
      r->value += *v;
    }
    out.result = std::move(r);
    out.status.succeed();
  }
  void publish(const GroupOutcome& out, CampaignValues& values) const override {
    values.put("w", "group:sum", out.result_as<NumberResult>()->value);
  }
  nlohmann::json results(const GroupOutcome&) const override { return {}; }
};

KindRegistry test_registry() {
  KindRegistry r;
  r.add(std::make_unique<SourceKind>());
  r.add(std::make_unique<SinkKind>("sink", true));
  r.add(std::make_unique<SinkKind>("optional-sink", false));
  r.add(std::make_unique<SumGroup>());
  r.add(std::make_unique<SinkKind>("late", true, "w"));  // the group's sum
  return r;
}

void add_test(TempDir& d, const std::string& id, const std::string& kind,
              const std::string& extra = "") {
  d.write(id + "/a.csv", "a\n1\n2\n");
  d.write(id + "/test.yaml",
          "kind: " + kind + "\nsample_rate_hz: 10\ndata: {file: a.csv}\n" + extra);
}

const TestOutcome& outcome(const CampaignResults& r, const std::string& id) {
  for (const auto& t : r.tests) {
    if (t.spec->id == id) return t;
  }
  throw std::logic_error("no test " + id);
}

double value_of(const TestOutcome& t) {
  const auto* r = t.status.ok() ? t.result_as<NumberResult>() : nullptr;
  if (!r) throw std::logic_error(t.spec->id + " did not run: " + t.status.message);
  return r->value;
}

TEST(Pipeline, OrdersByNeedsAndProvides) {
  TempDir d;
  d.write("campaign.yaml", testing::kCampaignYaml);
  add_test(d, "s1", "source", "value: 1\n");
  add_test(d, "s2", "source", "value: 2\n");
  add_test(d, "k", "sink");
  add_test(d, "late", "late");
  const KindRegistry kinds = test_registry();
  const auto levels = schedule(load_campaign(d.path(), kinds), kinds);
  // Sources first; the sink and the group that read "v" next; "late" reads the group's "w".
  ASSERT_EQ(levels.size(), 3u);
  EXPECT_EQ(levels[0], (std::vector<std::string>{"s1", "s2"}));
  EXPECT_EQ(levels[1], (std::vector<std::string>{"k", "group:sum"}));
  EXPECT_EQ(levels[2], (std::vector<std::string>{"late"}));
}

// Providers finish in the opposite order of their ids; readers still see them by id, so the
// results do not depend on thread timing.
TEST(Pipeline, ValuesInProviderOrder) {
  TempDir d;
  d.write("campaign.yaml", testing::kCampaignYaml);
  add_test(d, "a", "source", "value: 10\ndelay_ms: 50\n");
  add_test(d, "b", "source", "value: 20\n");
  add_test(d, "k", "sink");
  add_test(d, "late", "late");
  const KindRegistry kinds = test_registry();
  PipelineOptions o;
  o.jobs = 2;
  const CampaignResults r = run_campaign(load_campaign(d.path(), kinds), o, kinds);
  EXPECT_EQ(value_of(outcome(r, "k")), 10.0);
  ASSERT_NE(r.group("sum"), nullptr);
  EXPECT_EQ(r.group("sum")->members, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(value_of(outcome(r, "late")), 30.0);
}

TEST(Pipeline, FailedProviderSkipsRequiredConsumerWithTheReason) {
  TempDir d;
  d.write("campaign.yaml", testing::kCampaignYaml);
  add_test(d, "src", "source", "fail: input\n");
  add_test(d, "k", "sink");
  add_test(d, "opt", "optional-sink");
  const KindRegistry kinds = test_registry();
  const CampaignResults r = run_campaign(load_campaign(d.path(), kinds), {}, kinds);
  const TestOutcome& src = outcome(r, "src");
  EXPECT_FALSE(src.status.ok());
  EXPECT_EQ(src.failure, Failure::kInput);
  EXPECT_EQ(src.status.message, "src/test.yaml: value: bad on purpose");
  const TestOutcome& k = outcome(r, "k");
  EXPECT_FALSE(k.status.ok());
  EXPECT_EQ(k.failure, Failure::kInput);
  EXPECT_EQ(k.status.message,
            "needs 'v' from src, which was skipped: src/test.yaml: value: bad on purpose");
  // An optional need: the consumer runs without the value.
  const TestOutcome& opt = outcome(r, "opt");
  ASSERT_TRUE(opt.status.ok()) << opt.status.message;
  EXPECT_TRUE(std::isnan(value_of(opt)));
  EXPECT_EQ(r.internal_errors(), 0);
}

// A source that succeeds but publishes nothing: its consumers say so.
class SilentSource : public SourceKind {
 public:
  std::string name() const override { return "silent"; }
  void publish(const TestOutcome&, CampaignValues&) const override {}
};

TEST(Pipeline, ProviderThatGaveNoValueIsNamed) {
  TempDir d;
  d.write("campaign.yaml", testing::kCampaignYaml);
  add_test(d, "quiet", "silent");
  add_test(d, "k", "sink");
  KindRegistry kinds = test_registry();
  kinds.add(std::make_unique<SilentSource>());
  const CampaignResults r = run_campaign(load_campaign(d.path(), kinds), {}, kinds);
  EXPECT_EQ(outcome(r, "k").status.message,
            "needs 'v' from quiet, which was skipped: it gave no value");
}

TEST(Pipeline, NoProviderAtAllIsNamed) {
  TempDir d;
  d.write("campaign.yaml", testing::kCampaignYaml);
  add_test(d, "k", "sink");
  const KindRegistry kinds = test_registry();
  const CampaignResults r = run_campaign(load_campaign(d.path(), kinds), {}, kinds);
  EXPECT_EQ(outcome(r, "k").status.message, "needs 'v', which no test of the campaign provides");
}

TEST(Pipeline, InternalErrorsAreKeptApartFromInputErrors) {
  TempDir d;
  d.write("campaign.yaml", testing::kCampaignYaml);
  add_test(d, "bad", "source", "fail: internal\n");
  add_test(d, "good", "source", "value: 3\n");
  add_test(d, "k", "sink");
  const KindRegistry kinds = test_registry();
  const CampaignResults r = run_campaign(load_campaign(d.path(), kinds), {}, kinds);
  const TestOutcome& bad = outcome(r, "bad");
  EXPECT_EQ(bad.failure, Failure::kInternal);
  EXPECT_EQ(bad.status.message, "internal error: broken invariant on purpose");
  EXPECT_EQ(r.internal_errors(), 1);
  // The rest of the campaign ran, the consumer on the provider that succeeded.
  ASSERT_TRUE(outcome(r, "k").status.ok());
  EXPECT_EQ(value_of(outcome(r, "k")), 3.0);
}

TEST(Pipeline, UnknownKindNamesTheRegisteredOnes) {
  TempDir d;
  d.write("campaign.yaml", testing::kCampaignYaml);
  add_test(d, "x", "laser-scan");
  const KindRegistry kinds = test_registry();
  const CampaignSpec c = load_campaign(d.path(), kinds);
  ASSERT_EQ(c.tests.size(), 1u);
  ASSERT_FALSE(c.tests[0].usable());
  EXPECT_NE(c.tests[0].errors[0].find(
                "'laser-scan' is not a known test kind (source, sink, optional-sink, late)"),
            std::string::npos)
      << c.tests[0].errors[0];
}

TEST(CampaignValues, ReadingAnotherTypeIsABrokenInvariant) {
  CampaignValues v;
  v.put("v", "a", 1.0);
  EXPECT_EQ(*v.first<double>("v"), 1.0);
  EXPECT_THROW(v.first<int>("v"), InvariantError);
  EXPECT_THROW(v.all<float>("v"), InvariantError);
}

TEST(ParallelFor, CarriesTheFirstExceptionBack) {
  // Two threads: the exception comes back (how many items the other thread started before it
  // saw the stop depends on scheduling, so it is not asserted).
  EXPECT_THROW(parallel_for(100, 2,
                            [&](std::size_t i) {
                              if (i == 3) throw std::runtime_error("item 3");
                            }),
               std::runtime_error);
  // One thread: the remaining items do not start.
  std::atomic<int> ran{0};
  EXPECT_THROW(parallel_for(100, 1,
                            [&](std::size_t i) {
                              ++ran;
                              if (i == 3) throw std::runtime_error("item 3");
                            }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 4);
  try {
    parallel_for(4, 1, [](std::size_t i) {
      if (i >= 1) throw std::invalid_argument("item " + std::to_string(i));
    });
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "item 1");  // one thread: the first item that threw
  }
}

TEST(Registry, RejectsTwiceRegisteredKinds) {
  KindRegistry r;
  r.add(std::make_unique<SourceKind>());
  EXPECT_THROW(r.add(std::make_unique<SourceKind>()), std::logic_error);
  EXPECT_EQ(r.names(), "source");
}

}  // namespace
}  // namespace chatterlab::app
