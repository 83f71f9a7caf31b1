// `ssim` (frame_metric.h): SSIM (Wang et al. 2004, ssim.cpp) of Rec.709 luma, the reference
// prepared once per reference (every method of a frame shares it).
#include "sim/metrics/frame_metric.h"

namespace fovsim {

namespace {

struct SsimScratch : FrameMetricScratch {
  SsimPrepared ref;
  void reference_changed() override { ref.width = 0; }
};

bool in_unit_range(const Image& im) {
  for (float v : im.data)
    if (!(v >= 0.f && v <= 1.f)) return false;  // NaN too
  return true;
}

void compute(const FrameMetricArgs& a, MetricValues& out) {
  const Image& test = a.test;
  double v;
  if (a.identical && test.channels != 2 && test.width >= 11 && test.height >= 11 &&
      in_unit_range(test)) {
    // Identical images (the `full` method of every run): with mu_x = mu_y, sigma_x^2 = sigma_y^2
    // = sigma_xy bit for bit, 2 mu_x mu_y and mu_x^2 + mu_y^2 are the same doubling of one
    // rounded product, so every pixel's numerator and denominator are equal and nonzero (C1
    // and C2 dominate any rounding for values in [0,1]): each ratio is exactly 1, and so is
    // their mean (metrics_kernels_test checks it against the full computation).
    v = 1.0;
  } else {
    SsimPrepared& ref = static_cast<SsimScratch*>(a.scratch)->ref;
    if (ref.width == 0) ssim_prepare(a.ref, ref);
    v = ssim(test, ref);
  }
  out.set("ssim", v);
}

}  // namespace

const FrameMetric& ssim_frame_metric() {
  static const FrameMetric m = [] {
    FrameMetric d;
    d.name = "ssim";
    d.toggle = {"ssim", true, "Wang et al. 2004", "write `ssim` (image must be at least 11x11)"};
    d.columns = [](const MetricsConfig&) { return std::vector<std::string>{"ssim"}; };
    d.make_scratch = []() -> std::unique_ptr<FrameMetricScratch> {
      return std::make_unique<SsimScratch>();
    };
    d.prepares_reference = true;
    d.scratch_bytes = [](double pixels) { return 5 * 4 * pixels; };  // luma, G*y, G*y^2 planes
    d.compute = compute;
    return d;
  }();
  return m;
}

}  // namespace fovsim
