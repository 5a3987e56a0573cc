#include "analysis/common/number_text.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace chatterlab {

std::string significant_text(double v, int digits) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  const double a = std::abs(v);
  if (a != 0 && (a < 1e-3 || a >= 1e6)) {
    std::snprintf(buf, sizeof(buf), "%.*e", digits - 1, v);
  } else {
    std::snprintf(buf, sizeof(buf), "%.*g", digits, v);
  }
  return buf;
}

std::string stream_text(double v, int precision) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

std::string printf_text(const char* format, double a, double b, double c, double d) {
  char buf[256];
  std::snprintf(buf, sizeof buf, format, a, b, c, d);
  return buf;
}

}  // namespace chatterlab
