// Importer for recordings in other layouts, driven by a JSON column map
// (traces/README.md "Column maps"; examples in traces/maps/).
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "sim/core/params.h"
#include "sim/trace/trace.h"

namespace fovsim {

struct ImportReport {
  long data_rows = 0;          // rows after the header that were read
  long skipped_rows = 0;       // dropped under on_bad_row = skip (or a FOV skip)
  long invalid_rows = 0;       // imported with valid = 0
  long one_eye_rows = 0;       // per-eye gaze with only one eye valid (that eye used)
  long time_wraps = 0;         // counter wrap-arounds unwrapped (time.wrap_bits)
  long burst_samples = 0;      // samples closer than the burst interval to the previous one
  long repeated_poses = 0;     // samples whose head pose repeats the previous sample's exactly
  bool stopped_early = false;  // reading stopped at ImportOptions::stop_after_s
  double time_offset_s = 0;    // subtracted when rebasing
  long fused_rows = 0;         // rows whose fused field was split (the map's "fused")
  std::string on_invalid;      // the map's "on_invalid" (run default), "" when not given
  std::vector<std::string>
      notes;  // what was skipped/held/changed, one line per kind with the first location
};

struct ImportOptions {
  // Valid gaze outside the display FOV: an error at file:line:column (Fail), dropped (Skip),
  // or replaced by the last valid gaze (Hold). check_fov = false leaves it to the caller.
  bool check_fov = true;
  BadSamplePolicy on_fov = BadSamplePolicy::Fail;
  // False: the map's "on_bad" (when given) replaces on_fov; true: the caller chose it.
  bool on_fov_explicit = false;
  // Stop reading once a sample lies more than this many seconds after the first one (that
  // sample is kept, so resampling can bracket the end): a run asking for 2 s reads ~2 s.
  double stop_after_s = INFINITY;
};

// Reads `in` as described by the map file `map_path`. Map errors name the map file and JSON
// path; data errors name in:line:column. `display` converts normalized screen gaze and bounds
// the FOV check.
Trace import_trace(const std::string& in, const std::string& map_path, const Display& display,
                   ImportReport* report = nullptr, const ImportOptions& opt = {});
// The same with the map already parsed; `map_name` names it in map errors.
Trace import_trace(const std::string& in, const Json& map, const std::string& map_name,
                   const Display& display, ImportReport* report = nullptr,
                   const ImportOptions& opt = {});

}  // namespace fovsim
