// Option and input validation with the message rule of CONVENTIONS.md: the field, its value
// and the rule it broke ("ekf.r_m2 = 0: must be finite and > 0").
#pragma once

#include <sstream>
#include <string>

#include "analysis/common/summary.h"

namespace chatterlab {

// Throws InputError "<field> = <value>: <rule>" unless rule_holds.
template <typename T>
void require_rule(bool rule_holds, const std::string& field, const T& value,
                  const std::string& rule) {
  if (rule_holds) return;
  std::ostringstream m;
  m << field << " = " << value << ": " << rule;
  throw InputError(m.str());
}

}  // namespace chatterlab
