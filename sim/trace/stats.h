// Trace summary printed by `fovsim trace stats|validate|import` (traces/README.md).
#pragma once
#include <string>

#include "sim/trace/trace.h"

namespace fovsim {

struct TraceStats {
  size_t samples = 0;
  double duration_s = 0;
  double rate_hz = 0;          // 1 / median sample interval
  long gaps = 0;               // intervals longer than 1.5 x the median
  double max_gap_s = 0;
  double invalid_fraction = 0;
  // Gaze eccentricity (angle from head forward, deg) over valid samples.
  double ecc_p50 = 0, ecc_p95 = 0, ecc_max = 0;
  // Eye-in-head angular speed (deg/s) between consecutive valid samples.
  double speed_p50 = 0, speed_p95 = 0, speed_p99 = 0;
  // Head angular speed (deg/s) and path length (m).
  double head_speed_p50 = 0, head_speed_p99 = 0, head_path_m = 0;
};

TraceStats trace_stats(const Trace& tr);
// Multi-line human-readable summary.
std::string format_stats(const TraceStats& s);

}  // namespace fovsim
