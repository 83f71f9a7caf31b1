// compute_metrics: every enabled metric of one frame, by frames.csv column name (DESIGN §7-8).
// Region RMSEs (over all channels of the region's pixels):
//   rmse_fovea     = sqrt(mean err^2 over ecc <  fovea_deg)
//   rmse_periphery = sqrt(mean err^2 over ecc >= fovea_deg)
//   rmse_ecc_<a>_<b> = sqrt(mean err^2 over a <= ecc < b); NaN for an empty region.
#include <cmath>
#include <limits>

#include "sim/metrics/error_sums.h"
#include "sim/metrics/metrics.h"

namespace fovsim {

static double rms(double sq, double n) {
  return n > 0 ? std::sqrt(sq / n) : std::numeric_limits<double>::quiet_NaN();
}

Counters compute_metrics(const MetricsConfig& cfg, const Image& test, const Image& ref, const Camera& cam,
                         const std::vector<float>& ecc_deg, TemporalState* temporal) {
  const char* where = "metrics.compute_metrics";
  detail::check_same_size(test, ref, where);
  const bool need_ecc = cfg.fpsnr || cfg.regions || cfg.temporal;
  if (need_ecc) detail::check_ecc(test, ecc_deg, where);
  if (cfg.fpsnr) detail::check_cam(test, cam, where);

  Counters out;
  detail::ErrorSums s;
  if (cfg.psnr || cfg.fpsnr || cfg.regions) {
    detail::ErrorSumsRequest req;
    req.weighted = cfg.fpsnr;
    req.regions = cfg.regions;
    req.fovea_deg = cfg.fovea_deg;
    req.band_edges = &cfg.band_edges_deg;
    req.ecc = need_ecc ? &ecc_deg : nullptr;
    req.cam = &cam;
    req.ppd_scale = cfg.ppd_scale;
    s = detail::error_sums(test, ref, req);
  }
  if (cfg.psnr) out.set("psnr", detail::psnr_from_mse(s.sq / s.n));
  if (cfg.ssim) out.set("ssim", ssim(test, ref));
  if (cfg.fpsnr) out.set("fpsnr", detail::psnr_from_mse(s.w_sq / s.w));
  if (cfg.regions) {
    out.set("rmse_fovea", rms(s.fovea_sq, s.fovea_n));
    out.set("rmse_periphery", rms(s.periph_sq, s.periph_n));
    for (size_t k = 0; k + 1 < cfg.band_edges_deg.size(); ++k)
      out.set(band_column(cfg.band_edges_deg[k], cfg.band_edges_deg[k + 1]), rms(s.band_sq[k], s.band_n[k]));
  }
  if (cfg.temporal) {
    out.set("temporal_error", temporal ? temporal_error(test, ref, ecc_deg, cfg.fovea_deg, *temporal)
                                       : std::numeric_limits<double>::quiet_NaN());
  }
  return out;
}

}  // namespace fovsim
