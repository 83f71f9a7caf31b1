// Trace summary printed by `fovsim trace stats|validate|import` (traces/README.md).
#pragma once
#include <string>
#include <vector>

#include "sim/trace/trace.h"

namespace fovsim {

struct TraceStats {
  size_t samples = 0;
  double duration_s = 0;
  double rate_hz = 0;  // 1 / median sample interval
  double rate_mean_hz =
      0;          // (samples - 1) / duration: robust to jittered intervals (8/9 ms -> 120 Hz)
  long gaps = 0;  // intervals longer than 1.5 x the median
  double max_gap_s = 0;
  long bursts =
      0;  // intervals shorter than a quarter of the median (samples flushed after a stall)
  long repeated_poses = 0;     // samples whose head pose equals the previous sample's exactly
  bool constant_head = false;  // every sample has the same head pose: repeats not checked
  double invalid_fraction = 0;
  // Gaze eccentricity (angle from head forward, deg) over valid samples.
  double ecc_p50 = 0, ecc_p95 = 0, ecc_max = 0;
  // Eye-in-head angular speed (deg/s) between consecutive valid samples.
  double speed_p50 = 0, speed_p95 = 0, speed_p99 = 0;
  // Head angular speed (deg/s) and path length (m).
  double head_speed_p50 = 0, head_speed_p99 = 0, head_speed_max = 0, head_path_m = 0;
  // The largest head rotations between consecutive samples (at most 5, largest first):
  // "line 812 (t=3.456 s): 13.2 deg in 10.0 ms (1320 deg/s)".
  std::vector<std::string> head_jumps;
  // Plausibility: one line per value outside human ranges (eye-speed p99 > 700 deg/s: saccade
  // peak velocities saturate near 500-700 deg/s, docs/architecture.md "Inputs: displays, traces,
  // scenes, configs"; eccentricity p95 > 35 deg; bursts).
  std::vector<std::string> warnings;
};

constexpr double kPlausibleSpeedP99 = 700;  // deg/s
constexpr double kPlausibleEccP95 = 35;     // deg
// Head rotation: peaks reach a few hundred deg/s, the median over a session is far lower.
constexpr double kPlausibleHeadSpeedP50 = 200;  // deg/s
// Head rotation rarely exceeds ~500-800 deg/s even in fast turns (Grossman et al. 1988):
// above 1000 deg/s between two samples the pose or its time is wrong.
constexpr double kPlausibleHeadSpeed = 1000;  // deg/s

TraceStats trace_stats(const Trace& tr);
// Multi-line human-readable summary.
std::string format_stats(const TraceStats& s);

}  // namespace fovsim
