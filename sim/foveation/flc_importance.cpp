// FLC importance map (Yang et al. 2021 §4.1, eqs. 3-9). See flc_importance.h.
#include "sim/foveation/flc_importance.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace fovsim {

double flc_acuity(double dist_px, double half_diag_px, double tan_half_fov_diag,
                  const FlcImportanceParams& p, double ecc_rad) {
  // eq. 5: m(r, alpha) = atan(sqrt(r) tan(alpha/2)), sqrt(r) = fovea_frac.
  const double m = std::atan(p.fovea_frac * tan_half_fov_diag);
  double e = ecc_rad;
  if (e < 0.0) {
    // eq. 6: k = |c_p - c_g| / |d|, e = atan(k tan(alpha/2)).
    const double k = dist_px / std::max(half_diag_px, 1e-9);
    e = std::atan(k * tan_half_fov_diag);
  }
  const double h = 1.0 + p.slope * (m - e);  // eq. 4
  return std::clamp(h, p.omega_p, 1.0);      // eq. 3
}

double flc_color_difference(const float* c, const float* cn) {
  // eq. 7, with r-bar = c.r - c^.r as the seed writes it (a variant of the "redmean" metric).
  const double rbar = double(c[0]) - double(cn[0]);
  const double dr = 256.0 * (double(c[0]) - double(cn[0]));
  const double dg = 256.0 * (double(c[1]) - double(cn[1]));
  const double db = 256.0 * (double(c[2]) - double(cn[2]));
  return std::sqrt(std::max(0.0, (2.0 + rbar) * dr * dr + 4.0 * dg * dg + (3.0 - rbar) * db * db));
}

void flc_importance_map(const GBuffer& g, const Image& color, const Image* history,
                        const glm::dvec2& gaze_px, double tan_half_fov_diag,
                        const std::vector<float>* ecc_deg, const FlcImportanceParams& p,
                        FlcImportanceMaps& out, bool keep_parts) {
  const int W = g.width, H = g.height;
  out.importance.resize(W, H, 1);
  if (keep_parts) {
    out.acuity.resize(W, H, 1);
    out.silhouette.resize(W, H, 1);
    out.brightness.resize(W, H, 1);
  }
  const double half_diag = 0.5 * std::sqrt(double(W) * W + double(H) * H);
  const bool have_color = color.width == W && color.height == H && color.channels >= 3;
  const bool have_hist =
      history && history->width == W && history->height == H && history->channels == 1;
  const bool use_ecc = p.exact_eccentricity && ecc_deg && ecc_deg->size() == g.size();
  const bool have_normal = g.has(kNormal);
  const double cos_thr = std::cos(deg2rad(p.normal_threshold_deg));
  tbb::parallel_for(0, H, [&](int y) {
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * size_t(W) + size_t(x);
      if (!g.hit(i)) {
        out.importance.data[i] = 0.f;
        if (keep_parts) out.acuity.data[i] = out.silhouette.data[i] = out.brightness.data[i] = 0.f;
        continue;
      }
      const double dx = x + 0.5 - gaze_px.x, dy = y + 0.5 - gaze_px.y;
      const double ecc = use_ecc ? deg2rad(double((*ecc_deg)[i])) : -1.0;
      const double pa =
          flc_acuity(std::sqrt(dx * dx + dy * dy), half_diag, tan_half_fov_diag, p, ecc);
      // §4.1.2: silhouette from depth gradient, normal angle and colour difference (eq. 7).
      bool sil = false;
      const int nbx[4] = {x - 1, x + 1, x, x};
      const int nby[4] = {y, y, y - 1, y + 1};
      const float z = g.depth[i];
      for (int k = 0; k < 4 && !sil; ++k) {
        if (nbx[k] < 0 || nby[k] < 0 || nbx[k] >= W || nby[k] >= H) continue;
        const size_t j = size_t(nby[k]) * size_t(W) + size_t(nbx[k]);
        const float zn = g.depth[j];
        if (!(std::fabs(zn - z) <= float(p.depth_threshold) * z))
          sil = true;  // also misses (inf)
        else if (have_normal && double(glm::dot(g.normal[i], g.normal[j])) < cos_thr)
          sil = true;
        else if (have_color &&
                 flc_color_difference(color.at(x, y), color.at(nbx[k], nby[k])) > p.color_threshold)
          sil = true;
      }
      const double pg = sil ? p.silhouette_value : 0.0;
      // eq. 8: p_b = min(1, delta * b(p)), b = tone-mapped indirect brightness of history.
      const double pb =
          have_hist ? std::min(1.0, p.delta * std::max(0.0, double(history->data[i]))) : 1.0;
      const double imp = std::max(pa, pg) * pb;  // eq. 9
      out.importance.data[i] = float(imp);
      if (keep_parts) {
        out.acuity.data[i] = float(pa);
        out.silhouette.data[i] = float(pg);
        out.brightness.data[i] = float(pb);
      }
    }
  });
}

}  // namespace fovsim
