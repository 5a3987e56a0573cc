#include "analysis/common/summary.h"
