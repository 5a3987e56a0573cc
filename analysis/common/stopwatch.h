// Wall time of a step, for the runtime_s keys of results.json.
#pragma once

#include <chrono>

namespace chatterlab {

using SteadyClock = std::chrono::steady_clock;

// Seconds from t0 to now.
inline double seconds_since(SteadyClock::time_point t0) {
  return std::chrono::duration<double>(SteadyClock::now() - t0).count();
}

}  // namespace chatterlab
