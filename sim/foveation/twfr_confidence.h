// TWFR confidence function and redraw map (Franke et al. 2021 §5.2, §7) and the OR-mipmap of the
// redraw map used for foveation culling (§6.1).
//
// Threshold convention (documented in docs/methods.md "## twfr"): a pixel is redrawn iff
// c <= epsilon, or it is forced (uncovered by reprojection and hole filling, inside the
// discarded fovea, or transparent). §8.1: "confidence is computed on a scale from zero (must be
// redrawn) to one (good to display)"; with epsilon = 0 only c = 0 pixels (the fovea, where
// c_e = 0) and forced ones are redrawn, with epsilon = 1 every pixel is redrawn every frame.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "sim/core/math.h"
#include "sim/foveation/twfr_pushpull.h"  // kUncovered

namespace fovsim {
namespace twfr {

inline float smoothstep01(float x) {  // S_1 (§5.2)
  x = clamp01(x);
  return x * x * (3.f - 2.f * x);
}

// c_e(phi) = S_1((phi - phi_F) / (phi_0 - phi_F))  (§5.2). For phi_0 == phi_F the smooth step
// degenerates to a step: 0 for phi <= phi_F, 1 beyond.
inline float eccentricity_confidence(float phi, float phi_f, float phi_0) {
  if (!(phi_0 > phi_f)) return phi > phi_f ? 1.f : 0.f;
  return smoothstep01((phi - phi_f) / (phi_0 - phi_f));
}

struct ConfidenceParams {
  float epsilon = 0.2f;  // redraw iff c <= epsilon (§5.2, §8.1)
  float phi_f = 10.f;    // degrees (§5.2)
  float phi_0 = 30.f;    // degrees (§5.2)
  float A = 0.6f;        // hole-size confidence base, c_s(m) = A^m (§5.2)
  float D = 0.75f;       // dynamic confidence base, c_d(t) = D^t (§7)
  // Scale invariance (docs/fidelity.md "Scale invariance of the methods"): m counts mip levels of
  // display pixels (§5.2). At render.scale s a simulated level-m texel is a display level
  // m + log2(1 / s) texel, so c_s = A^max(0, m + level_offset) with level_offset = -log2(s)
  // (0 at s = 1).
  float level_offset = 0.f;
};

// Why a pixel is in the redraw map (bit flags, for debugging and counters).
enum RedrawReason : uint8_t {
  kRedrawConfidence = 1,  // c <= epsilon
  kRedrawUncovered = 2,   // no data (nothing reprojected, push-pull found nothing)
  kRedrawFovea = 4,       // fovea: reprojected splats were discarded there (§4)
  kRedrawForced = 8,      // transparent surface (§8.5: rendered in a pass after the pipeline)
};

// Per-pixel inputs of the confidence function.
struct ConfidenceInputs {
  const float* eccentricity = nullptr;  // degrees
  const uint8_t* hole_level = nullptr;  // 0 reprojected, m >= 1 filled at level m, 255 uncovered
  const float* contrast = nullptr;      // c_c (1 for reprojected pixels)
  const uint8_t* dynamic = nullptr;  // 1 where the reprojected sample belongs to a dynamic object
  const uint16_t* age = nullptr;     // frames since last redraw (reprojected samples)
  const uint8_t* fovea = nullptr;    // 1 where splats were discarded (ecc < phi_F)
  const uint8_t* forced = nullptr;   // optional: 1 forces a redraw (transparency)
};

struct ConfidenceStats {
  size_t redrawn = 0, by_confidence = 0, uncovered = 0, fovea = 0, forced = 0, dynamic = 0;
};

// c = c_e * c_c * c_s * c_d (§5.2, §7); writes confidence (0 where uncovered) and the redraw
// map (reason bits, 0 = keep). Parallel over rows; W*H entries.
ConfidenceStats compute_redraw_map(const ConfidenceInputs& in, const ConfidenceParams& p, int W,
                                   int H, std::vector<float>& confidence,
                                   std::vector<uint8_t>& redraw);

// OR-mipmap of a binary map (§6.1): level 0 = map != 0, level k+1 texel = OR of its children.
struct OrMip {
  std::vector<int> w, h;
  std::vector<std::vector<uint8_t>> level;
  void build(const std::vector<uint8_t>& map, int W, int H);
  // Any marked pixel in the inclusive pixel rectangle [x0, x1] x [y0, y1] (clipped to the
  // screen)? Queries the level where the rectangle spans at most 2x2 texels: four lookups.
  bool any(int x0, int y0, int x1, int y1) const;
};

}  // namespace twfr
}  // namespace fovsim
