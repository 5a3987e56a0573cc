// Runs every test of a campaign through the steps of its kind (DESIGN.md data flow), in
// parallel, each test isolated: a test that fails is skipped with its reason and never stops
// the others. A report never shows a number from a step that failed.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/cutting/dyno_options.h"
#include "analysis/cutting/dyno_slot.h"
#include "analysis/cutting/slot_fit.h"
#include "app/campaign.h"
#include "app/cut_step.h"
#include "app/tap_step.h"

namespace chatterlab::app {

struct PipelineOptions {
  int jobs = 0;  // worker threads; 0: one per hardware thread
  cutting::DynoOptions dyno;
  TapStepOptions tap;
};

struct DynoRecordOutcome {
  double feed_per_tooth_m = 0, axial_depth_m = 0, spindle_rpm = 0;
  cutting::SlotRecordResult result;
};

struct TestOutcome {
  const TestSpec* spec = nullptr;  // points into CampaignResults::campaign.tests
  // ok: analysed. Otherwise the test was skipped and message says why.
  StepSummary status;
  std::vector<std::string> warnings;
  double runtime_s = 0;
  std::optional<TapOutcome> tap;
  std::optional<DynoRecordOutcome> dyno;
  std::optional<CutOutcome> cut;
};

struct DynoGroupOutcome {
  StepSummary summary;  // ok only when the coefficient fit succeeded
  std::vector<std::string> test_ids;
  cutting::SlotCoefficients fit;
};

struct InputFile {
  std::string relative_path;
  std::uintmax_t bytes = 0;
  std::string sha256;
};

struct CampaignResults {
  CampaignSpec campaign;
  PipelineOptions options;
  std::vector<TestOutcome> tests;  // same order as campaign.tests
  std::optional<DynoGroupOutcome> dyno_group;
  CutStepInputs cut_inputs;       // what the cut tests took from the tap tests and dyno group
  std::vector<InputFile> inputs;  // every yaml and signal file read
  double runtime_s = 0;
};

// The cut test whose identification gives the campaign's `identified` block
// (docs/identification.md): the first constant-depth cut test (by id) whose identification
// succeeded, else the first ramped one; null when none succeeded.
const TestOutcome* identification_source(const CampaignResults& r);

// Loads nothing: takes a loaded campaign. Never throws for bad test content.
CampaignResults run_campaign(CampaignSpec campaign, const PipelineOptions& options);

}  // namespace chatterlab::app
