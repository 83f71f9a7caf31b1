// Importer for recordings in other layouts, driven by a JSON column map
// (traces/README.md "Column maps"; example traces/maps/pico_neo3_pro.json).
#pragma once
#include <string>
#include <vector>

#include "sim/trace/trace.h"

namespace fovsim {

struct ImportReport {
  long data_rows = 0;      // rows after the header
  long skipped_rows = 0;   // dropped under on_bad_row = skip
  long invalid_rows = 0;   // imported with valid = 0
  double time_offset_s = 0;  // subtracted when rebasing
  std::vector<std::string> notes;  // what was skipped/held, one line per kind with the first location
};

// Reads `in` as described by the map file `map_path`. Map errors name the map file and JSON
// path; data errors name in:line:column. `display` converts normalized screen gaze.
Trace import_trace(const std::string& in, const std::string& map_path, const Display& display,
                   ImportReport* report = nullptr);

}  // namespace fovsim
