// `chatterlab report <campaign> --out <dir>`: runs the campaign and writes index.html,
// report.pdf, results.json and figures/ (docs/formats.md).
#pragma once

#include <filesystem>
#include <ostream>

#include "app/pipeline/pipeline.h"

namespace chatterlab::app {

struct ReportOptions {
  bool pdf = true;  // also write report.pdf through WeasyPrint
  int jobs = 0;     // worker threads for tests and figures; 0: one per hardware thread
};

// Returns the process exit code: 0 when the report was written (skipped tests included),
// 1 when the campaign could not be read at all or the PDF could not be written, 3 when a test
// or group stopped on an internal error (the report is written and names it).
int run_report(const std::filesystem::path& campaign, const std::filesystem::path& out,
               const ReportOptions& options, std::ostream& log,
               const KindRegistry& kinds = builtin_kinds());

}  // namespace chatterlab::app
