// Progress of `report`: the pipeline calls PipelineOptions::on_finished once per test or group
// as it finishes, never two calls at once, counting up; run_report turns each call into a
// flushed line ("[3/10] cuts/a ok 4.1 s, 12 s elapsed, ~28 s left") and sends errors to
// ReportOptions::errors.
#include "app/cli/progress.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <sstream>
#include <streambuf>
#include <thread>

#include "app/cli/exit_codes.h"
#include "app/report/report.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::kCampaignYaml;
using chatterlab::testing::TempDir;

TEST(Progress, Durations) {
  EXPECT_EQ(format_duration(0.04), "0.0 s");
  EXPECT_EQ(format_duration(4.12), "4.1 s");
  EXPECT_EQ(format_duration(12.4), "12 s");
  EXPECT_EQ(format_duration(119.4), "119 s");
  EXPECT_EQ(format_duration(185), "3 min 05 s");
  EXPECT_EQ(format_duration(-1), "0.0 s");
}

TEST(Progress, LineWithTheEstimateOnLongRuns) {
  NodeFinished f;
  f.name = "cuts/a";
  f.ok = true;
  f.runtime_s = 4.1;
  f.elapsed_s = 12;
  f.done = 3;
  f.total = 10;
  EXPECT_EQ(progress_line(f, 10), "[3/10] cuts/a ok 4.1 s, 12 s elapsed, ~28 s left");
  EXPECT_EQ(progress_line(f, 20), "[3/10] cuts/a ok 4.1 s, 12 s elapsed");  // not long yet
  f.done = 10;
  EXPECT_EQ(progress_line(f, 0), "[10/10] cuts/a ok 4.1 s, 12 s elapsed");  // nothing left
  NodeFinished g;
  g.name = "group:dyno-slot";
  g.group = true;
  g.failure = Failure::kInput;
  g.done = 1;
  g.total = 2;
  EXPECT_EQ(progress_line(g, 100), "[1/2] group dyno-slot skipped 0.0 s, 0.0 s elapsed");
  g.failure = Failure::kInternal;
  EXPECT_EQ(progress_line(g, 100), "[1/2] group dyno-slot ERROR 0.0 s, 0.0 s elapsed");
}

struct Empty : KindSpec {};
struct Done : KindResult {};

// Sleeps 20 ms; a test named crash* throws a std::runtime_error.
class SlowKind : public TestKind {
 public:
  std::string name() const override { return "slow"; }
  std::vector<std::string> keys() const override { return {}; }
  std::shared_ptr<const KindSpec> parse(const YAML::Node&, YamlReader&) const override {
    return std::make_shared<Empty>();
  }
  std::vector<std::string> required_channels(const TestSpec&) const override { return {"a"}; }
  void run(const TestSpec& t, const CampaignValues&, const RunContext&,
           TestOutcome& out) const override {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (t.id.rfind("crash", 0) == 0) throw std::runtime_error("on purpose");
    out.result = std::make_unique<Done>();
    out.status.succeed();
  }
};

KindRegistry slow_kinds() {
  KindRegistry kinds;
  register_builtin_kinds(kinds);
  kinds.add(std::make_unique<SlowKind>());
  return kinds;
}

void write_slow_campaign(const TempDir& d, int tests, const std::string& prefix = "t") {
  d.write("campaign.yaml", kCampaignYaml);
  for (int i = 0; i < tests; ++i) {
    const std::string id = prefix + std::to_string(i);
    d.write(id + "/a.csv", "a\n1\n");
    d.write(id + "/test.yaml", "kind: slow\nsample_rate_hz: 10\ndata: {file: a.csv}\n");
  }
}

TEST(Progress, PipelineCallsOncePerTestSerializedAndCountingUp) {
  TempDir d;
  write_slow_campaign(d, 8);
  // One unusable test (its record is missing): counted, first, as skipped.
  d.write("bad/test.yaml", "kind: slow\nsample_rate_hz: 10\ndata: {file: none.csv}\n");
  const KindRegistry kinds = slow_kinds();
  PipelineOptions o;
  o.jobs = 4;
  std::atomic<int> inside{0};
  std::atomic<bool> overlapped{false};
  std::vector<NodeFinished> calls;
  o.on_finished = [&](const NodeFinished& f) {
    if (inside.fetch_add(1) != 0) overlapped = true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    calls.push_back(f);
    inside.fetch_sub(1);
  };
  const auto r = run_campaign(load_campaign(d.path(), kinds), o, kinds);
  EXPECT_FALSE(overlapped);
  ASSERT_EQ(calls.size(), 9u);
  EXPECT_EQ(calls[0].name, "bad");
  EXPECT_FALSE(calls[0].ok);
  EXPECT_EQ(calls[0].failure, Failure::kInput);
  for (std::size_t k = 0; k < calls.size(); ++k) {
    EXPECT_EQ(calls[k].done, k + 1);
    EXPECT_EQ(calls[k].total, 9u);
    if (k > 0) {
      EXPECT_TRUE(calls[k].ok) << calls[k].name;
      EXPECT_GE(calls[k].runtime_s, 0.015);
      EXPECT_GE(calls[k].elapsed_s, calls[k - 1].elapsed_s);
    }
  }
  // As they finish, not at the end: with 4 threads the first of 8 tests of 20 ms is reported
  // well before the whole run is over.
  EXPECT_LT(calls[1].elapsed_s, r.runtime_s - 0.015);
}

// Records the text and where each flush happened.
class FlushLog : public std::streambuf {
 public:
  std::string text;
  std::vector<std::size_t> flushed_at;

 protected:
  int_type overflow(int_type c) override {
    if (c != traits_type::eof()) text.push_back(static_cast<char>(c));
    return c;
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    text.append(s, static_cast<std::size_t>(n));
    return n;
  }
  int sync() override {
    flushed_at.push_back(text.size());
    return 0;
  }
};

TEST(Progress, ReportFlushesEachLineAndSendsErrorsApart) {
  TempDir d;
  write_slow_campaign(d, 3);
  write_slow_campaign(d, 1, "crash");
  const KindRegistry kinds = slow_kinds();
  FlushLog buf;
  std::ostream log(&buf);
  std::ostringstream errors;
  ReportOptions o;
  o.pdf = false;
  o.jobs = 1;
  o.progress = true;
  o.estimate_after_s = 0;
  o.errors = &errors;
  int written_before = -1;
  o.before_writing = [&] {
    written_before = std::filesystem::exists(d.path() / "out/results.json") ? 1 : 0;
  };
  EXPECT_EQ(run_report(d.path(), d.path() / "out", o, log, kinds), kExitInternalError);
  EXPECT_EQ(written_before, 0);
  const std::string& text = buf.text;
  int lines = 0;
  for (std::size_t at = text.find("\n["); at != std::string::npos; at = text.find("\n[", at + 1)) {
    ++lines;
    const std::size_t end = text.find('\n', at + 1) + 1;
    EXPECT_NE(std::find(buf.flushed_at.begin(), buf.flushed_at.end(), end), buf.flushed_at.end())
        << "not flushed: " << text.substr(at + 1, end - at - 1);
    const std::string line = text.substr(at + 1, end - at - 2);
    if (line.rfind("[4/4]", 0) != 0) {
      EXPECT_NE(line.find(" left"), std::string::npos) << line;  // estimate_after_s = 0
    }
  }
  EXPECT_EQ(lines, 4) << text;
  EXPECT_NE(text.find("] crash0 ERROR "), std::string::npos) << text;
  // Errors apart: the internal error on the error stream only.
  EXPECT_EQ(text.find("INTERNAL ERROR"), std::string::npos) << text;
  EXPECT_NE(
      errors.str().find("chatterlab report: INTERNAL ERROR crash0: internal error: on purpose"),
      std::string::npos)
      << errors.str();

  // Without progress, no progress line; a campaign of crashes alone is still status 3, not 4.
  TempDir c;
  write_slow_campaign(c, 1, "crash");
  std::ostringstream quiet_log, quiet_errors;
  ReportOptions q;
  q.pdf = false;
  q.errors = &quiet_errors;
  EXPECT_EQ(run_report(c.path(), c.path() / "out", q, quiet_log, kinds), kExitInternalError);
  EXPECT_EQ(quiet_log.str().find("[1/"), std::string::npos) << quiet_log.str();
  EXPECT_NE(quiet_errors.str().find("no test was analysed"), std::string::npos);
}

}  // namespace
}  // namespace chatterlab::app
