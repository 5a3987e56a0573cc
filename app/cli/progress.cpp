#include "app/cli/progress.h"

#include <cmath>
#include <cstdio>

namespace chatterlab::app {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) seconds = 0;
  char buf[48];
  if (seconds < 9.95) {
    std::snprintf(buf, sizeof buf, "%.1f s", seconds);
  } else if (seconds < 119.5) {
    std::snprintf(buf, sizeof buf, "%.0f s", seconds);
  } else {
    const long total = std::lround(seconds);
    std::snprintf(buf, sizeof buf, "%ld min %02ld s", total / 60, total % 60);
  }
  return buf;
}

std::string progress_line(const NodeFinished& f, double estimate_after_s) {
  std::string name = f.name;
  if (f.group && name.rfind("group:", 0) == 0) name = "group " + name.substr(6);
  const char* status = f.ok ? "ok" : (f.failure == Failure::kInternal ? "ERROR" : "skipped");
  std::string line = "[" + std::to_string(f.done) + "/" + std::to_string(f.total) + "] " + name +
                     " " + status + " " + format_duration(f.runtime_s) + ", " +
                     format_duration(f.elapsed_s) + " elapsed";
  if (f.done > 0 && f.done < f.total && f.elapsed_s >= estimate_after_s) {
    const double left =
        f.elapsed_s / static_cast<double>(f.done) * static_cast<double>(f.total - f.done);
    line += ", ~" + format_duration(left) + " left";
  }
  return line;
}

}  // namespace chatterlab::app
