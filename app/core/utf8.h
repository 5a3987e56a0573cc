// UTF-8 checks for names that come from the file system or from data files (folder names, CSV
// headers): results.json, results.csv and the report are UTF-8, and a byte that is not (a
// folder named in Latin-1 on an old share) must neither end the run nor reach them raw.
#pragma once

#include <string>
#include <string_view>

namespace chatterlab::app {

// Whether `text` is well-formed UTF-8 (RFC 3629: no overlong forms, no surrogates, at most
// U+10FFFF).
bool valid_utf8(std::string_view text);

// `text` with every byte that is not part of a well-formed UTF-8 sequence replaced by U+FFFD
// (one replacement per byte); unchanged when valid.
std::string utf8_replaced(std::string_view text);

}  // namespace chatterlab::app
