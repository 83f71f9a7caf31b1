// libFuzzer target: a sweep config -> expand_sweep -> validate_cells.
// Every failure must be a fovsim::Error (no "internal error", no crash, no unbounded memory:
// the cell cap applies before expansion).
#include <cstddef>
#include <cstdint>
#include <string>

#include "sim/core/error.h"
#include "sim/experiment/sweep_spec.h"

using namespace fovsim;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  try {
    LoadedConfig cfg;
    cfg.file = "fuzz.json";
    cfg.doc = parse_json_text(text, cfg.file);
    SweepPlan plan = expand_sweep(cfg);
    if (plan.cells.size() <= 64) validate_cells(plan);  // constructs methods: keep each run short
  } catch (const Error&) {
  }
  return 0;
}
