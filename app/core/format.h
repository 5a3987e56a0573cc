// Number formatting for the report (results.json carries the full-precision values).
#pragma once

#include <string>

namespace chatterlab::app {

// `digits` significant digits, plain notation within 1e-3..1e6, else scientific; NaN -> "n/a".
std::string fmt_sig(double v, int digits = 4);
// Fixed number of decimals; NaN -> "n/a".
std::string fmt_fixed(double v, int decimals);

}  // namespace chatterlab::app
