// What running one test or one group product leaves: its status, its warnings and the kind's
// own result (KindResult), which only the kind reads.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "analysis/common/check.h"
#include "analysis/common/summary.h"
#include "app/core/campaign.h"

namespace chatterlab::app {

// The result of a kind's step; each kind derives its own (TapResult, CutOutcome, ...).
struct KindResult {
  virtual ~KindResult() = default;
};

// Why a test or group did not succeed. Input: bad input or a missing input (the test is
// skipped with the reason); internal: an exception that is not an InputError, a broken
// invariant (the report and the exit code say so distinctly).
enum class Failure { kNone, kInput, kInternal };

// What a test's or a group's step left.
struct Outcome {
  StepSummary status;  // not run, ok, or failed with its message
  Failure failure = Failure::kNone;
  std::vector<std::string> warnings;
  double runtime_s = 0;                // of the run that computed it (a restored one's too)
  std::unique_ptr<KindResult> result;  // the kind's result; read only when status is ok
  bool restored = false;               // read back from the per-test cache, not computed

  template <class T>
  const T* result_as() const {
    return dynamic_cast<const T*>(result.get());
  }
  // The kind's result, which must exist and be of type T (a kind reads its own results only
  // of steps whose status is ok): anything else is a broken invariant.
  template <class T>
  const T& result_of() const {
    const T* r = result_as<T>();
    CHATTERLAB_CHECK(r != nullptr,
                     "no result of the expected type (status: " + status.message + ")");
    return *r;
  }
  // Takes a step's result whose own summary and warnings decide the status (TapOutcome,
  // CutOutcome: R has `summary` and `warnings`).
  template <class R>
  void adopt(std::unique_ptr<R> r) {
    warnings.insert(warnings.end(), r->warnings.begin(), r->warnings.end());
    if (r->summary.ok()) {
      status.succeed();
    } else {
      status.fail(r->summary.message);
    }
    result = std::move(r);
  }
};

struct TestOutcome : Outcome {
  const TestSpec* spec = nullptr;  // points into CampaignResults::campaign.tests
};

struct GroupOutcome : Outcome {
  std::string name;                  // GroupProduct::name()
  std::vector<std::string> members;  // test ids whose values it used
};

}  // namespace chatterlab::app
