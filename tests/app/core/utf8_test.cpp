// UTF-8 well-formedness (RFC 3629) of names from the file system and data files.
#include "app/core/utf8.h"

#include <gtest/gtest.h>

namespace chatterlab::app {
namespace {

TEST(Utf8, ValidTextIsKept) {
  for (const char* s : {"", "tap/x", "Fr\xC3\xA4sen", "\xE2\x82\xAC", "\xF0\x9F\x94\xA7",
                        "\xED\x9F\xBF", "\xF4\x8F\xBF\xBF"}) {
    EXPECT_TRUE(valid_utf8(s)) << s;
    EXPECT_EQ(utf8_replaced(s), s);
  }
}

TEST(Utf8, EachBadByteBecomesOneReplacementCharacter) {
  const std::string r = "\xEF\xBF\xBD";
  const struct {
    std::string in, out;
  } cases[] = {
      {"y\xFF", "y" + r},                   // never in UTF-8
      {"Fr\xE4sen", "Fr" + r + "sen"},      // Latin-1 a-umlaut
      {"\xC0\xAF", r + r},                  // overlong '/'
      {"\xE0\x80\xAF", r + r + r},          // overlong, three bytes
      {"\xED\xA0\x80", r + r + r},          // a surrogate (U+D800)
      {"\xF4\x90\x80\x80", r + r + r + r},  // above U+10FFFF
      {"\xE2\x82", r + r},                  // cut short at the end
      {"\xE2(\xA1", r + "(" + r},           // a continuation byte missing
  };
  for (const auto& c : cases) {
    EXPECT_FALSE(valid_utf8(c.in)) << c.in;
    EXPECT_EQ(utf8_replaced(c.in), c.out) << c.in;
    EXPECT_TRUE(valid_utf8(utf8_replaced(c.in)));
  }
}

}  // namespace
}  // namespace chatterlab::app
