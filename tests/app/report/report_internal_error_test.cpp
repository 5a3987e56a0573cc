// An internal error (an exception that is not bad input) in one test: the rest of the
// campaign runs, results.json and the report say `error` apart from skipped tests, and
// `report` exits with status 3.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "app/report/report.h"
#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

using chatterlab::testing::kCampaignYaml;
using chatterlab::testing::TempDir;

struct Empty : KindSpec {};
struct Done : KindResult {};

// A kind whose step fails on purpose by test id: `crash` throws a std::runtime_error, `refuse`
// an InputError, anything else succeeds.
class ProbeKind : public TestKind {
 public:
  std::string name() const override { return "probe"; }
  std::vector<std::string> keys() const override { return {}; }
  std::shared_ptr<const KindSpec> parse(const YAML::Node&, YamlReader&) const override {
    return std::make_shared<Empty>();
  }
  std::vector<std::string> required_channels(const TestSpec&) const override { return {"a"}; }
  void run(const TestSpec& t, const CampaignValues&, const RunContext&,
           TestOutcome& out) const override {
    if (t.id == "crash") throw std::runtime_error("index out of range on purpose");
    if (t.id == "refuse") throw InputError(t.yaml_label + ": key 'mode' refused on purpose");
    out.result = std::make_unique<Done>();
    out.status.succeed();
  }
};

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ReportInternalError, IsReportedApartAndExitsWithThree) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  for (const char* id : {"crash", "refuse", "fine"}) {
    d.write(std::string(id) + "/a.csv", "a\n1\n");
    d.write(std::string(id) + "/test.yaml",
            "kind: probe\nsample_rate_hz: 10\ndata: {file: a.csv}\n");
  }
  KindRegistry kinds;
  register_builtin_kinds(kinds);
  kinds.add(std::make_unique<ProbeKind>());
  ReportOptions o;
  o.pdf = false;
  std::ostringstream log;
  EXPECT_EQ(run_report(d.path(), d.path() / "out", o, log, kinds), 3) << log.str();
  EXPECT_NE(log.str().find("INTERNAL ERROR crash: internal error: index out of range on purpose"),
            std::string::npos)
      << log.str();

  std::ifstream in(d.path() / "out/results.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["internal_errors"], 1);
  EXPECT_EQ(j["tests"]["crash"]["status"], "error");
  EXPECT_EQ(j["tests"]["crash"]["skip_reason"], "internal error: index out of range on purpose");
  EXPECT_EQ(j["tests"]["refuse"]["status"], "skipped");
  EXPECT_EQ(j["tests"]["refuse"]["skip_reason"], "refuse/test.yaml: key 'mode' refused on purpose");
  EXPECT_EQ(j["tests"]["fine"]["status"], "ok");

  const std::string html = read_text(d.path() / "out/index.html");
  EXPECT_NE(html.find("<h3>Internal errors</h3>"), std::string::npos);
  EXPECT_NE(html.find("index out of range on purpose"), std::string::npos);
}

TEST(ReportInternalError, CleanCampaignExitsWithZero) {
  TempDir d;
  d.write("campaign.yaml", kCampaignYaml);
  d.write("fine/a.csv", "a\n1\n");
  d.write("fine/test.yaml", "kind: probe\nsample_rate_hz: 10\ndata: {file: a.csv}\n");
  KindRegistry kinds;
  register_builtin_kinds(kinds);
  kinds.add(std::make_unique<ProbeKind>());
  ReportOptions o;
  o.pdf = false;
  std::ostringstream log;
  EXPECT_EQ(run_report(d.path(), d.path() / "out", o, log, kinds), 0) << log.str();
  const std::string html = read_text(d.path() / "out/index.html");
  EXPECT_EQ(html.find("<h3>Internal errors</h3>"), std::string::npos);
}

}  // namespace
}  // namespace chatterlab::app
