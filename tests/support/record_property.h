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

}  // namespace chatterlab::testing
