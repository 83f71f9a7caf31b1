// TWFR foveation culling (Franke et al. 2021 §6.1): a sub-model (<= ~500 faces) is culled when the
// screen-space rectangle of its world AABB covers no pixel of the redraw map, queried on the
// OR-mipmap at the level matching the rectangle (four texel lookups).
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "sim/core/math.h"
#include "sim/display/display.h"
#include "sim/foveation/twfr_confidence.h"

namespace fovsim {
namespace twfr {

enum class RectKind { Offscreen, Rect, FullScreen };

// Conservative inclusive pixel rectangle covered by a world AABB seen from `cam`. A pixel whose
// centre ray hits a point of the box lies inside the rectangle. Offscreen: no pixel can see the
// box (all of it behind the eye or outside the view). FullScreen: the box straddles the eye
// plane (rectangle = whole screen).
RectKind screen_rect(const Camera& cam, const AABB& box, int& x0, int& y0, int& x1, int& y1);

struct CullStats {
  size_t submodels = 0, submodels_culled = 0, submodels_offscreen = 0;
  double prims_total = 0, prims_offscreen = 0, prims_culled = 0, prims_submitted = 0;
};

// culled[s] = 1 for sub-models not drawn in the redraw pass (offscreen or foveation-culled).
// bounds(s) gives the world AABB of sub-model s now; tri_count(s) its triangle count.
CullStats cull_submodels(const Camera& cam, const OrMip& redraw_mip, size_t count,
                         const std::function<AABB(size_t)>& bounds,
                         const std::function<double(size_t)>& tri_count,
                         std::vector<uint8_t>& culled);

}  // namespace twfr
}  // namespace fovsim
