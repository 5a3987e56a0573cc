// A measured value in a test's XML report (--gtest_output=xml), where docs pick it up.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace chatterlab::testing {

inline void record(const std::string& key, double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", value);
  ::testing::Test::RecordProperty(key, buf);
}

// The same, also printed to the test's output for a reader of the run.
inline void record_and_print(const std::string& key, double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", value);
  ::testing::Test::RecordProperty(key, buf);
  std::printf("  %s = %s\n", key.c_str(), buf);
}

}  // namespace chatterlab::testing
