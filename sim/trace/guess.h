// `fovsim trace import IN --guess`: a starting column map inferred from a recording's header
// and first rows, every inferred convention marked "ASSUMPTION" (traces/README.md "--guess").
#pragma once
#include <string>

#include "sim/core/params.h"

namespace fovsim {

// The map as JSON (loadable by import_trace once the assumptions are checked). Throws Error
// naming the file when it cannot be read or has no rows.
Json guess_map(const std::string& in);

}  // namespace fovsim
