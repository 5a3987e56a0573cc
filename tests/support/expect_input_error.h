// Asserts that a call throws InputError with exactly the given message (CONVENTIONS.md: every
// message a user can meet is asserted somewhere).
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "analysis/common/summary.h"

namespace chatterlab::testing {

inline void expect_input_error(const std::function<void()>& f, const std::string& message) {
  try {
    f();
    ADD_FAILURE() << "no error; expected: " << message;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

}  // namespace chatterlab::testing
