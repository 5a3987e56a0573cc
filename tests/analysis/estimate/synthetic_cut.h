// Forwards to tests/support/synthetic_cuts.h (the estimator tests' cuts, from the generator of
// analysis/sync/cut_synth.h) for estimate_filter_test.cpp until it includes that header itself.
#pragma once

#include "tests/support/synthetic_cuts.h"
