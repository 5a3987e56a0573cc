// The progress line `report` prints as each test or group finishes (docs/cli.md#progress):
//   [3/10] cuts/a ok 4.1 s, 12 s elapsed, ~28 s left
#pragma once

#include <string>

#include "app/pipeline/pipeline.h"

namespace chatterlab::app {

// A duration for people: "0.4 s", "12 s", "3 min 05 s".
std::string format_duration(double seconds);

// One line, without the newline. The estimate of the time left ("~28 s left": the mean wall
// time per finished test or group so far, times the number left) is added once `f.elapsed_s`
// reaches `estimate_after_s` and something is left.
std::string progress_line(const NodeFinished& f, double estimate_after_s);

}  // namespace chatterlab::app
