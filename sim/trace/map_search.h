// `fovsim trace import IN --guess`: a column map chosen by testing hypotheses against the data
// (traces/README.md "--guess"). The name-based starting map (guess.h) is varied along the
// conventions the names cannot tell -- time column and unit, axis convention, gaze space,
// quaternion order and direction, validity encoding, gaze sentinels, angle units -- and every
// variant imports a sample of the rows through the real importer and is scored on how human
// the result looks (gaze in front of the eye, eccentricity, eye and head speed, valid
// fraction, monotone time, an upright head).
#pragma once
#include <string>
#include <vector>

#include "sim/core/params.h"
#include "sim/display/display.h"
#include "sim/trace/importer.h"

namespace fovsim {

struct MapSearchResult {
  Json map;  // the chosen map; importing IN with it (default options) succeeds
  // For stderr: the choice and its evidence, the runner-up and the margin, ambiguity.
  std::vector<std::string> report;
  bool plausible = false;  // the chosen map's import passes every plausibility bound
  bool ambiguous = false;  // the runner-up scores within kAmbiguousMargin of the best
  int hypotheses = 0;      // distinct maps imported and scored
};

// Score difference below which two hypotheses count as indistinguishable.
constexpr double kAmbiguousMargin = 0.05;

// Throws Error naming IN and the evidence when no hypothesis imports at all.
MapSearchResult search_map(const std::string& in, const Display& display);

// One line naming the map key most likely wrong for a failed import of `in` with `map`,
// judged from the data (e.g. "gaze z > 0 on 100 % of rows: try `coordinates: unity`"); ""
// when no single change of one key makes the import succeed.
std::string import_failure_hint(const std::string& in, const Json& map, const Display& display);

// import_trace, and on failure the same Error with import_failure_hint appended.
Trace import_trace_hinted(const std::string& in, const std::string& map_path,
                          const Display& display, ImportReport* report = nullptr,
                          const ImportOptions& opt = {});

}  // namespace fovsim
