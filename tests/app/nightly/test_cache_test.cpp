// The per-test cache of a nightly site (app/nightly/test_cache.h): bytes round-trip through
// zlib, damaged ones are refused, and a node is restored only under its unchanged key.
#include "app/nightly/test_cache.h"

#include <gtest/gtest.h>

#include "tests/support/expect_input_error.h"

namespace chatterlab::app {
namespace {

TEST(TestCache, BytesRoundTripThroughZlib) {
  std::string bytes(100000, '\0');
  for (std::size_t i = 0; i < bytes.size(); i += 7) bytes[i] = static_cast<char>(i % 251);
  const std::string c = compress_bytes(bytes);
  EXPECT_LT(c.size(), bytes.size() / 2);  // mostly zeros
  EXPECT_EQ(decompress_bytes(c), bytes);
  EXPECT_EQ(decompress_bytes(compress_bytes("")), "");
}

TEST(TestCache, DamagedBytesAreRefused) {
  const std::string c = compress_bytes(std::string(1000, 'x'));
  chatterlab::testing::expect_input_error([&] { decompress_bytes("abc"); },
                                          "a cached result is damaged (too short)");
  std::string bad = c;
  bad[bad.size() - 3] ^= 0x5a;
  chatterlab::testing::expect_input_error([&] { decompress_bytes(bad); },
                                          "a cached result is damaged (zlib)");
  std::string huge = c;
  huge[7] = 0x7f;  // a length of about 2^62
  chatterlab::testing::expect_input_error([&] { decompress_bytes(huge); },
                                          "a cached result is damaged (impossible length)");
}

TEST(TestCache, RestoresOnlyUnderTheSameKey) {
  SiteResultCache cache({{"tap/x", "k1"}, {"tap/y", "k2-new"}, {"cuts/a", "k3"}},
                        {{"tap/x", {"k1", compress_bytes("X")}},
                         {"tap/y", {"k2-old", compress_bytes("Y")}},
                         {"gone", {"k9", compress_bytes("G")}}});
  EXPECT_EQ(cache.find("tap/x"), std::optional<std::string>("X"));
  EXPECT_EQ(cache.find("tap/y"), std::nullopt);   // its key changed
  EXPECT_EQ(cache.find("cuts/a"), std::nullopt);  // nothing stored
  EXPECT_EQ(cache.find("gone"), std::nullopt);    // not in this run
  cache.keep("tap/y", "Y2");
  EXPECT_EQ(cache.restored(), std::vector<std::string>{"tap/x"});
  EXPECT_EQ(decompress_bytes(*cache.compressed_to_store("tap/x")), "X");
  EXPECT_EQ(decompress_bytes(*cache.compressed_to_store("tap/y")), "Y2");
  EXPECT_EQ(cache.compressed_to_store("cuts/a"), std::nullopt);
}

}  // namespace
}  // namespace chatterlab::app
