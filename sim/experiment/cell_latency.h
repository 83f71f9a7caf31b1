// The latency what-if in a cell (docs/latency.md): its `latency` block, the metric columns its
// per-phase summary covers (summarize_phases, latency.h) and the row columns it adds
// (results/README.md "Latency what-if"). The estimated gaze itself comes from the cell's
// GazeSource (gaze_source.h).
#pragma once
#include <set>
#include <string>

#include "sim/experiment/gaze_source.h"
#include "sim/experiment/latency.h"
#include "sim/experiment/table.h"
#include "sim/foveation/frame.h"
#include "sim/metrics/metrics.h"

namespace fovsim {

struct CellLatency {
  LatencyConfig config;
  std::set<std::string> metric_names;  // every metric column a row had (the phases' means)

  // Notes a row's metric columns (with the what-if on).
  void note(const MetricValues& metrics);
  // The row's latency columns: phase, latency_ms, the estimated gaze in pixels of the real
  // display (`scale`: render.scale), its error against the true gaze, the true gaze's speed.
  void add_columns(ResultRow& row, const GazeSource& gaze, double lat_ms, const FrameData& fd,
                   const FrameContext& ctx, double scale) const;
};

}  // namespace fovsim
