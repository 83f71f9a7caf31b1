// A cell's cost side (docs/architecture.md "Data flow of one frame", step 4 "rows"): its GPU
// profiles, the workload of what the scene does not say and budget.p_fit. Cell::build_rows
// (cell_rows.cpp) turns one method's frame into one ResultRow per GPU.
#pragma once
#include <vector>

#include "sim/cost/budget.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/workload.h"

namespace fovsim {

struct CellCost {
  std::vector<GpuProfile> gpus;
  double fit_level = kDefaultFitLevel;  // budget.p_fit
  Workload workload;
};

}  // namespace fovsim
