// compute_metrics: every enabled metric of one frame, by frames.csv column name
// (docs/architecture.md §7-8). Region RMSEs (over all channels of the region's pixels):
//   rmse_fovea     = sqrt(mean err^2 over ecc <  fovea_deg)
//   rmse_periphery = sqrt(mean err^2 over ecc >= fovea_deg)
//   rmse_ecc_<a>_<b> = sqrt(mean err^2 over a <= ecc < b); NaN for an empty region.
//   flip = mean of the LDR-FLIP map (flip.cpp) at flip_ppd(cam);
//   flip_ecc_<a>_<b> = mean FLIP error over a <= ecc < b; NaN for an empty region.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "sim/core/error.h"
#include "sim/metrics/error_sums.h"
#include "sim/metrics/metrics.h"

namespace fovsim {

static double rms(double sq, double n) {
  return n > 0 ? std::sqrt(sq / n) : std::numeric_limits<double>::quiet_NaN();
}

static bool in_unit_range(const Image& im) {
  for (float v : im.data)
    if (!(v >= 0.f && v <= 1.f)) return false;  // NaN too
  return true;
}

MetricValues compute_metrics(const MetricsConfig& cfg, const Image& test, const Image& ref,
                             const Camera& cam, const std::vector<float>& ecc_deg,
                             TemporalState* temporal, MetricsScratch* scratch,
                             const FlipPrepared* test_flip) {
  const char* where = "metrics.compute_metrics";
  detail::check_same_size(test, ref, where);
  const bool need_ecc = cfg.fpsnr || cfg.regions || cfg.temporal;
  if (cfg.flip) detail::check_cam(test, cam, where);
  if (need_ecc) detail::check_ecc(test, ecc_deg, where);
  if (cfg.fpsnr) detail::check_cam(test, cam, where);

  // The reference's FLIP and SSIM preparations are reused while its pixels are unchanged.
  MetricsScratch local;
  MetricsScratch& sc = scratch ? *scratch : local;
  sc.flip_test_valid = false;
  if (cfg.ssim || cfg.flip) {
    const Image& rp = sc.ref_pixels;
    if (rp.width != ref.width || rp.height != ref.height || rp.channels != ref.channels ||
        rp.data != ref.data) {
      sc.flip_ref.ppd = 0;  // stale (a prepared ppd is > 0)
      sc.ssim_ref.width = 0;
      if (scratch) sc.ref_pixels = ref;
    }
  }
  const bool identical = test.data == ref.data;  // sizes are equal (checked above)

  MetricValues out;
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
  if (cfg.ssim) {
    double v;
    if (identical && test.channels != 2 && test.width >= 11 && test.height >= 11 &&
        in_unit_range(test)) {
      // Identical images (the `full` method of every run): with mu_x = mu_y, sigma_x^2 = sigma_y^2
      // = sigma_xy bit for bit, 2 mu_x mu_y and mu_x^2 + mu_y^2 are the same doubling of one
      // rounded product, so every pixel's numerator and denominator are equal and nonzero (C1
      // and C2 dominate any rounding for values in [0,1]): each ratio is exactly 1, and so is
      // their mean (metrics_kernels_test checks it against the full computation).
      v = 1.0;
    } else {
      if (sc.ssim_ref.width == 0) ssim_prepare(ref, sc.ssim_ref);
      v = ssim(test, sc.ssim_ref);
    }
    out.set("ssim", v);
  }
  if (cfg.fpsnr) out.set("fpsnr", detail::psnr_from_mse(s.w_sq / s.w));
  if (cfg.regions) {
    out.set("rmse_fovea", rms(s.fovea_sq, s.fovea_n));
    out.set("rmse_periphery", rms(s.periph_sq, s.periph_n));
    for (size_t k = 0; k + 1 < cfg.band_edges_deg.size(); ++k)
      out.set(band_column(cfg.band_edges_deg[k], cfg.band_edges_deg[k + 1]),
              rms(s.band_sq[k], s.band_n[k]));
  }
  if (cfg.flip) {
    const double ppd = flip_ppd(cam);
    if (sc.flip_ref.ppd != ppd) flip_prepare(ref, ppd, sc.flip_ref, &sc.flip_workspace);
    const Image& map = sc.flip_map;
    if (identical) {
      // Identical images: every FLIP term is a difference of equal values, so E = 0 exactly
      // (FLIP.md §10.1); skip the work (the `full` method of every run).
      sc.flip_map.resize(test.width, test.height, 1, 0.f);
      out.set("flip", 0.0);
    } else if (test_flip) {
      FOVSIM_CHECK(test_flip->ppd == ppd,
                   "compute_metrics: the given test FLIP preparation is at " +
                       std::to_string(test_flip->ppd) + " ppd, not " + std::to_string(ppd));
      out.set("flip", flip(sc.flip_ref, *test_flip, &sc.flip_map));
    } else {
      flip_prepare(test, ppd, sc.flip_test, &sc.flip_workspace);
      sc.flip_test_valid = true;
      out.set("flip", flip(sc.flip_ref, sc.flip_test, &sc.flip_map));
    }
    const size_t nb = cfg.band_edges_deg.size() >= 2 ? cfg.band_edges_deg.size() - 1 : 0;
    if (cfg.regions && nb > 0) {
      // Serial pass in pixel order (deterministic); the map is one float per pixel.
      std::vector<double> sum(nb, 0.0), n(nb, 0.0);
      const double* edges = cfg.band_edges_deg.data();
      for (size_t i = 0; i < map.pixels(); ++i) {
        const double e = ecc_deg[i];
        if (e < edges[0] || !(e < edges[nb])) continue;
        const size_t k = size_t(std::upper_bound(edges, edges + nb + 1, e) - edges) - 1;
        sum[k] += map.data[i];
        n[k] += 1;
      }
      for (size_t k = 0; k < nb; ++k)
        out.set(flip_band_column(edges[k], edges[k + 1]),
                n[k] > 0 ? sum[k] / n[k] : std::numeric_limits<double>::quiet_NaN());
    }
  }
  if (cfg.temporal) {
    out.set("temporal_error", temporal
                                  ? temporal_error(test, ref, ecc_deg, cfg.fovea_deg, *temporal)
                                  : std::numeric_limits<double>::quiet_NaN());
  }
  return out;
}

}  // namespace fovsim
