// `chatterlab report <campaign> --out <dir>`: runs the campaign and writes index.html,
// report.pdf, results.json and figures/ (docs/formats.md).
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

#include "app/pipeline/pipeline.h"

namespace chatterlab::app {

struct ReportOptions {
  bool pdf = true;           // also write report.pdf through WeasyPrint
  bool single_file = false;  // also write report.html, one self-contained file
  int jobs = 0;              // worker threads for tests and figures; 0: one per hardware thread
  // A line on `log` as each test or group finishes ("[3/10] cuts/a ok 4.1 s, 12 s elapsed,
  // ~28 s left"), flushed; the estimate of the time left once the run is estimate_after_s old.
  bool progress = false;
  double estimate_after_s = 10;
  // Where errors go (the campaign that cannot be read, the PDF not written, internal errors,
  // no test analysed): the CLI's stderr. nullptr: `log`.
  std::ostream* errors = nullptr;
  // Called once, after the campaign was read and before the first file is written to `out`
  // (the CLI puts `out`, a temporary folder, in the place of --out only when it was called:
  // app/cli/output_folder.h).
  std::function<void()> before_writing;
  // The per-test cache of a nightly run (app/pipeline/pipeline.h; nullptr: every test runs).
  ResultCache* cache = nullptr;
};

// The campaign folder's own name ("demo" for /any/where/demo/): a report shows no path of the
// machine it ran on.
std::string campaign_folder_name(const CampaignSpec& c);

// results.json `campaign` (it matches [A-Za-z0-9._-]+, docs/results.schema.json): campaign.yaml
// `name` when it is set and valid, else the campaign folder's name with every other character
// as '-' ("campaign" when nothing is left).
std::string results_campaign_name(const CampaignSpec& c);

// Returns the process exit code (app/cli/exit_codes.h, docs/cli.md#exit-status): 0 when the
// report was written and at least one test analysed (skipped tests included); 1 when the
// campaign could not be read at all (nothing written) or the PDF could not be written; 3 when
// a test or group stopped on an internal error (the report is written and names it); 4 when
// the report was written but no test was analysed (every test skipped, or none found).
// Precedence: 3, then 4, then 1.
int run_report(const std::filesystem::path& campaign, const std::filesystem::path& out,
               const ReportOptions& options, std::ostream& log,
               const KindRegistry& kinds = builtin_kinds());

}  // namespace chatterlab::app
