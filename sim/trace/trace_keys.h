// The run config's `trace` block and its `synthetic` object as declared tables
// (sim/core/param_table.h): one row per key drives load_trace()'s parsing (located errors,
// defaults, ranges) and the `trace` sections of configs/README.md.
#pragma once
#include <string>

#include "sim/core/param_table.h"

namespace fovsim {

// `trace`.
struct TraceBlock {
  std::string on_invalid = "hold";
  double widen_per_s = 10.0;
  std::string on_bad_sample = "fail";
  double quat_tolerance = 1e-3;
  double start = 0, duration = 0;
  std::string on_short = "fail";
  bool resample = true;
  double rate_hz = 90;  // default: the display's refresh rate (set before reading)
  double max_samples = 2e6;
  std::string file, map;  // given: read from a file (map: imported on the fly)
};
const ParamTable<TraceBlock>& trace_block_table();

// `trace.synthetic`.
struct SynthBlock {
  std::string scenario;
  double seed = 1;       // an integer in [0, 2^53] (checked by the table's validator)
  double duration = 10;  // default: trace.start + (trace.duration or 10) (set before reading)
};
const ParamTable<SynthBlock>& synth_block_table();

}  // namespace fovsim
