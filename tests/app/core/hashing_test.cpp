#include "app/core/hashing.h"

#include <gtest/gtest.h>

#include "tests/support/temp_campaign.h"

namespace chatterlab::app {
namespace {

TEST(Hashing, Sha256OfKnownStrings) {
  chatterlab::testing::TempDir d;
  // FIPS 180-2 test vector "abc" and the empty message.
  EXPECT_EQ(sha256_file(d.write("abc.txt", "abc")),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_file(d.write("empty.txt", "")),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

}  // namespace
}  // namespace chatterlab::app
