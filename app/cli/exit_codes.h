// The exit status of `chatterlab` (docs/cli.md#exit-status), shared by every command.
#pragma once

namespace chatterlab::app {

inline constexpr int kExitOk = 0;
// Bad input: a campaign or spec that cannot be read, a refused --out folder, `validate`
// finding a problem, a PDF that could not be written, a simulation that did not complete.
inline constexpr int kExitInputError = 1;
// `compare`: a number moved beyond its tolerance or vanished (the format's rule: exit 1).
inline constexpr int kExitFlagged = 1;
inline constexpr int kExitUsage = 2;  // a command line that does not parse
// A bug or a broken invariant: a test or group of `report` stopped on one (the report is
// written and names it), or any command stopped on one.
inline constexpr int kExitInternalError = 3;
// `report` wrote its report but analysed no test: every test was skipped, or none was found.
inline constexpr int kExitNothingAnalysed = 4;

}  // namespace chatterlab::app
