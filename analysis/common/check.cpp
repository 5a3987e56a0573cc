#include "analysis/common/check.h"

#include <cstring>

namespace chatterlab {

void invariant_failed(const char* condition, const std::string& what, const char* file, int line) {
  const char* slash = std::strrchr(file, '/');
  throw InvariantError("invariant '" + std::string(condition) + "' broken at " +
                       (slash ? slash + 1 : file) + ":" + std::to_string(line) + ": " + what);
}

}  // namespace chatterlab
