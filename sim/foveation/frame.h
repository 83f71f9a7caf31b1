// Shared per-frame inputs (docs/architecture.md "Data flow of one frame"): camera, full-res
// G-buffer, reference shading and eccentricity, computed once per frame and shared by every method
// and sweep cell.
#pragma once
#include <optional>
#include <vector>

#include "sim/foveation/method.h"
#include "sim/trace/trace.h"

namespace fovsim {

struct FrameData {
  int frame = 0;
  double t = 0;
  Camera camera;
  std::optional<Camera> prev_camera;
  glm::dvec3 gaze_dir{0, 0, -1};
  glm::dvec2 gaze_px{0, 0};
  bool gaze_valid = true;
  GBuffer gbuffer;                  // channels: kShadingChannels | what the methods asked for
  Image reference;                  // linear RGB: direct + indirect from all VPLs (if any)
  Image direct;                     // direct light only; filled only when has_vpls
  bool has_vpls = false;            // the scene wants indirect light (Scene::wants_indirect)
  FrameVpls vpls;                   // the frame's VPL set (lighting.h), when has_vpls
  std::vector<float> eccentricity;  // degrees, W*H
  Counters counters;                // rays etc. of the reference pass

  FrameContext context(const Scene& scene, const Renderer& r, const Display& d, bool debug) const;
};

// What prepare_frame computes after the G-buffer and the VPL set, and what a reference cache
// keeps (sim/experiment/reference_cache.h): the reference, the 1-spp direct light (empty when
// prepare_frame leaves it empty), the indirect light of all VPLs at every pixel
// (FrameVpls::all_indirect; empty when not computed) and the frame's counters.
struct FrameReference {
  Image reference, direct, all_indirect;
  Counters counters;
};
// Copies those parts of a prepared frame.
FrameReference frame_reference_of(const FrameData& fd);

// Renders the shared data of one frame (with the scene's VPLs and their indirect light in the
// reference when the scene wants indirect light). `prev` is the previous frame's camera (or
// nullptr). The renderer's time must already be set to s.t.
// `cached` (optional): the frame's FrameReference from an earlier run with the same inputs;
// then only the G-buffer, the VPL set and the eccentricity map are computed and the rest is
// moved from it (it is left empty): the same FrameData, bit for bit
// (tests/experiment/reference_cache_test.cpp).
void prepare_frame(const Renderer& r, const Display& d, const TraceSample& s, int frame,
                   uint32_t channels, const Camera* prev, FrameData& out,
                   FrameReference* cached = nullptr);

// Gaze pixel of a head-space gaze direction (may be outside the screen; a direction behind
// the eye maps far outside, at +-1e6).
glm::dvec2 gaze_pixel(const Camera& cam, const glm::dvec3& gaze_dir);

}  // namespace fovsim
