// `psnr` (frame_metric.h): 10 log10(1 / MSE) over all pixels and channels, from the shared
// error sums (error_sums.h).
#include "sim/metrics/frame_metric.h"

namespace fovsim {

const FrameMetric& psnr_frame_metric() {
  static const FrameMetric m = [] {
    FrameMetric d;
    d.name = "psnr";
    d.toggle = {"psnr", true, "", "write `psnr`"};
    d.columns = [](const MetricsConfig&) { return std::vector<std::string>{"psnr"}; };
    d.sums = [](const MetricsConfig&, detail::ErrorSumsRequest&) {};  // the plain sums
    d.compute = [](const FrameMetricArgs& a, MetricValues& out) {
      out.set("psnr", detail::psnr_from_mse(a.sums.sq / a.sums.n));
    };
    return d;
  }();
  return m;
}

}  // namespace fovsim
