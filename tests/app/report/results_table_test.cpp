// results.csv from results.json (app/report/results_table.h).
#include "app/report/results_table.h"

#include <gtest/gtest.h>

#include <sstream>

namespace chatterlab::app {
namespace {

using nlohmann::json;

TEST(ResultsTable, FlattensTestsAndGroupsIntoRows) {
  json big = json::array();
  for (std::size_t i = 0; i <= kResultsTableMaxArray; ++i) big.push_back(1.0);
  const json r = {{"campaign", "c"},
                  {"settings", {{"not", "a row"}}},
                  {"tests",
                   {{"tap/x",
                     {{"status", "ok"},
                      {"modes", json::array({{{"fn_hz", 898.4}, {"zeta", 0.0123456789012}}})},
                      {"note", "a, \"quoted\" text"},
                      {"flag", true},
                      {"missing", nullptr},
                      {"series", big}}}}},
                  {"groups", {{"dyno-slot", {{"Ktc_N_m2", 6.61e8}}}}}};
  const std::string csv = results_table_csv(r);
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("# chatterlab results of campaign c:", 0), 0u) << line;
  std::vector<std::string> rows;
  while (std::getline(in, line)) rows.push_back(line);
  const std::vector<std::string> expected = {
      "test,key,value",
      "tap/x,flag,true",
      "tap/x,missing,",
      "tap/x,modes.0.fn_hz,898.4",
      "tap/x,modes.0.zeta,0.0123456789",
      "tap/x,note,\"a, \"\"quoted\"\" text\"",
      "tap/x,status,ok",
      "group:dyno-slot,Ktc_N_m2,661000000",
  };
  EXPECT_EQ(rows, expected);  // settings are not rows; the 65-value series is left out
}

TEST(ResultsTable, EmptyResultsGiveTheHeaderOnly) {
  const std::string csv = results_table_csv(json::object());
  EXPECT_NE(csv.find("\ntest,key,value\n"), std::string::npos);
  EXPECT_EQ(csv.substr(csv.find("test,key,value\n") + 15), "");
}

}  // namespace
}  // namespace chatterlab::app
