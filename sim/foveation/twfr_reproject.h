// TWFR forward reprojection (Franke et al. 2021 §4, §7): one pixel-sized splat per source pixel,
// carrying colour and the exact world position (not a depth-buffer reconstruction, Fig. 3),
// depth-tested into the new view. Splats landing in the new fovea are discarded (§4, last
// paragraph); pixels that were hole-filled carry no position and are never reprojected again (§4).
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "sim/core/image.h"
#include "sim/core/math.h"
#include "sim/display/display.h"

namespace fovsim {
namespace twfr {

// What a pixel of the composed frame carries into the next frame (§4: colour + world position;
// §7: object id in the position buffer's W; age = frames since the pixel was last redrawn).
enum SampleKind : uint8_t {
  kNoSample = 0,  // hole-filled (or nothing): never reprojected
  kSurface = 1,   // pos = world-space hit point
  kSky = 2,       // pos = unit world direction of a primary-ray miss (a point at infinity)
};
struct Sample {
  glm::vec3 pos{0.f};
  int32_t object = -1;  // scene object index, -1 for sky / none
  uint16_t age = 0;     // frames since last redraw (saturating), for c_d (§7)
  uint8_t kind = kNoSample;
};

struct ReprojectStats {
  size_t splats = 0;           // source pixels that carried a position
  size_t offscreen = 0;        // splats outside the new view (or behind the eye)
  size_t fovea_discarded = 0;  // splats landing where ecc < fovea_deg (§4)
  size_t landed = 0;           // target pixels that received a (depth-test winning) splat
};

// Scratch z-buffer for the depth test: atomic min over (depth bits << 32 | source index), so
// the winner does not depend on thread scheduling (deterministic at any thread count).
struct SplatBuffer {
  std::unique_ptr<std::atomic<uint64_t>[]> key;
  size_t size = 0;
  void resize(size_t n);
};

struct ReprojectInput {
  const Image* color = nullptr;                  // previous composed colour, W x H x 3 (linear)
  const std::vector<Sample>* samples = nullptr;  // previous per-pixel samples, W*H
  // Per scene object: world(t) * inverse(world(t_prev)) (§7: sprites move with their object).
  // Empty, or identity entries, for static objects.
  const std::vector<glm::mat4>* object_motion = nullptr;
  const std::vector<uint8_t>* object_dynamic = nullptr;  // per object, 1 = apply object_motion
  const Camera* camera = nullptr;                        // new view
  const std::vector<float>* eccentricity = nullptr;      // new frame, degrees, W*H
  float fovea_deg = 10.f;  // discard splats landing at ecc < fovea_deg
};

// Writes the reprojected colour (W x H x 3, 0 where nothing landed), the reprojected samples
// (age + 1, positions moved with their object) and covered[i] = 1 where a splat landed.
ReprojectStats forward_reproject(const ReprojectInput& in, Image& color,
                                 std::vector<Sample>& samples, std::vector<uint8_t>& covered,
                                 SplatBuffer& scratch);

}  // namespace twfr
}  // namespace fovsim
