// The gaze each method of a cell sees on one frame (docs/architecture.md "Data flow of one frame":
// gaze source): the true gaze; under the latency what-if (docs/latency.md) the gaze estimated at t
// - latency, whose render part can be the method's own previous cost estimate (the feedback,
// `feedback`); on a frame the tracker lost (docs/tracking.md, trace.on_invalid) the tracking-loss
// policy's gaze. Metrics always keep the frame's true gaze; only the methods' FrameContext changes.
// Eccentricity maps around the estimated and the tracking-loss gaze are buffers of the source,
// computed at most once per frame and gaze, reused across frames.
#pragma once
#include <vector>

#include "sim/experiment/latency.h"
#include "sim/foveation/frame.h"
#include "sim/trace/tracking.h"

namespace fovsim {

class GazeSource {
 public:
  // `truth`: the trace before resampling (gaze at any time, for the estimate); `trace`: the
  // run's resampled trace (frame fi is sample fi). The source keeps references to all four.
  GazeSource(const LatencyConfig& latency, const Trace& truth, const Trace& trace,
             const TrackingPolicy& tracking, const Display& display);

  // Starts frame `fi` for `methods` methods: the frame's phase, gaze speed and tracking state.
  // Sets ctx.widen (kfr, rmfr and flc widen their own parameters).
  void begin_frame(int fi, size_t methods, FrameContext& ctx);
  // Sets the gaze of method `mi` in `ctx` (direction, pixel, validity, eccentricity) and
  // returns the end-to-end latency it used in ms (0 without the what-if).
  double gaze_for(size_t mi, const FrameData& fd, FrameContext& ctx);
  // The method's cost estimate of this frame on the run's first GPU: the render part of its
  // next frame's latency with latency.render_from_estimate.
  void feedback(size_t mi, double est_ms);
  // Forgets the feedback (before a frame that does not follow the previous one).
  void reset();

  const TrackedGaze& tracked() const { return tracked_; }  // this frame's tracking state
  const char* phase() const { return phase_; }   // saccade phase (latency what-if), else null
  double speed_deg_s() const { return speed_; }  // true gaze speed (latency what-if), else 0

 private:
  const LatencyConfig& latency_;
  const Trace& truth_;
  const Trace& trace_;
  const TrackingPolicy& tracking_;
  const Display& display_;
  std::vector<double> prev_est_ms_;  // per method; NaN: no estimate yet
  double t_ = 0;
  int fi_ = 0;
  const char* phase_ = nullptr;
  double speed_ = 0;
  TrackedGaze tracked_;
  glm::dvec3 est_dir_cached_{NAN};  // the direction est_ecc_ was computed for (this frame)
  std::vector<float> est_ecc_;      // eccentricity around the estimated gaze
  bool trk_ecc_ready_ = false;
  std::vector<float> trk_ecc_;  // eccentricity around the gaze shown while tracking is lost
};

}  // namespace fovsim
