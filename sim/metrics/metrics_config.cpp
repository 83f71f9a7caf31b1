// The metric config's keys (docs/metrics.md, configs/README.md): one row each in
// metrics_config_table(). The per-frame metrics' toggles are the rows their declarations give
// (frame_metric.h); any other key is one row here plus the MetricsConfig member it fills.
#include <cstdio>
#include <string>

#include "sim/core/param_table.h"
#include "sim/metrics/frame_metric.h"
#include "sim/metrics/metrics.h"

namespace fovsim {

const ParamTable<MetricsConfig>& metrics_config_table() {
  using C = MetricsConfig;
  static const auto t = [] {
    ParamTable<C> t;
    // One row per toggle a per-frame metric declares (frame_metric.h), in frame_metrics() order.
    auto toggle = [&t](const MetricToggle& g) {
      const std::string key = g.key;
      t.custom(
           g.key, ParamKind::Bool, Json(g.def), Range::any(),
           [key](C& c, const Json& v) { c.set(key, v.get<bool>()); },
           [key](const C& c) { return Json(c.on(key)); })
          .doc(g.source, g.doc);
    };
    for (const FrameMetric& m : frame_metrics()) {
      toggle(m.toggle);
      if (m.image) toggle(m.image_toggle);
    }
    t.boolean("fvvdp", true, &C::fvvdp)
        .doc("Mantiuk et al. 2021", "write `fvvdp_q`, `fvvdp_jod` (FovVideoVDP)")
        .boolean("fvvdp_foveated", true, &C::fvvdp_foveated)
        .doc("Mantiuk et al. 2021",
             "FovVideoVDP foveated around each frame's true gaze; `false`: non-foveated")
        .boolean("foveation_loss", true, &C::foveation_loss)
        .doc("",
             "also write every metric against `full` at the methods' sampling rate, "
             "`<metric>_fl`")
        .number("fovea_deg", 5.0, Range::above(0.0, 180.0), &C::fovea_deg)
        .doc("", "fovea radius in degrees of eccentricity (`rmse_fovea`)")
        .numbers("band_edges_deg", {0, 5, 10, 20, 30, 60}, Range::closed(0.0, 180.0),
                 &C::band_edges_deg)
        .doc("",
             "edges of the `rmse_ecc_<a>_<b>` bands, strictly increasing; `[]` = no "
             "bands; one edge is an error")
        .validate([](const C& c, Params& p) {
          if (c.band_edges_deg.size() == 1)
            p.fail("band_edges_deg", "needs at least 2 edges (or [] for no bands), got 1");
          for (size_t i = 1; i < c.band_edges_deg.size(); ++i)
            if (!(c.band_edges_deg[i] > c.band_edges_deg[i - 1]))
              p.fail("band_edges_deg[" + std::to_string(i) + "]",
                     "edges must be strictly increasing, got " +
                         std::to_string(c.band_edges_deg[i - 1]) + " then " +
                         std::to_string(c.band_edges_deg[i]));
        });
    return t;
  }();
  return t;
}

MetricsConfig MetricsConfig::from_params(Params& p) {
  return metrics_config_table().read(p);
}

static std::string short_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  std::string s(buf);
  for (char& ch : s)
    if (ch == '.') ch = 'p';
  return s;
}

std::string band_column(double a, double b) {
  return "rmse_ecc_" + short_number(a) + "_" + short_number(b);
}

std::string flip_band_column(double a, double b) {
  return "flip_ecc_" + short_number(a) + "_" + short_number(b);
}

}  // namespace fovsim
