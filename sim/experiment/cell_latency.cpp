#include "sim/experiment/cell_latency.h"

namespace fovsim {

void CellLatency::note(const MetricValues& metrics) {
  if (config.enabled)
    for (auto& kv : metrics.items()) metric_names.insert(kv.first);
}

void CellLatency::add_columns(ResultRow& row, const GazeSource& gaze, double lat_ms,
                              const FrameData& fd, const FrameContext& ctx, double scale) const {
  if (!config.enabled) return;
  row.set_text("phase", gaze.phase());
  row.set("latency_ms", lat_ms);
  row.set("gaze_est_x", ctx.gaze_px.x / scale);
  row.set("gaze_est_y", ctx.gaze_px.y / scale);
  row.set("gaze_error_deg", angle_deg(fd.gaze_dir, ctx.gaze_dir));
  row.set("gaze_speed_deg_s", gaze.speed_deg_s());
}

}  // namespace fovsim
