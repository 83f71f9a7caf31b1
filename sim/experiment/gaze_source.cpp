#include "sim/experiment/gaze_source.h"

#include <algorithm>
#include <cmath>

namespace fovsim {

GazeSource::GazeSource(const LatencyConfig& latency, const Trace& truth, const Trace& trace,
                       const TrackingPolicy& tracking, const Display& display)
    : latency_(latency), truth_(truth), trace_(trace), tracking_(tracking), display_(display) {}

void GazeSource::begin_frame(int fi, size_t methods, FrameContext& ctx) {
  if (prev_est_ms_.size() != methods) prev_est_ms_.assign(methods, NAN);
  fi_ = fi;
  t_ = trace_.samples[size_t(fi)].t;
  const double period = 1.0 / display_.refresh_hz;
  phase_ = nullptr;
  speed_ = 0;
  if (latency_.enabled) {
    phase_ = phase_name(gaze_phase(truth_, t_, period, latency_));
    speed_ = gaze_speed_deg_s(truth_, t_, 0.5 * period);
  }
  est_dir_cached_ = glm::dvec3(NAN);
  tracked_ = tracked_gaze(trace_, size_t(fi), tracking_);
  ctx.widen = tracked_.valid ? 1.0 : tracked_.widen;
  trk_ecc_ready_ = false;
}

double GazeSource::gaze_for(size_t mi, const FrameData& fd, FrameContext& ctx) {
  double lat_ms = 0;
  if (latency_.enabled) {
    double render_part = latency_.render_ms;
    if (latency_.render_from_estimate && std::isfinite(prev_est_ms_[mi])) {
      // A frame is scanned out at the first vsync after its GPU work: whole periods.
      const double budget = display_.frame_budget_ms();
      render_part = std::max(1.0, std::ceil(prev_est_ms_[mi] / budget - 1e-9)) * budget;
    }
    lat_ms = latency_.total_ms(fi_, render_part);
  }
  // Zero latency without a predictor: exactly the true gaze and its numbers.
  if (latency_.enabled && (lat_ms > 0 || latency_.predictor != "none")) {
    const double period = 1.0 / display_.refresh_hz;
    TraceSample est = estimated_gaze(truth_, t_, lat_ms * 1e-3, period, latency_);
    glm::dvec3 dir = glm::normalize(est.gaze_dir);
    if (!(dir == est_dir_cached_)) {
      eccentricity_map(fd.camera, dir, est_ecc_);
      est_dir_cached_ = dir;
    }
    ctx.gaze_dir = dir;
    ctx.gaze_px = gaze_pixel(fd.camera, dir);
    ctx.gaze_valid = est.valid;
    ctx.eccentricity = &est_ecc_;
  } else {  // this method's latency is 0: the true gaze, even after another method's estimate
    ctx.gaze_dir = fd.gaze_dir;
    ctx.gaze_px = fd.gaze_px;
    ctx.gaze_valid = fd.gaze_valid;
    ctx.eccentricity = &fd.eccentricity;
  }
  if (!tracked_.valid) {  // the frame's own tracking state, also under the latency what-if
    if (!trk_ecc_ready_) {
      eccentricity_map(fd.camera, tracked_.gaze_dir, trk_ecc_);
      if (tracked_.ecc_scale != 1.0)
        for (float& e : trk_ecc_) e = float(double(e) * tracked_.ecc_scale);
      trk_ecc_ready_ = true;
    }
    ctx.gaze_dir = tracked_.gaze_dir;
    ctx.gaze_px = gaze_pixel(fd.camera, tracked_.gaze_dir);
    ctx.gaze_valid = false;
    ctx.eccentricity = &trk_ecc_;
  }
  return lat_ms;
}

void GazeSource::feedback(size_t mi, double est_ms) {
  prev_est_ms_[mi] = est_ms;
}

void GazeSource::reset() {
  std::fill(prev_est_ms_.begin(), prev_est_ms_.end(), NAN);
}

}  // namespace fovsim
