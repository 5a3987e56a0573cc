// A test fixture whose scratch folder is also TMPDIR for the test's duration, so that temporary
// folders made by the code under test land in it (and a test can see they are removed), with
// an out/ folder inside for the outputs. TMPDIR is restored afterwards.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "render/temp_dir.h"

namespace chatterlab::testing {

class ScratchTmpdirTest : public ::testing::Test {
 protected:
  explicit ScratchTmpdirTest(const char* prefix) : scratch_(prefix) {}
  void SetUp() override {
    old_tmpdir_ = std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "";
    ::setenv("TMPDIR", scratch_.path().c_str(), 1);
    out_ = scratch_.path() / "out";
    std::filesystem::create_directory(out_);
  }
  void TearDown() override {
    if (old_tmpdir_.empty()) {
      ::unsetenv("TMPDIR");
    } else {
      ::setenv("TMPDIR", old_tmpdir_.c_str(), 1);
    }
  }

  render::TempDir scratch_;
  std::filesystem::path out_;

 private:
  std::string old_tmpdir_;
};

}  // namespace chatterlab::testing
