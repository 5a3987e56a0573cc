// results.csv: every value of results.json's tests and groups as one long table (test, key,
// value), for a spreadsheet or a lab's own scripts that do not read JSON
// (docs/format/results-json.md#resultscsv).
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

namespace chatterlab::app {

// Arrays longer than this are not flattened into rows (a Poincare map's points, a series);
// results.json keeps them.
inline constexpr std::size_t kResultsTableMaxArray = 64;

// The CSV text: a header comment naming the campaign and the rule, then "test,key,value" and one
// row per scalar below results["tests"][id] (test = id) and results["groups"][name] (test =
// "group:" + name), keys joined by '.', array elements by their 0-based index, numbers with 10
// significant digits, booleans as true/false, null as an empty value, strings quoted when they
// hold a comma, quote or line break (RFC 4180). Rows follow results.json's key order.
std::string results_table_csv(const nlohmann::json& results);

}  // namespace chatterlab::app
