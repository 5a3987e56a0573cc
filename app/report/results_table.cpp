#include "app/report/results_table.h"

#include <cstdio>

namespace chatterlab::app {
namespace {

using nlohmann::json;

std::string csv_cell(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

std::string scalar_text(const json& v) {
  if (v.is_null()) return {};
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer()) return v.dump();
  if (v.is_number_float()) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.10g", v.get<double>());
    return buf;
  }
  return v.is_string() ? v.get<std::string>() : v.dump();
}

void rows(const std::string& test, const std::string& key, const json& v, std::string& out) {
  if (v.is_object()) {
    for (const auto& [k, e] : v.items()) rows(test, key.empty() ? k : key + "." + k, e, out);
    return;
  }
  if (v.is_array()) {
    if (v.size() > kResultsTableMaxArray) return;
    for (std::size_t i = 0; i < v.size(); ++i) {
      rows(test, key + "." + std::to_string(i), v[i], out);
    }
    return;
  }
  out += csv_cell(test) + "," + csv_cell(key) + "," + csv_cell(scalar_text(v)) + "\n";
}

}  // namespace

std::string results_table_csv(const json& results) {
  std::string out = "# chatterlab results of campaign " +
                    results.value("campaign", std::string("?")) +
                    ": every value of results.json's tests and groups, one per row (units in "
                    "the key names; arrays of more than " +
                    std::to_string(kResultsTableMaxArray) + " values only in results.json)\n";
  out += "test,key,value\n";
  if (const auto t = results.find("tests"); t != results.end() && t->is_object()) {
    for (const auto& [id, test] : t->items()) rows(id, "", test, out);
  }
  if (const auto g = results.find("groups"); g != results.end() && g->is_object()) {
    for (const auto& [name, group] : g->items()) rows("group:" + name, "", group, out);
  }
  return out;
}

}  // namespace chatterlab::app
