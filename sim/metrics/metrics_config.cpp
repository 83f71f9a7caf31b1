// The metric config's keys (docs/metrics.md, configs/README.md): one row each in
// metrics_config_table(). A new key is one row there plus the MetricsConfig member it fills.
#include <cstdio>
#include <string>

#include "sim/core/param_table.h"
#include "sim/metrics/metrics.h"

namespace fovsim {

const ParamTable<MetricsConfig>& metrics_config_table() {
  using C = MetricsConfig;
  static const auto t =
      ParamTable<C>()
          .boolean("psnr", true, &C::psnr)
          .doc("", "write `psnr`")
          .boolean("ssim", true, &C::ssim)
          .doc("Wang et al. 2004", "write `ssim` (image must be at least 11x11)")
          .boolean("fpsnr", true, &C::fpsnr)
          .doc("Lee, Pattichis, Bovik 2002", "write `fpsnr` (foveated PSNR)")
          .boolean("regions", true, &C::regions)
          .doc("", "write `rmse_fovea`, `rmse_periphery`, `rmse_ecc_*`")
          .boolean("temporal", true, &C::temporal)
          .doc("", "write `temporal_error`")
          .boolean("flip", true, &C::flip)
          .doc("Andersson et al. 2020", "write `flip`, with `regions` also `flip_ecc_*`")
          .boolean("flip_images", true, &C::flip_images)
          .doc("", "with `flip`: write `<label>_flip.png` (the FLIP error map) for image frames")
          .boolean("fvvdp", true, &C::fvvdp)
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
