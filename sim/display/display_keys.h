// The declaration of a display's keys (models/displays/*.json or an inline `display` object):
// parsing, defaults, ranges and the tables of configs/README.md (sim/core/param_table.h).
#pragma once
#include "sim/core/param_info.h"
#include "sim/display/display.h"

namespace fovsim {

const ParamTable<Display>& display_table();

}  // namespace fovsim
