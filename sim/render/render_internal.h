// Private to sim/render: the renderer's shared state (Renderer::Impl) and the helpers that
// more than one of its files needs. Not part of the library interface.
//   renderer.cpp      Embree scene setup, instancing, set_time, sub-model bounds
//   render_trace.cpp  primary rays: packet G-buffer tracing, trace_points, intersect
//   render_shade.cpp  shading: light terms, shadow rays (occlusion filter), shade()
//   tonemap.cpp       tone mapping + display encoding (tonemap.h)
#pragma once
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "sim/core/error.h"
#include "sim/render/renderer.h"

namespace fovsim {

constexpr float kInf = std::numeric_limits<float>::infinity();

inline glm::vec3 xform_point(const glm::mat4& m, const glm::vec3& p) {
  return glm::vec3(m * glm::vec4(p, 1.f));
}

// Light state at the current time.
struct LightNow {
  Light::Type type;
  glm::vec3 pos, dir, radiance;  // radiance = color * intensity
  float cos_inner, cos_outer;
  bool shadows;
};

// Renderer state (a plain struct so the file's helpers can use it; Impl derives from it).
struct RenderState {
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  RTCScene static_scene = nullptr;  // == top when there are no dynamic objects
  unsigned static_inst = RTC_INVALID_GEOMETRY_ID;
  std::vector<int> static_geom_object;  // geomID in static_scene -> object
  std::vector<int> inst_object;         // geomID in top (instances) -> object, -1 = static
  std::vector<RTCScene> child_scenes;
  std::vector<unsigned> dyn_geom;  // object -> instance geomID in top (or invalid)

  // Per object: shading data.
  struct Obj {
    std::vector<glm::vec3> pos;  // world space (static) or object space (dynamic), +1 pad
    std::vector<glm::vec3> nrm;  // world/object space vertex normals (may be empty)
    glm::mat4 xf{1.f}, inv{1.f}, prev_xf{1.f};
    glm::mat3 nxf{1.f};  // normal matrix of xf
    bool dynamic = false;
    std::vector<int32_t> tri_sub;  // primitive -> sub-model index
  };
  std::vector<Obj> objs;
  // Geometry user data (Embree filters): the object, and where the renderer's state is.
  struct GeomUser {
    const RenderState* I = nullptr;
    const Scene* scene = nullptr;
    int object = -1;
    bool cutout = false;  // some triangle has a cut-out material (alpha_filter is attached)
  };
  std::vector<GeomUser> geom_user;  // per object; sized before any geometry is attached
  std::vector<LightNow> lights;
  std::vector<glm::vec2> mat_cs;  // cos, sin of each material's texture angle
  float scene_scale = 1.f;        // for ray offsets
  // Context flags for 16-wide packets (primary and shadow rays). See packet_flags() below.
  RTCIntersectContextFlags packet_flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;

  void check(const char* what) {
    RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE)
      throw Error("embree",
                  std::string(what) + " failed (RTCError " + std::to_string(int(e)) + ")");
  }

  ~RenderState() {
    for (RTCScene s : child_scenes) rtcReleaseScene(s);
    if (static_scene && static_scene != top) rtcReleaseScene(static_scene);
    if (top) rtcReleaseScene(top);
    if (device) rtcReleaseDevice(device);
  }
};

struct Renderer::Impl : RenderState {};

// Embree filter for shadow rays (render_shade.cpp); set on every geometry by renderer.cpp.
void occlusion_filter(const RTCFilterFunctionNArguments* args);
// Embree intersect filter of geometries with cut-out materials (render_trace.cpp): rejects hits
// whose material alpha is below its cutoff, so primary rays, RSM rays and shadow rays
// (occlusion_filter asks the same) all see through the cut-out parts.
void alpha_filter(const RTCFilterFunctionNArguments* args);
bool alpha_rejects(const RenderState& I, const Scene& scene, int obj, uint32_t prim, float u,
                   float v);

inline int hit_object(const RenderState& I, const RTCHit& h) {
  if (h.geomID == RTC_INVALID_GEOMETRY_ID) return -1;
  unsigned inst = h.instID[0];
  if (inst == RTC_INVALID_GEOMETRY_ID) return I.static_geom_object[h.geomID];
  int o = I.inst_object[inst];
  return o >= 0 ? o : I.static_geom_object[h.geomID];
}

// Fills every requested channel of sample `i` from a hit (or a miss when obj < 0).
// `px` is the sample's screen point (for motion).
// Embree decides which triangle a ray hits; the t, u, v it reports come from ISA-specific
// kernels (FMA on its AVX2/AVX-512 paths, none on SSE/AVX; other evaluation orders) and differ
// in the last bits between CPUs, which moved reference pixels and every later number. Recompute
// them from the same triangle in double precision (Moller-Trumbore; the base build has no FMA,
// so the operations are the same IEEE ones on every x86-64 CPU): every G-buffer channel then
// depends only on which triangle was hit. Dynamic objects: the ray goes to object space (the
// affine map keeps the ray parameter t). A degenerate determinant keeps Embree's values.
inline void refine_hit(const RenderState& I, const Scene& scene, int obj, uint32_t prim,
                       const glm::vec3& org, const glm::vec3& dir, float& t, float& u, float& v) {
  const RenderState::Obj& ob = I.objs[size_t(obj)];
  const glm::uvec3 tri = scene.meshes[size_t(scene.objects[size_t(obj)].mesh)].triangles[prim];
  glm::dvec3 o(org), d(dir);
  if (ob.dynamic) {
    const glm::dmat4 inv(ob.inv);
    o = glm::dvec3(inv * glm::dvec4(o, 1.0));
    d = glm::dmat3(inv) * d;
  }
  const glm::dvec3 p0(ob.pos[tri.x]), e1 = glm::dvec3(ob.pos[tri.y]) - p0,
                                      e2 = glm::dvec3(ob.pos[tri.z]) - p0;
  const glm::dvec3 pv = glm::cross(d, e2);
  const double det = glm::dot(e1, pv);
  if (!(std::fabs(det) > 1e-300)) return;
  const double inv_det = 1.0 / det;
  const glm::dvec3 tv = o - p0, qv = glm::cross(tv, e1);
  // Clamped into the triangle: Embree found the hit inside it (watertight test), a last-bit
  // difference must not push an interpolation outside.
  const double uu = std::clamp(glm::dot(tv, pv) * inv_det, 0.0, 1.0);
  const double vv = std::clamp(glm::dot(d, qv) * inv_det, 0.0, 1.0 - uu);
  const double tt = glm::dot(e2, qv) * inv_det;
  if (!(tt >= 0.0) || !std::isfinite(tt)) return;
  t = float(tt);
  u = float(uu);
  v = float(vv);
}

// Shadow rays decide occlusion with the same portable t: Embree is given a slightly wider
// interval [tnear - d, tfar + d] and every candidate hit it finds goes through this filter,
// which recomputes t from the world-space ray (kept in the context, indexed by ray id) and
// accepts it only inside the requested [tnear, tfar]. Embree's own boundary decisions (a hit
// a few ulps before or after tfar, ISA-dependent) therefore no longer flip visibility; only
// whether a ray touches a triangle exactly at a silhouette edge can still differ.
struct OcclusionContext {
  RTCIntersectContext ctx;  // first member: Embree passes &ctx back to the filter
  const RenderState* I;
  const Scene* scene;
  // The world-space rays by ray id, one array per component (shade_packet fills them 4 lanes
  // at a time).
  float org_x[16], org_y[16], org_z[16], dir_x[16], dir_y[16], dir_z[16];
  float tnear[16], tfar[16];
};
static_assert(std::is_standard_layout<OcclusionContext>::value, "context must be standard layout");

// Primary rays through screen points, one rtcIntersect16 packet at a time, for a pass that
// consumes each packet's samples at once (render_reference): trace_points' ray, lane and
// per-sample operations (the same bits), without a frame-sized G-buffer. One per thread.
class PointPacketTracer {
 public:
  // `channels` as trace_points (| kDepth; kMotion is not filled); `spacing` as trace_points.
  PointPacketTracer(const Scene& scene, const RenderState& I, const Camera& cam, uint32_t channels,
                    float spacing);
  ~PointPacketTracer();
  PointPacketTracer(PointPacketTracer&&) noexcept;
  // Traces pts[0..n) (n <= 16, pixel coordinates) as one packet, lane k = pts[k]. Returns the
  // packet's 16-slot G-buffer, slot k = sample k; valid until the next call.
  const GBuffer& trace(const glm::vec2* pts, int n);

 private:
  struct Impl;
  std::unique_ptr<Impl> p_;
};

// Scratch of shade_packet (per thread; it needs none at present, the packet's state lives on
// the stack).
struct ShadeScratch {};
// Direct lighting of up to 16 samples of g (slots idx[0..n)), one rtcOccluded16 shadow packet
// per light (render_shade.cpp, the kernel of Renderer::shade): the colour of slot idx[k] goes to
// out[idx[k] * 3 + 0..2]. Adds the shadow rays traced to shadow_rays. The lanes are computed 4
// at a time with the same IEEE operations per lane as shade_one, so both give the same bits.
void shade_packet(const Scene& scene, const RenderState& I, bool shadows, const GBufferRef& g,
                  const size_t* idx, int n, const glm::vec3& eye, float* out, uint64_t& shadow_rays,
                  ShadeScratch& scratch);

// The widening of the interval handed to Embree (see OcclusionContext).
inline float occlusion_slack(const RenderState& I) {
  return 1e-4f * I.scene_scale;
}

}  // namespace fovsim
