// TWFR foveation culling (Franke et al. 2021 §6.1). See twfr_cull.h.
#include "sim/foveation/twfr_cull.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace fovsim {
namespace twfr {

RectKind screen_rect(const Camera& cam, const AABB& box, int& x0, int& y0, int& x1, int& y1) {
  x0 = 0;
  y0 = 0;
  x1 = cam.width - 1;
  y1 = cam.height - 1;
  if (box.empty()) return RectKind::Offscreen;
  if (!(std::isfinite(box.lo.x) && std::isfinite(box.lo.y) && std::isfinite(box.lo.z) &&
        std::isfinite(box.hi.x) && std::isfinite(box.hi.y) && std::isfinite(box.hi.z)))
    return RectKind::FullScreen;
  const glm::dquat inv = glm::conjugate(cam.orientation);
  glm::dvec3 h[8];
  int behind = 0;
  for (int c = 0; c < 8; ++c) {
    glm::dvec3 p((c & 1) ? box.hi.x : box.lo.x, (c & 2) ? box.hi.y : box.lo.y,
                 (c & 4) ? box.hi.z : box.lo.z);
    h[c] = inv * (p - cam.position);
    if (!(h[c].z < 0.0)) ++behind;
  }
  // Every visible point has head-space z < 0; a convex box with all corners at z >= 0 is unseen.
  if (behind == 8) return RectKind::Offscreen;
  // Straddling the eye plane (or touching it): projection unbounded, keep the whole screen.
  const double kNear = 1e-6;
  for (int c = 0; c < 8; ++c)
    if (!(h[c].z < -kNear)) return RectKind::FullScreen;
  // All corners in front: the projection of the box is the convex hull of the corners'.
  double lx = 1e300, ly = 1e300, hx = -1e300, hy = -1e300;
  for (int c = 0; c < 8; ++c) {
    glm::dvec2 px;
    cam.project_head(h[c], px);
    lx = std::min(lx, px.x);
    ly = std::min(ly, px.y);
    hx = std::max(hx, px.x);
    hy = std::max(hy, px.y);
  }
  // Pixel (i, j) has its centre at (i + 0.5, j + 0.5): it is in the hull only if
  // lx <= i + 0.5 <= hx. Half a pixel of margin absorbs rounding (float AABBs, double rays).
  const double m = 0.5;
  double fx0 = std::floor(lx - m), fy0 = std::floor(ly - m), fx1 = std::floor(hx + m),
         fy1 = std::floor(hy + m);
  if (fx1 < 0 || fy1 < 0 || fx0 > cam.width - 1 || fy0 > cam.height - 1) return RectKind::Offscreen;
  x0 = int(std::max(fx0, 0.0));
  y0 = int(std::max(fy0, 0.0));
  x1 = int(std::min(fx1, double(cam.width - 1)));
  y1 = int(std::min(fy1, double(cam.height - 1)));
  return RectKind::Rect;
}

CullStats cull_submodels(const Camera& cam, const OrMip& mip, size_t count,
                         const std::function<AABB(size_t)>& bounds,
                         const std::function<double(size_t)>& tri_count,
                         std::vector<uint8_t>& culled) {
  culled.assign(count, 0);
  std::vector<uint8_t> offscreen(count, 0);
  // One test per sub-model (a compute-shader invocation per sub-model in the seed, §6.1).
  tbb::parallel_for(size_t(0), count, [&](size_t s) {
    int x0, y0, x1, y1;
    RectKind k = screen_rect(cam, bounds(s), x0, y0, x1, y1);
    if (k == RectKind::Offscreen) {
      offscreen[s] = 1;
      culled[s] = 1;
    } else {
      culled[s] = mip.any(x0, y0, x1, y1) ? 0 : 1;
    }
  });
  CullStats st;
  st.submodels = count;
  for (size_t s = 0; s < count; ++s) {  // serial sum: deterministic
    const double t = tri_count(s);
    st.prims_total += t;
    if (offscreen[s]) {
      ++st.submodels_offscreen;
      st.prims_offscreen += t;
    } else if (culled[s]) {
      ++st.submodels_culled;
      st.prims_culled += t;
    } else {
      st.prims_submitted += t;
    }
  }
  return st;
}

}  // namespace twfr
}  // namespace fovsim
