// `fpsnr` (frame_metric.h): foveated PSNR (Lee, Pattichis and Bovik 2002), the squared error
// weighted by the eccentricity-dependent cutoff frequency, from the shared error sums
// (error_sums.h, psnr.cpp's weight).
#include "sim/metrics/frame_metric.h"

namespace fovsim {

const FrameMetric& fpsnr_frame_metric() {
  static const FrameMetric m = [] {
    FrameMetric d;
    d.name = "fpsnr";
    d.toggle = {"fpsnr", true, "Lee, Pattichis, Bovik 2002", "write `fpsnr` (foveated PSNR)"};
    d.columns = [](const MetricsConfig&) { return std::vector<std::string>{"fpsnr"}; };
    d.needs_ecc = true;
    d.needs_camera = true;
    d.sums = [](const MetricsConfig&, detail::ErrorSumsRequest& req) { req.weighted = true; };
    d.compute = [](const FrameMetricArgs& a, MetricValues& out) {
      out.set("fpsnr", detail::psnr_from_mse(a.sums.w_sq / a.sums.w));
    };
    return d;
  }();
  return m;
}

}  // namespace fovsim
