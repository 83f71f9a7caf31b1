#include "sim/foveation/frame.h"

#include <algorithm>
#include <utility>

namespace fovsim {

glm::dvec2 gaze_pixel(const Camera& cam, const glm::dvec3& gaze_dir) {
  glm::dvec2 px;
  if (!cam.project_head(glm::normalize(gaze_dir), px)) {
    // Behind the eye: push far outside in the direction of the gaze, keeping it finite.
    px = glm::dvec2(gaze_dir.x >= 0 ? 1e6 : -1e6, gaze_dir.y >= 0 ? -1e6 : 1e6);
  }
  px = glm::clamp(px, glm::dvec2(-1e6), glm::dvec2(1e6));
  return px;
}

FrameReference frame_reference_of(const FrameData& fd) {
  FrameReference f;
  f.reference = fd.reference;
  f.direct = fd.direct;
  if (fd.has_vpls && fd.vpls.all_indirect_of == &fd.gbuffer) f.all_indirect = fd.vpls.all_indirect;
  f.counters = fd.counters;
  return f;
}

void prepare_frame(const Renderer& r, const Display& d, const TraceSample& s, int frame,
                   uint32_t channels, const Camera* prev, FrameData& out, FrameReference* cached) {
  out.frame = frame;
  out.t = s.t;
  out.camera = Camera::from_pose(d, s.head_pos, s.head_rot);
  if (prev)
    out.prev_camera = *prev;
  else
    out.prev_camera.reset();
  out.gaze_dir = glm::normalize(s.gaze_dir);
  out.gaze_valid = s.valid;
  out.gaze_px = gaze_pixel(out.camera, out.gaze_dir);
  out.counters.clear();
  r.trace_gbuffer(out.camera, channels | kShadingChannels, out.gbuffer, &out.counters, prev);
  out.has_vpls = r.scene().wants_indirect;
  const bool supersampled = r.settings().spp > 1;
  if (cached) {
    // The VPL set is rebuilt (the methods' strategies select from it; cheap next to shading
    // all of it at every pixel, which `cached` holds).
    std::swap(out.reference, cached->reference);
    std::swap(out.direct, cached->direct);
    if (out.has_vpls) {
      build_frame_vpls(r, out.vpls, nullptr);
      if (!cached->all_indirect.data.empty()) {
        std::swap(out.vpls.all_indirect, cached->all_indirect);
        out.vpls.all_indirect_of = &out.gbuffer;
      } else {
        out.vpls.all_indirect = Image();
        out.vpls.all_indirect_of = nullptr;
      }
    }
    std::swap(out.counters,
              cached->counters);  // those of the pass that computed it (the same passes)
  } else if (!out.has_vpls && !supersampled) {
    r.shade(out.gbuffer, out.camera.position, out.reference, nullptr, &out.counters);
  } else {
    // `direct`: one sample per pixel centre, what every full-sampling method starts from.
    r.shade(out.gbuffer, out.camera.position, out.direct, nullptr, &out.counters);
    if (supersampled) {
      r.render_reference(out.camera, out.gbuffer, out.reference, &out.counters);  // render.spp
    } else {
      out.reference.resize(out.direct.width, out.direct.height, 3);
      std::copy(out.direct.data.begin(), out.direct.data.end(), out.reference.data.begin());
    }
    if (out.has_vpls) {
      // One VPL set per frame; reference = direct + indirect from all VPLs (the FLC paper's
      // TBDS ground truth, §7), added by the same loop the methods' strategies use. The
      // indirect term is evaluated at pixel centres, not per sub-sample: one-bounce light from
      // VPLs is smooth, and 16x the VPL shading would dominate the run (docs/metrics.md).
      build_frame_vpls(r, out.vpls, &out.counters);
      out.counters.set(Counter::vpls_total, double(out.vpls.vpls.size()));
      if (cache_all_indirect(out.gbuffer, &r, out.vpls))  // kept for the all_vpls methods
        add_cached_indirect(out.gbuffer, out.vpls, nullptr, out.reference, &out.counters);
      else
        add_indirect(out.gbuffer, out.vpls.all, out.vpls.shading, &r, nullptr, out.reference,
                     &out.counters);
    }
  }
  eccentricity_map(out.camera, out.gaze_dir, out.eccentricity);  // reuses the previous frame's
}

FrameContext FrameData::context(const Scene& scene, const Renderer& r, const Display& d,
                                bool debug) const {
  FrameContext c;
  c.frame = frame;
  c.t = t;
  c.scene = &scene;
  c.renderer = &r;
  c.display = &d;
  c.camera = &camera;
  c.prev_camera = prev_camera ? &*prev_camera : nullptr;
  c.gaze_dir = gaze_dir;
  c.gaze_px = gaze_px;
  c.gaze_valid = gaze_valid;
  c.gbuffer = &gbuffer;
  c.reference = &reference;
  c.direct = direct.data.empty() ? &reference : &direct;  // 1 spp, direct light only
  c.vpls = has_vpls ? &vpls : nullptr;
  c.eccentricity = &eccentricity;
  c.want_debug = debug;
  return c;
}

}  // namespace fovsim
