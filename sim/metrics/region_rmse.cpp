// `regions` (frame_metric.h): RMSE over all channels of the pixels of a region, from the shared
// error sums (error_sums.h):
//   rmse_fovea       = sqrt(mean err^2 over ecc <  fovea_deg)
//   rmse_periphery   = sqrt(mean err^2 over ecc >= fovea_deg)
//   rmse_ecc_<a>_<b> = sqrt(mean err^2 over a <= ecc < b); NaN for an empty region.
#include <cmath>
#include <limits>

#include "sim/metrics/frame_metric.h"

namespace fovsim {

namespace {
double rms(double sq, double n) {
  return n > 0 ? std::sqrt(sq / n) : std::numeric_limits<double>::quiet_NaN();
}
}  // namespace

const FrameMetric& region_rmse_frame_metric() {
  static const FrameMetric m = [] {
    FrameMetric d;
    d.name = "regions";
    d.toggle = {"regions", true, "", "write `rmse_fovea`, `rmse_periphery`, `rmse_ecc_*`"};
    d.columns = [](const MetricsConfig& cfg) {
      std::vector<std::string> c{"rmse_fovea", "rmse_periphery"};
      for (size_t k = 0; k + 1 < cfg.band_edges_deg.size(); ++k)
        c.push_back(band_column(cfg.band_edges_deg[k], cfg.band_edges_deg[k + 1]));
      return c;
    };
    d.needs_ecc = true;
    d.sums = [](const MetricsConfig&, detail::ErrorSumsRequest& req) { req.regions = true; };
    d.compute = [](const FrameMetricArgs& a, MetricValues& out) {
      const detail::ErrorSums& s = a.sums;
      out.set("rmse_fovea", rms(s.fovea_sq, s.fovea_n));
      out.set("rmse_periphery", rms(s.periph_sq, s.periph_n));
      const std::vector<double>& e = a.cfg.band_edges_deg;
      for (size_t k = 0; k + 1 < e.size(); ++k)
        out.set(band_column(e[k], e[k + 1]), rms(s.band_sq[k], s.band_n[k]));
    };
    return d;
  }();
  return m;
}

}  // namespace fovsim
