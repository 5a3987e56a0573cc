#include "app/core/format.h"

#include <cmath>
#include <cstdio>

#include "analysis/common/number_text.h"

namespace chatterlab::app {

std::string fmt_sig(double v, int digits) { return significant_text(v, digits); }

std::string fmt_fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  std::string s = buf;
  if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);  // "-0.00"
  return s;
}

}  // namespace chatterlab::app
