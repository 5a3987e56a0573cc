// Numbers in messages and rule texts (the report shows them; results.json keeps full precision).
#pragma once

#include <string>

namespace chatterlab {

// `digits` significant digits: printf %.*g within 1e-3 <= |v| < 1e6 (and for 0), %.*e outside;
// a NaN or infinity gives "n/a". The same text as the report's numbers (app/core/format.h fmt_sig
// calls it).
std::string significant_text(double v, int digits = 4);

// v as an ostream with this precision prints it (printf %.*g; "nan", "inf"): the sync and
// cutting messages.
std::string stream_text(double v, int precision = 6);

// snprintf(format, a, b, c, d) into a 256-byte buffer: a printf format of up to four doubles
// (the frf and sifs messages).
std::string printf_text(const char* format, double a, double b = 0.0, double c = 0.0,
                        double d = 0.0);

}  // namespace chatterlab
