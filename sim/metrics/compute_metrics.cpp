// compute_metrics: every enabled per-frame metric of one frame (frame_metrics(), frame_metric.h),
// by frames.csv column name (docs/architecture.md "Metrics", "Outputs"). Each metric's formula
// is in its own file; this runs them in registration order over one shared error-sums pass.
#include <string>

#include "sim/core/error.h"
#include "sim/metrics/error_sums.h"
#include "sim/metrics/frame_metric.h"
#include "sim/metrics/metrics.h"

namespace fovsim {

MetricsScratch::MetricsScratch() = default;
MetricsScratch::~MetricsScratch() = default;
MetricsScratch::MetricsScratch(MetricsScratch&&) noexcept = default;
MetricsScratch& MetricsScratch::operator=(MetricsScratch&&) noexcept = default;

MetricValues compute_metrics(const MetricsConfig& cfg, const Image& test, const Image& ref,
                             const Camera& cam, const std::vector<float>& ecc_deg,
                             TemporalState* temporal, MetricsScratch* scratch,
                             const MetricsScratch* same_test) {
  const char* where = "metrics.compute_metrics";
  const std::vector<FrameMetric>& all = frame_metrics();
  std::vector<const FrameMetric*> on;
  bool need_ecc = false, need_cam = false, need_sums = false, prepares = false;
  for (const FrameMetric& m : all)
    if (cfg.on(m.toggle.key)) {
      on.push_back(&m);
      need_ecc = need_ecc || m.needs_ecc;
      need_cam = need_cam || m.needs_camera;
      need_sums = need_sums || m.sums;
      prepares = prepares || m.prepares_reference;
    }
  detail::check_same_size(test, ref, where);
  if (need_cam) detail::check_cam(test, cam, where);
  if (need_ecc) detail::check_ecc(test, ecc_deg, where);

  // The metrics' preparations of the reference are reused while its pixels are unchanged.
  MetricsScratch local;
  MetricsScratch& sc = scratch ? *scratch : local;
  sc.per_metric.resize(all.size());
  for (auto& s : sc.per_metric)
    if (s) s->new_test();
  if (prepares) {
    const Image& rp = sc.ref_pixels;
    if (rp.width != ref.width || rp.height != ref.height || rp.channels != ref.channels ||
        rp.data != ref.data) {
      for (auto& s : sc.per_metric)
        if (s) s->reference_changed();
      if (scratch) sc.ref_pixels = ref;
    }
  }
  const bool identical = test.data == ref.data;  // sizes are equal (checked above)

  detail::ErrorSums sums;
  if (need_sums) {
    detail::ErrorSumsRequest req;
    req.fovea_deg = cfg.fovea_deg;
    req.band_edges = &cfg.band_edges_deg;
    req.ecc = need_ecc ? &ecc_deg : nullptr;
    req.cam = &cam;
    req.ppd_scale = cfg.ppd_scale;
    for (const FrameMetric* m : on)
      if (m->sums) m->sums(cfg, req);
    sums = detail::error_sums(test, ref, req);
  }
  MetricValues out;
  for (const FrameMetric* m : on) {
    const size_t i = size_t(m - all.data());
    if (m->make_scratch && !sc.per_metric[i]) sc.per_metric[i] = m->make_scratch();
    const FrameMetricScratch* given =
        same_test && i < same_test->per_metric.size() ? same_test->per_metric[i].get() : nullptr;
    const FrameMetricArgs a{
        cfg, test, ref, cam, ecc_deg, identical, sums, temporal, sc.per_metric[i].get(), given};
    m->compute(a, out);
  }
  return out;
}

}  // namespace fovsim
