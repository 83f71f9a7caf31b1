// Head+gaze traces (docs/architecture.md "Inputs: displays, traces, scenes, configs"). Canonical
// CSV documented in traces/README.md.
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/core/params.h"
#include "sim/display/display.h"

namespace fovsim {

struct TraceSample {
  double t = 0;                     // seconds, strictly increasing
  glm::dvec3 head_pos{0.0};         // metres, world
  glm::dquat head_rot{1, 0, 0, 0};  // world-from-head, unit
  glm::dvec3 gaze_dir{0, 0, -1};    // unit, head space (-Z forward)
  bool valid = true;                // false during blinks / tracking loss
};

struct Trace {
  std::string source;  // file path or "synthetic:<scenario>:<seed>"
  std::vector<TraceSample> samples;
  // Problems that a skip/hold policy handled (one line per kind, with the first location and
  // a count) or that a caller should know. Never empty when something was changed.
  std::vector<std::string> warnings;
  // Line of each sample in its source file, when read from one (empty otherwise, and after
  // resampling): lets summaries name the lines of implausible samples.
  std::vector<long> lines;
  double duration() const { return samples.empty() ? 0 : samples.back().t - samples.front().t; }
};

// What to do with a problem sample (NaN, gaze outside the FOV, invalid flag): never silent.
enum class BadSamplePolicy { Fail, Skip, Hold };

struct TraceReadOptions {
  BadSamplePolicy on_bad = BadSamplePolicy::Fail;
  double quat_tolerance = 1e-3;  // | |q| - 1 | beyond this is an error
  // Intervals between kept samples longer than this (seconds) are listed in
  // Trace::warnings with the first location, count and longest (`trace validate --max-gap`);
  // INFINITY checks nothing.
  double max_gap_s = INFINITY;
};

// Largest |t| a trace may hold: 2^53 microseconds (~285 years). Up to there a double holds
// every microsecond exactly and t in nanoseconds fits a 64-bit integer; beyond it a time is
// an error ("time value out of range"), like a bad number.
constexpr double kMaxTraceTimeS = 9007199254.740992;
// Shortest interval between consecutive samples: 1 us, the resolution kMaxTraceTimeS keeps
// exact, so a trace's rate is at most 1 MHz (research eye trackers sample at up to 2 kHz,
// Holmqvist et al. 2011 ch. 2). A closer sample (t=0 then t=1e-12, or a denormal step whose
// rate is inf Hz) is refused like a non-increasing time ("interval too short").
constexpr double kMinTraceIntervalS = 1e-6;

// Reads the canonical CSV. Errors name file:line:column. Gaze given as a normalized screen
// point (columns gaze_u, gaze_v) is converted with `display`. Rows with valid=0 may carry no
// (or any) gaze: the last valid gaze is used. Problems handled by skip/hold are listed in
// Trace::warnings (traces/README.md).
Trace read_trace_csv(const std::string& path, const Display& display,
                     const TraceReadOptions& opt = {});
void write_trace_csv(const std::string& path, const Trace& trace);
// Checks `trace` as write_trace_csv would write it to `out` with read_trace_csv's checks and
// defaults (trace validate's): the first problem is an Error naming the line of `source` the
// sample came from (Trace::lines), the row and column it would have in `out`, and what is wrong.
// `trace import` runs it before writing, so it never writes a file validate refuses.
void check_trace_as_written(const Trace& trace, const Display& display, const std::string& source,
                            const std::string& out);

// Above this fraction of samples flagged invalid, readers add a warning (Trace::warnings):
// blinks and brief losses are 2-10 % of a recording (Holmqvist et al. 2011 ch. 4); a quarter
// or more usually means a wrong validity condition or a tracker that lost the eyes.
constexpr double kWarnInvalidFraction = 0.25;
// Adds that warning to `tr`; a trace with no valid sample at all is an Error naming its source
// (nothing to foveate on: refused by import, validate and run). `hint` ends the error message.
void check_invalid_fraction(Trace& tr, const std::string& hint = "");

// Resamples to `hz` from the first sample: lerp positions, slerp orientations, normalized lerp of
// gaze (nearest for `valid`). Frames past the end, or past `t_end` (absolute time), are not
// produced: a caller resamples only the range it uses.
Trace resample(const Trace& trace, double hz, double t_end = INFINITY);
// Number of samples resample(trace, hz, t_end) produces, computed without producing them.
double resampled_count(const Trace& trace, double hz, double t_end = INFINITY);

// Default of the trace block's "max_samples": most samples a run holds after resampling.
constexpr double kDefaultMaxTraceSamples = 2e6;

// Sample at any time t (s): resample()'s interpolation (normalized lerp of gaze, lerp of
// position, `valid` from the nearest sample), held at the first/last sample outside the trace.
// Orientation is taken from the nearest sample (callers use the gaze only).
TraceSample sample_at(const Trace& trace, double t);
// Angle between two directions in degrees (stable for tiny angles).
double angle_deg(const glm::dvec3& a, const glm::dvec3& b);
// Eye-in-head angular speed (deg/s) at t: angle between the gaze at t - h and t + h over 2h.
double gaze_speed_deg_s(const Trace& trace, double t, double half_window_s);

// True if a head-space direction is in front of the eye and projects inside the display's
// screen rectangle (normalized screen point in [0,1]^2).
bool gaze_inside_fov(const Display& display, const glm::dvec3& dir);

// Trace from a run config's "trace" block: {"file": ...} or {"synthetic": {...}}.
// `needed_s`: seconds after `start` the caller will use (from frames.count); the trace is
// resampled only up to there, and the resampled range is checked against "max_samples"
// before it is allocated.
// `tracking`, when given, receives the "on_invalid" and "widen_per_s" keys (tracking.h).
struct TrackingPolicy;
Trace load_trace(Params& p, const Display& display, const std::string& base_dir,
                 double needed_s = INFINITY, TrackingPolicy* tracking = nullptr);

}  // namespace fovsim
