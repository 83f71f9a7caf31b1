// What the run engine and the config table ask of the per-frame metrics as a whole
// (frame_metric.h): their columns, images, scratch bytes, toggles.
#include "sim/metrics/frame_metric.h"

#include "sim/core/error.h"

namespace fovsim {

bool MetricsConfig::on(const std::string& key) const {
  if (auto it = toggles.find(key); it != toggles.end()) return it->second;
  for (const FrameMetric& m : frame_metrics()) {
    if (key == m.toggle.key) return m.toggle.def;
    if (m.image && key == m.image_toggle.key) return m.image_toggle.def;
  }
  FOVSIM_CHECK(false, "metrics: no per-frame metric declares the toggle \"" + key + "\"");
  return false;
}

std::vector<std::string> frame_metric_columns(const MetricsConfig& cfg) {
  std::vector<std::string> c;
  for (const FrameMetric& m : frame_metrics())
    if (cfg.on(m.toggle.key))
      for (auto& col : m.columns(cfg)) c.push_back(col);
  return c;
}

std::vector<std::pair<std::string, Image>> frame_metric_images(const MetricsConfig& cfg,
                                                               const MetricsScratch& scratch) {
  std::vector<std::pair<std::string, Image>> out;
  const std::vector<FrameMetric>& all = frame_metrics();
  for (size_t i = 0; i < all.size(); ++i) {
    const FrameMetric& m = all[i];
    if (!m.image || !cfg.on(m.toggle.key) || !cfg.on(m.image_toggle.key)) continue;
    if (i < scratch.per_metric.size() && scratch.per_metric[i])
      out.emplace_back(m.image_suffix, m.image(*scratch.per_metric[i]));
  }
  return out;
}

double frame_metrics_scratch_bytes(const MetricsConfig& cfg, double pixels) {
  bool copy = false;
  for (const FrameMetric& m : frame_metrics())
    copy = copy || (m.prepares_reference && cfg.on(m.toggle.key));
  double b = copy ? 12 * pixels : 0;  // the reference's pixels (RGB float)
  for (const FrameMetric& m : frame_metrics())
    if (m.scratch_bytes && cfg.on(m.toggle.key)) b += m.scratch_bytes(pixels);
  return b;
}

double frame_metrics_state_bytes(const MetricsConfig& cfg, double pixels) {
  double b = 0;
  for (const FrameMetric& m : frame_metrics())
    if (m.state_bytes && cfg.on(m.toggle.key)) b += m.state_bytes(pixels);
  return b;
}

MetricsConfig without_reference_only(const MetricsConfig& cfg) {
  MetricsConfig c = cfg;
  for (const FrameMetric& m : frame_metrics())
    if (m.reference_only) c.set(m.toggle.key, false);
  return c;
}

bool is_reference_only_column(const MetricsConfig& cfg, const std::string& column) {
  for (const FrameMetric& m : frame_metrics())
    if (m.reference_only)
      for (auto& c : m.columns(cfg))
        if (c == column) return true;
  return false;
}

}  // namespace fovsim
