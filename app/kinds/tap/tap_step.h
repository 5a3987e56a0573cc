// The tap-test step: hits -> H1/H2 + coherence -> modal fit (DESIGN.md data flow), with the
// result copied into plain data for results.json and the report.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/frf/frf.h"
#include "analysis/frf/hits.h"
#include "analysis/frf/modal_fit.h"
#include "analysis/frf/mode.h"
#include "app/core/campaign.h"
#include "app/pipeline/outcome.h"

namespace chatterlab::app {

// Analysis defaults of every tap test (docs/tap-tests.md); a test's band_hz and modes keys
// override fit.band_hz and fit.n_modes for that test.
struct TapStepOptions {
  frf::HitOptions hits;
  frf::FrfOptions frf;
  frf::ModalFitOptions fit;
};

// test.yaml `frf:` of a tap test that gives a measured FRF instead of hits (docs/tap-tests.md,
// "A measured FRF as input").
struct TapFrfInput {
  std::string file;    // relative to the test folder
  char delimiter = 0;  // text files: as frf_text::ReadOptions
  char decimal = 0;
  int record = 0;  // UFF58: 1-based among the file's FRF records (function type 4); 0: the only
  double exp_window_tau_s = 0.0;  // an exponential window the FRF already carries (0: none)
};

// test.yaml keys of a tap test (docs/formats.md).
struct TapSpec : KindSpec {
  std::string axis;      // "x" or "y"
  std::string response;  // acceleration | velocity | displacement
  bool hits_auto = true;
  std::vector<std::pair<double, double>> hit_windows_s;
  std::optional<std::pair<double, double>> band_hz;
  int modes = 0;                   // 0: automatic
  std::optional<TapFrfInput> frf;  // set: the FRF comes from this file (no data, no hits)
};

struct TapHitInfo {
  double time_s = 0;  // start of the hit's pulse
  double peak_N = 0;
  bool accepted = false;
  std::string reason;  // why it was rejected
};

struct TapOutcome : KindResult {
  StepSummary summary;
  // FRF from a file (test.yaml `frf:`): no hits, H2 = H1, coherence 1 unless the file has it.
  bool from_file = false;
  std::string frf_file;       // as test.yaml names it (relative to the test folder)
  std::string frf_columns;    // how the file's columns were read
  bool has_coherence = true;  // ok when the FRF exists (the fit may still have failed: fit_ok)
  std::vector<std::string> warnings;
  std::vector<TapHitInfo> hits;
  int hits_used = 0;
  Eigen::VectorXd f_hz;
  Eigen::VectorXcd h1, h2;  // receptance, m/N
  Eigen::VectorXd coherence;
  double df_hz = std::numeric_limits<double>::quiet_NaN();
  double exp_window_tau_s = std::numeric_limits<double>::quiet_NaN();  // NaN: none applied
  bool fit_ok = false;
  std::string fit_message = "not run";
  std::vector<frf::Mode> modes;           // sorted by frequency; empty unless fit_ok
  std::vector<frf::ModeQuality> quality;  // one per mode
  double fit_nrmse_pct = std::numeric_limits<double>::quiet_NaN();
  double band_lo_hz = std::numeric_limits<double>::quiet_NaN();
  double band_hi_hz = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXcd fitted;  // model receptance on f_hz (empty unless fit_ok)
};

// test.yaml's `response` (acceleration | velocity | displacement, validated by the loader).
frf::ResponseKind response_kind_of(const std::string& response);

// The measured FRF of a tap test that names one (test.yaml `frf:`), as receptance with the
// file's coherence (1 where it has none). Throws InputError naming the file (and line, key).
frf::Frf read_tap_frf(const TestSpec& t, std::vector<std::string>* warnings = nullptr,
                      std::string* columns = nullptr, bool* has_coherence = nullptr);

// Runs the step on one tap test. Bad input throws InputError (the caller skips the test).
TapOutcome run_tap_test(const TestSpec& t, const TapStepOptions& options);

}  // namespace chatterlab::app
