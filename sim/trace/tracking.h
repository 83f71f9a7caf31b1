// Tracking loss as a simulated condition (traces/README.md "Tracking loss", docs/tracking.md):
// what gaze a foveation method sees on a frame whose sample is flagged invalid, under the
// run's `trace.on_invalid` policy.
#pragma once
#include <string>
#include <vector>

#include "sim/trace/trace.h"

namespace fovsim {

enum class OnInvalid {
  Hold,    // the last valid gaze (the default: what the readers already store)
  Centre,  // the view centre (head forward)
  Full,    // the last valid gaze, and the method renders as `full` until tracking returns
  Widen    // the last valid gaze, with the foveal region widened by time since it
};

struct TrackingPolicy {
  OnInvalid on_invalid = OnInvalid::Hold;
  // Widen: k = 1 + widen_per_s * (time since the last valid sample); eccentricities the method
  // sees are divided by k, so a foveal radius r becomes k r, and kfr, rmfr and flc widen their
  // own parameters by k (FrameContext::widen, docs/tracking.md).
  double widen_per_s = 10.0;
};

// The policy names, "hold", "centre", "full", "widen": the one list that trace.on_invalid, the
// importer map's on_invalid and `predict --on-invalid` accept.
const std::vector<std::string>& on_invalid_choices();
// Parses one of on_invalid_choices(); false for anything else.
bool parse_on_invalid(const std::string& s, OnInvalid& out);
const char* on_invalid_name(OnInvalid p);

struct TrackedGaze {
  glm::dvec3 gaze_dir{0, 0, -1};  // head space, unit: what the method is given
  bool valid = true;              // the frame's own sample is valid
  // "valid" (tracked), "held" (invalid, last valid gaze shown: hold, full, widen) or "lost"
  // (invalid, no gaze shown: centre). frames.csv column `tracking`.
  const char* state = "valid";
  double since_valid_s = 0;  // time since the last valid sample (0 when valid; from the
                             // first sample when none was valid yet)
  bool render_full = false;  // policy full on an invalid frame
  double widen = 1.0;        // widen only: k = 1 + widen_per_s * since_valid_s (FrameContext)
  double ecc_scale = 1.0;    // multiply the eccentricity map by this (1 / widen)
};

// The gaze of sample `i` of `trace` (a resampled run trace) under `p`. On a valid sample it
// is the sample's gaze unchanged (bit-identical), whatever the policy.
TrackedGaze tracked_gaze(const Trace& trace, size_t i, const TrackingPolicy& p);

}  // namespace fovsim
