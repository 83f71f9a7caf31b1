// MetricsConfig::from_params. Keys (docs/metrics.md):
// | key            | type     | default              | valid range                    |
// |----------------|----------|----------------------|--------------------------------|
// | psnr           | bool     | true                 |                                |
// | ssim           | bool     | true                 |                                |
// | fpsnr          | bool     | true                 |                                |
// | regions        | bool     | true                 | rmse_fovea/periphery + bands   |
// | temporal       | bool     | true                 | temporal_error                 |
// | flip           | bool     | true                 | flip (+ flip_ecc_* bands)      |
// | fvvdp          | bool     | true                 | fvvdp_q, fvvdp_jod             |
// | fvvdp_foveated | bool     | true                 | foveated around the true gaze  |
// | foveation_loss | bool     | true                 | <metric>_fl vs full at 1 spp   |
// | fovea_deg      | number   | 5                    | (0, 180]                       |
// | band_edges_deg | number[] | [0,5,10,20,30,60]    | [0, 180], strictly increasing, |
// |                |          |                      | empty (no bands) or >= 2 edges |
#include <cstdio>
#include <string>

#include "sim/metrics/metrics.h"

namespace fovsim {

MetricsConfig MetricsConfig::from_params(Params& p) {
  MetricsConfig c;
  c.psnr = p.boolean("psnr", c.psnr);
  c.ssim = p.boolean("ssim", c.ssim);
  c.fpsnr = p.boolean("fpsnr", c.fpsnr);
  c.regions = p.boolean("regions", c.regions);
  c.temporal = p.boolean("temporal", c.temporal);
  c.flip = p.boolean("flip", c.flip);
  c.fvvdp = p.boolean("fvvdp", c.fvvdp);
  c.fvvdp_foveated = p.boolean("fvvdp_foveated", c.fvvdp_foveated);
  c.foveation_loss = p.boolean("foveation_loss", c.foveation_loss);
  c.fovea_deg = p.number("fovea_deg", c.fovea_deg, Range::above(0.0, 180.0));
  c.band_edges_deg = p.numbers("band_edges_deg", c.band_edges_deg, Range::closed(0.0, 180.0));
  if (c.band_edges_deg.size() == 1)
    p.fail("band_edges_deg", "needs at least 2 edges (or [] for no bands), got 1");
  for (size_t i = 1; i < c.band_edges_deg.size(); ++i)
    if (!(c.band_edges_deg[i] > c.band_edges_deg[i - 1]))
      p.fail("band_edges_deg[" + std::to_string(i) + "]",
             "edges must be strictly increasing, got " + std::to_string(c.band_edges_deg[i - 1]) +
                 " then " + std::to_string(c.band_edges_deg[i]));
  return c;
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
