// `temporal` (frame_metric.h): the frame-to-frame change of the error in the periphery
// (temporal.cpp), against the converged reference only; NaN without the caller's temporal state
// or on its first frame.
#include <limits>

#include "sim/metrics/frame_metric.h"

namespace fovsim {

const FrameMetric& temporal_frame_metric() {
  static const FrameMetric m = [] {
    FrameMetric d;
    d.name = "temporal";
    d.toggle = {"temporal", true, "", "write `temporal_error`"};
    d.columns = [](const MetricsConfig&) { return std::vector<std::string>{"temporal_error"}; };
    d.needs_ecc = true;
    d.state_bytes = [](double pixels) { return 2 * 4 * pixels; };  // two luma planes
    d.reference_only = true;
    d.compute = [](const FrameMetricArgs& a, MetricValues& out) {
      out.set("temporal_error",
              a.temporal ? temporal_error(a.test, a.ref, a.ecc, a.cfg.fovea_deg, *a.temporal)
                         : std::numeric_limits<double>::quiet_NaN());
    };
    return d;
  }();
  return m;
}

}  // namespace fovsim
