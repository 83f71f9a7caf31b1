// Embree 3 ray caster (DESIGN §4). Static objects are flattened into one BVH (world-space
// vertices); when the scene has dynamic objects, the static BVH becomes one instance and
// each dynamic object another, so a frame's recommit only rebuilds the small top level.
// Primary rays go through Embree as 4x4 packets (rtcIntersect16; coherent flag on static
// scenes, incoherent on instanced ones, see packet_flags), one tile at a time; tiles run in
// parallel with TBB. Every pixel is computed independently, so
// results are identical at any thread count.
#include "sim/render/renderer.h"

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>

#include "sim/core/error.h"
#include "sim/render/embree_device.h"

namespace fovsim {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

void embree_error(void*, RTCError code, const char* str) {
  // Errors are collected by check() after each build step; nothing to do here.
  (void)code;
  (void)str;
}

inline glm::vec3 xform_point(const glm::mat4& m, const glm::vec3& p) {
  return glm::vec3(m * glm::vec4(p, 1.f));
}

}  // namespace

RenderSettings RenderSettings::from_params(Params& p) {
  RenderSettings s;
  s.shadows = p.boolean("shadows", true);
  s.tile = p.integer("tile", 32, Range::closed(4, 256));
  return s;
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

// Embree filter for shadow rays (defined with OcclusionContext below).
void occlusion_filter(const RTCFilterFunctionNArguments* args);

namespace {

// Shared vertex buffers need 16 readable bytes past the last vertex (Embree SIMD loads).
// The geometry's user data is its object index (for occlusion_filter).
void attach_mesh(RTCDevice dev, RTCScene sc, const std::vector<glm::vec3>& pos, const Mesh& m,
                 size_t object, unsigned* geom_id) {
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryUserData(g, reinterpret_cast<void*>(object));
  rtcSetGeometryOccludedFilterFunction(g, occlusion_filter);
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, pos.data(), 0,
                             sizeof(glm::vec3), pos.size() - 1);
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, m.triangles.data(), 0,
                             sizeof(glm::uvec3), m.triangles.size());
  rtcCommitGeometry(g);
  *geom_id = rtcAttachGeometry(sc, g);
  rtcReleaseGeometry(g);
}

}  // namespace

Renderer::Renderer(const Scene& scene, const RenderSettings& settings)
    : scene_(scene), settings_(settings), impl_(std::make_unique<Impl>()) {
  Impl& I = *impl_;
  const std::string cfg = embree_device_config();  // FOVSIM_EMBREE_ISA forces a code path
  I.device = rtcNewDevice(cfg.empty() ? nullptr : cfg.c_str());
  if (!I.device) throw Error("embree", "rtcNewDevice(\"" + cfg + "\") failed");
  rtcSetDeviceErrorFunction(I.device, embree_error, nullptr);

  bool any_dynamic = false;
  for (const Object& o : scene.objects) any_dynamic |= o.dynamic();

  I.top = rtcNewScene(I.device);
  I.static_scene = any_dynamic ? rtcNewScene(I.device) : I.top;
  rtcSetSceneBuildQuality(I.static_scene, RTC_BUILD_QUALITY_HIGH);
  // Why dynamic scenes trace packets with the incoherent flag: Embree 3.13.5's coherent
  // (frustum) traversal of 16-wide packets, rtcOccluded16 with RTC_INTERSECT_CONTEXT_FLAG_
  // COHERENT, never returns on this two-level scene once the top level has been recommitted
  // (set_time). Reproduced with a single active lane holding a finite, normalised ray (tnear
  // 0, tfar inf or finite, mask ~0, time 0), with and without RTC_SCENE_FLAG_DYNAMIC/ROBUST and
  // build quality LOW, with a freshly created top-level scene holding the same instances, and
  // with no transform change at all (a plain recommit); the same packet traverses correctly
  // with the incoherent flag, as 8-wide coherent packets, as single rays, and on a flat scene.
  // Which ISA path hangs depends on the CPU (AVX-512 here, AVX2 elsewhere), so the inputs we
  // pass are not the cause; the fix is to keep instanced scenes off Embree's coherent packet
  // path. Flat (static) scenes keep it (~15% faster primary rays). Results are unaffected:
  // both paths run the same ray-triangle test. Regression: Render.DynamicSceneShadowPackets*.
  if (any_dynamic) I.packet_flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  if (any_dynamic) {
    rtcSetSceneFlags(I.top, RTC_SCENE_FLAG_DYNAMIC);
    rtcSetSceneBuildQuality(I.top, RTC_BUILD_QUALITY_LOW);
  }

  for (const Material& m : scene.materials)
    I.mat_cs.emplace_back(std::cos(m.angle), std::sin(m.angle));
  I.objs.resize(scene.objects.size());
  I.dyn_geom.assign(scene.objects.size(), RTC_INVALID_GEOMETRY_ID);
  AABB world;
  // Sub-model lookup per primitive.
  for (size_t si = 0; si < scene.submodels.size(); ++si) {
    const SubModel& sm = scene.submodels[si];
    auto& ts = I.objs[size_t(sm.object)].tri_sub;
    if (ts.empty())
      ts.assign(scene.meshes[size_t(scene.objects[size_t(sm.object)].mesh)].triangles.size(), -1);
    for (uint32_t t = sm.first_tri; t < sm.first_tri + sm.tri_count && t < ts.size(); ++t)
      ts[t] = int32_t(si);
  }

  for (size_t oi = 0; oi < scene.objects.size(); ++oi) {
    const Object& o = scene.objects[oi];
    const Mesh& m = scene.meshes[size_t(o.mesh)];
    RenderState::Obj& ob = I.objs[oi];
    ob.dynamic = o.dynamic();
    ob.xf = ob.prev_xf = o.dynamic() ? o.transform_at(0.0) : o.transform;
    ob.inv = glm::inverse(ob.xf);
    ob.nxf = glm::transpose(glm::inverse(glm::mat3(ob.xf)));
    ob.pos.reserve(m.positions.size() + 1);
    if (ob.dynamic) {
      ob.pos = m.positions;
      ob.nrm = m.normals;
    } else {
      for (const glm::vec3& p : m.positions) ob.pos.push_back(xform_point(ob.xf, p));
      ob.nrm.reserve(m.normals.size());
      for (const glm::vec3& n : m.normals) {
        glm::vec3 w = ob.nxf * n;
        float l = glm::length(w);
        ob.nrm.push_back(l > 0.f ? w / l : w);
      }
    }
    for (const glm::vec3& p : m.positions) world.extend(xform_point(ob.xf, p));
    ob.pos.push_back(glm::vec3(0.f));  // padding
    if (m.triangles.empty()) continue;
    if (!ob.dynamic) {
      unsigned gid;
      attach_mesh(I.device, I.static_scene, ob.pos, m, oi, &gid);
      if (I.static_geom_object.size() <= gid) I.static_geom_object.resize(gid + 1, -1);
      I.static_geom_object[gid] = int(oi);
    } else {
      RTCScene child = rtcNewScene(I.device);
      rtcSetSceneBuildQuality(child, RTC_BUILD_QUALITY_HIGH);
      unsigned gid;
      attach_mesh(I.device, child, ob.pos, m, oi, &gid);
      rtcCommitScene(child);
      I.child_scenes.push_back(child);
      RTCGeometry inst = rtcNewGeometry(I.device, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(inst, child);
      rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &ob.xf[0][0]);
      rtcCommitGeometry(inst);
      unsigned iid = rtcAttachGeometry(I.top, inst);
      rtcReleaseGeometry(inst);
      I.dyn_geom[oi] = iid;
      if (I.inst_object.size() <= iid) I.inst_object.resize(iid + 1, -1);
      I.inst_object[iid] = int(oi);
    }
  }
  if (any_dynamic) {
    rtcCommitScene(I.static_scene);
    RTCGeometry inst = rtcNewGeometry(I.device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(inst, I.static_scene);
    glm::mat4 id(1.f);
    rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &id[0][0]);
    rtcCommitGeometry(inst);
    I.static_inst = rtcAttachGeometry(I.top, inst);
    rtcReleaseGeometry(inst);
    if (I.inst_object.size() <= I.static_inst) I.inst_object.resize(I.static_inst + 1, -1);
    I.inst_object[I.static_inst] = -1;
  }
  rtcCommitScene(I.top);
  I.check("scene build");
  if (!world.empty()) {
    glm::vec3 e = glm::max(glm::abs(world.lo), glm::abs(world.hi));
    I.scene_scale = std::max(1.f, std::max(e.x, std::max(e.y, e.z)));
  }
  time_ = 0.0;
  // Lights at t = 0.
  set_time(0.0);
  for (auto& ob : I.objs) ob.prev_xf = ob.xf;
}

Renderer::~Renderer() = default;

void* Renderer::embree_scene() const {
  return impl_->top;
}

void Renderer::set_time(double t) {
  Impl& I = *impl_;
  time_ = t;
  bool changed = false;
  for (size_t oi = 0; oi < scene_.objects.size(); ++oi) {
    RenderState::Obj& ob = I.objs[oi];
    ob.prev_xf = ob.xf;
    if (!ob.dynamic) continue;
    ob.xf = scene_.objects[oi].transform_at(t);
    ob.inv = glm::inverse(ob.xf);
    ob.nxf = glm::transpose(glm::inverse(glm::mat3(ob.xf)));
    if (I.dyn_geom[oi] != RTC_INVALID_GEOMETRY_ID) {
      RTCGeometry g = rtcGetGeometry(I.top, I.dyn_geom[oi]);
      rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &ob.xf[0][0]);
      rtcCommitGeometry(g);
      changed = true;
    }
  }
  if (changed) {
    rtcCommitScene(I.top);
    I.check("scene update");
  }
  I.lights.clear();
  for (const Light& l : scene_.lights) {
    LightNow n;
    n.type = l.type;
    n.pos = l.position;
    n.dir = glm::normalize(l.direction);
    if (l.moving()) {
      // Keys move the light: translation offsets the position, rotation turns the direction.
      Object tmp;
      tmp.keys = l.keys;
      glm::mat4 m = tmp.transform_at(t);
      n.pos = l.position + glm::vec3(m[3]);
      n.dir = glm::normalize(glm::mat3(m) * n.dir);
    }
    n.radiance = l.color * l.intensity;
    n.cos_inner = float(std::cos(deg2rad(std::min(l.spot_inner_deg, l.spot_outer_deg))));
    n.cos_outer = float(std::cos(deg2rad(l.spot_outer_deg)));
    n.shadows = l.shadows;
    I.lights.push_back(n);
  }
}

namespace {

struct HitInfo {
  int object = -1;
  uint32_t prim = 0;
  float u = 0, v = 0;
};

inline int hit_object(const RenderState& I, const RTCHit& h) {
  if (h.geomID == RTC_INVALID_GEOMETRY_ID) return -1;
  unsigned inst = h.instID[0];
  if (inst == RTC_INVALID_GEOMETRY_ID) return I.static_geom_object[h.geomID];
  int o = I.inst_object[inst];
  return o >= 0 ? o : I.static_geom_object[h.geomID];
}

}  // namespace

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
  glm::vec3 org[16], dir[16];
  float tnear[16], tfar[16];
};
static_assert(std::is_standard_layout<OcclusionContext>::value, "context must be standard layout");

void occlusion_filter(const RTCFilterFunctionNArguments* args) {
  const auto* oc = reinterpret_cast<const OcclusionContext*>(args->context);
  const int obj = int(reinterpret_cast<size_t>(args->geometryUserPtr));
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned id = RTCRayN_id(args->ray, args->N, i);
    const uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
    float t = RTCRayN_tfar(args->ray, args->N, i), u = RTCHitN_u(args->hit, args->N, i),
          v = RTCHitN_v(args->hit, args->N, i);
    refine_hit(*oc->I, *oc->scene, obj, prim, oc->org[id], oc->dir[id], t, u, v);
    if (!(t >= oc->tnear[id] && t <= oc->tfar[id])) args->valid[i] = 0;
  }
}

// The widening of the interval handed to Embree (see OcclusionContext).
inline float occlusion_slack(const RenderState& I) {
  return 1e-4f * I.scene_scale;
}

struct SampleWriter {
  const Scene& scene;
  const RenderState& I;
  const Camera* prev;
  uint32_t ch;

  void albedo(GBuffer& g, size_t i, glm::vec2 uv, int mat) const {
    const Material& mt = scene.materials[size_t(mat)];
    g.albedo[i] = eval_albedo(scene, mt, uv, I.mat_cs[size_t(mat)].x, I.mat_cs[size_t(mat)].y);
  }

  void miss(GBuffer& g, size_t i) const {
    g.depth[i] = kInf;
    if (ch & kPosition) g.position[i] = glm::vec3(0.f);
    if (ch & kNormal) g.normal[i] = glm::vec3(0.f);
    if (ch & kAlbedo) g.albedo[i] = glm::vec3(0.f);
    if (ch & kMaterial) g.material[i] = -1;
    if (ch & kObjectId) g.object_id[i] = -1;
    if (ch & kSubModel) g.submodel[i] = -1;
    if (ch & kMotion) g.motion[i] = glm::vec2(0.f);
    if (ch & kUV) g.uv[i] = glm::vec2(0.f);
  }

  // With `deferred` (a packet's pass), the albedo is not evaluated here: the texture inputs
  // go to deferred->uv / mat and the caller runs eval_albedo for the packet afterwards.
  struct Deferred {
    glm::vec2 uv;
    int mat;
  };
  void hit(GBuffer& g, size_t i, const glm::vec3& org, const glm::vec3& dir, float t, int obj,
           uint32_t prim, float bu, float bv, const glm::vec2& px,
           Deferred* deferred = nullptr) const {
    refine_hit(I, scene, obj, prim, org, dir, t, bu, bv);
    g.depth[i] = t;
    if (!(ch & ~kDepth)) return;
    const Object& o = scene.objects[size_t(obj)];
    const Mesh& m = scene.meshes[size_t(o.mesh)];
    const RenderState::Obj& ob = I.objs[size_t(obj)];
    const glm::uvec3 tri = m.triangles[prim];
    const glm::vec3 P = org + t * dir;
    if (ch & kPosition) g.position[i] = P;
    if (ch & kObjectId) g.object_id[i] = obj;
    if (ch & kSubModel) g.submodel[i] = ob.tri_sub.empty() ? -1 : ob.tri_sub[prim];
    const int mat = m.tri_material.empty() ? m.material : m.tri_material[prim];
    if (ch & kMaterial) g.material[i] = mat;
    const float bw = 1.f - bu - bv;
    const bool need_uv = (ch & (kUV | kAlbedo)) != 0;
    glm::vec3 ng(0.f);
    if ((ch & kNormal) || (need_uv && m.uvs.empty())) {
      const glm::vec3 &p0 = ob.pos[tri.x], &p1 = ob.pos[tri.y], &p2 = ob.pos[tri.z];
      ng = glm::cross(p1 - p0, p2 - p0);  // world (static) or object (dynamic) space
    }
    glm::vec2 uv(0.f);
    if (need_uv) {
      if (!m.uvs.empty()) {
        uv = bw * m.uvs[tri.x] + bu * m.uvs[tri.y] + bv * m.uvs[tri.z];
      } else {
        // No uvs: planar projection along the dominant axis of the object-space normal.
        glm::vec3 po = ob.dynamic ? xform_point(ob.inv, P) : P;
        glm::vec3 a = glm::abs(ng);
        uv = (a.x >= a.y && a.x >= a.z) ? glm::vec2(po.z, po.y)
             : (a.y >= a.z)             ? glm::vec2(po.x, po.z)
                                        : glm::vec2(po.x, po.y);
      }
      if (ch & kUV) g.uv[i] = uv;
    }
    if (ch & kAlbedo) {
      if (deferred)
        *deferred = {uv, mat};
      else
        albedo(g, i, uv, mat);
    }
    if (ch & kNormal) {
      glm::vec3 n;
      if (ob.dynamic) ng = ob.nxf * ng;
      if (!ob.nrm.empty()) {
        n = bw * ob.nrm[tri.x] + bu * ob.nrm[tri.y] + bv * ob.nrm[tri.z];
        if (ob.dynamic) n = ob.nxf * n;
      } else {
        n = ng;
      }
      // Face the viewer: geometric normal against the ray, shading normal on its side.
      if (glm::dot(ng, dir) > 0.f) ng = -ng;
      if (glm::dot(n, ng) < 0.f) n = -n;
      float l = glm::length(n);
      if (!(l > 0.f)) {
        n = ng;
        l = glm::length(n);
      }
      n = l > 0.f ? n / l : -dir;
      // Interpolated normals can still point away from the eye near silhouettes: bend them
      // just past the view-perpendicular so every normal faces the viewer.
      const float nv = glm::dot(n, dir);
      if (nv > 0.f) n = glm::normalize(n - dir * (nv + 1e-3f));
      g.normal[i] = n;
    }
    if (ch & kMotion) {
      glm::vec2 mv(0.f);
      if (prev) {
        glm::vec3 Pp = ob.dynamic ? xform_point(ob.prev_xf, xform_point(ob.inv, P)) : P;
        glm::dvec2 pp;
        if (prev->project_world(glm::dvec3(Pp), pp)) mv = px - glm::vec2(pp);
      }
      g.motion[i] = mv;
    }
  }
};

namespace {

// A packet of up to 16 primary rays from one origin (rtcIntersect16). 4x4 pixel blocks are
// the most coherent unit; measured ~15% faster than the rtcIntersect1M stream API here.
struct Packet {
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  size_t idx[16];
  glm::vec2 px[16];
  int n = 0;

  // Fields rtcIntersect16 only reads (tnear, time, mask, id, flags) are set once here; add()
  // writes the rest (Embree writes tfar and the hit fields back).
  Packet() {
    for (int k = 0; k < 16; ++k) {
      rh.ray.tnear[k] = 0.f;
      rh.ray.time[k] = 0.f;
      rh.ray.mask[k] = 0xffffffffu;
      rh.ray.id[k] = unsigned(k);
      rh.ray.flags[k] = 0;
    }
  }
  void reset() { n = 0; }
  void add(const glm::vec3& o, const glm::vec3& d, size_t i, glm::vec2 p) {
    const int k = n++;
    rh.ray.org_x[k] = o.x;
    rh.ray.org_y[k] = o.y;
    rh.ray.org_z[k] = o.z;
    rh.ray.dir_x[k] = d.x;
    rh.ray.dir_y[k] = d.y;
    rh.ray.dir_z[k] = d.z;
    rh.ray.tfar[k] = kInf;
    rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    valid[k] = -1;
    idx[k] = i;
    px[k] = p;
  }
  void trace(const RenderState& I, const SampleWriter& w, const glm::vec3& o, GBuffer& g) {
    if (n == 0) return;
    // Inactive lanes are masked off, but Debian's Embree (assertions on) still checks their
    // ray fields in the 8-wide halves: give them a copy of lane 0's valid ray.
    for (int k = n; k < 16; ++k) {
      valid[k] = 0;
      rh.ray.org_x[k] = rh.ray.org_x[0];
      rh.ray.org_y[k] = rh.ray.org_y[0];
      rh.ray.org_z[k] = rh.ray.org_z[0];
      rh.ray.dir_x[k] = rh.ray.dir_x[0];
      rh.ray.dir_y[k] = rh.ray.dir_y[0];
      rh.ray.dir_z[k] = rh.ray.dir_z[0];
      rh.ray.tfar[k] = kInf;
      rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = I.packet_flags;
    rtcIntersect16(valid, I.top, &ctx, &rh);
    // Geometry of every lane first, then the packet's textures (libm sin/cos calls) in a loop
    // of their own; each sample's operations are unchanged.
    SampleWriter::Deferred tex[16];
    int hits[16], nh = 0;
    const bool albedo = (w.ch & kAlbedo) != 0;
    for (int k = 0; k < n; ++k) {
      if (rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) {
        w.miss(g, idx[k]);
        continue;
      }
      RTCHit h;
      h.geomID = rh.hit.geomID[k];
      h.instID[0] = rh.hit.instID[0][k];
      glm::vec3 d(rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k]);
      w.hit(g, idx[k], o, d, rh.ray.tfar[k], hit_object(I, h), rh.hit.primID[k], rh.hit.u[k],
            rh.hit.v[k], px[k], albedo ? &tex[nh] : nullptr);
      hits[nh++] = k;
    }
    if (albedo)
      for (int j = 0; j < nh; ++j) w.albedo(g, idx[hits[j]], tex[j].uv, tex[j].mat);
    n = 0;
  }
};

inline void init_ray(RTCRayHit& r, const glm::vec3& o, const glm::vec3& d) {
  r.ray.org_x = o.x;
  r.ray.org_y = o.y;
  r.ray.org_z = o.z;
  r.ray.tnear = 0.f;
  r.ray.dir_x = d.x;
  r.ray.dir_y = d.y;
  r.ray.dir_z = d.z;
  r.ray.time = 0.f;
  r.ray.tfar = kInf;
  r.ray.mask = 0xffffffffu;
  r.ray.id = 0;
  r.ray.flags = 0;
  r.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  r.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace

void Renderer::trace_gbuffer(const Camera& cam, uint32_t channels, GBuffer& out, Counters* c,
                             const Camera* prev) const {
  const RenderState& I = *impl_;
  channels |= kDepth;
  if (out.width != cam.width || out.height != cam.height || out.channels != channels)
    out.resize(cam.width, cam.height, channels);
  const int T = std::max(4, settings_.tile);
  const int tx = (cam.width + T - 1) / T, ty = (cam.height + T - 1) / T;
  const glm::vec3 org(cam.position);
  const glm::dmat3 R = glm::mat3_cast(cam.orientation);
  // Camera::dir_head's terms per column and row (same operations, so the same bits).
  // Their squares too: glm::normalize(v) is v * (1 / sqrt((v.x*v.x + v.y*v.y) + v.z*v.z)), so
  // (hx2 + hy2) + 1.0 below is the same sum, operation for operation.
  std::vector<double> hx(size_t(cam.width)), hy(size_t(cam.height));
  std::vector<double> hx2(size_t(cam.width)), hy2(size_t(cam.height));
  for (int x = 0; x < cam.width; ++x) {
    hx[size_t(x)] = (2.0 * (x + 0.5) / cam.width - 1.0) * cam.tan_half_h;
    hx2[size_t(x)] = hx[size_t(x)] * hx[size_t(x)];
  }
  for (int y = 0; y < cam.height; ++y) {
    hy[size_t(y)] = (1.0 - 2.0 * (y + 0.5) / cam.height) * cam.tan_half_v;
    hy2[size_t(y)] = hy[size_t(y)] * hy[size_t(y)];
  }
  SampleWriter w{scene_, I, prev, channels};
  tbb::parallel_for(
      tbb::blocked_range<int>(0, tx * ty, 1),
      [&](const tbb::blocked_range<int>& r) {
        Packet pk;
        for (int tile = r.begin(); tile != r.end(); ++tile) {
          const int x0 = (tile % tx) * T, y0 = (tile / tx) * T;
          const int x1 = std::min(x0 + T, cam.width), y1 = std::min(y0 + T, cam.height);
          for (int by = y0; by < y1; by += 4)
            for (int bx = x0; bx < x1; bx += 4) {
              for (int y = by; y < std::min(by + 4, y1); ++y)
                for (int x = bx; x < std::min(bx + 4, x1); ++x) {
                  // == Camera::dir_world(x + 0.5, y + 0.5)
                  const double s = 1.0 / std::sqrt((hx2[size_t(x)] + hy2[size_t(y)]) + 1.0);
                  const glm::dvec3 d = R * glm::dvec3(hx[size_t(x)] * s, hy[size_t(y)] * s, -s);
                  pk.add(org, glm::vec3(d), size_t(y) * size_t(cam.width) + size_t(x),
                         glm::vec2(float(x) + 0.5f, float(y) + 0.5f));
                }
              pk.trace(I, w, org, out);
            }
        }
      },
      tbb::simple_partitioner());
  const double n = double(cam.width) * double(cam.height);
  rays_ += uint64_t(n);
  if (c) c->add("primary_rays", n);
}

void Renderer::trace_points(const Camera& cam, const std::vector<glm::vec2>& pts_in,
                            uint32_t channels, GBuffer& out, Counters* c) const {
  const RenderState& I = *impl_;
  channels |= kDepth;
  const int n_pts = int(pts_in.size());
  if (out.width != n_pts || out.height != 1 || out.channels != channels)
    out.resize(n_pts, 1, channels);
  const glm::vec3 org(cam.position);
  const glm::dmat3 R = glm::mat3_cast(cam.orientation);
  SampleWriter w{scene_, I, nullptr, channels & ~uint32_t(kMotion)};
  if (channels & kMotion)
    for (auto& m : out.motion) m = glm::vec2(0.f);
  // Consecutive points in packets of 16 (callers usually pass them in scanline order).
  const int B = 256;
  tbb::parallel_for(
      tbb::blocked_range<int>(0, (n_pts + B - 1) / B, 1),
      [&](const tbb::blocked_range<int>& r) {
        Packet pk;
        for (int b = r.begin(); b != r.end(); ++b) {
          const int i0 = b * B, i1 = std::min(n_pts, i0 + B);
          for (int i = i0; i < i1; ++i) {
            const glm::vec2 p = pts_in[size_t(i)];
            glm::dvec3 d = R * cam.dir_head(p.x, p.y);
            pk.add(org, glm::vec3(d), size_t(i), p);
            if (pk.n == 16) pk.trace(I, w, org, out);
          }
          pk.trace(I, w, org, out);
        }
      },
      tbb::simple_partitioner());
  rays_ += uint64_t(n_pts);
  if (c) c->add("primary_rays", double(n_pts));
}

namespace {

inline float smooth01(float e0, float e1, float x) {
  if (e1 <= e0) return x >= e1 ? 1.f : 0.f;
  float t = clamp01((x - e0) / (e1 - e0));
  return t * t * (3.f - 2.f * t);
}

inline bool occluded_ray(const Scene& scene, const RenderState& I, const glm::vec3& o,
                         const glm::vec3& d, float tnear, float tfar) {
  OcclusionContext oc;
  rtcInitIntersectContext(&oc.ctx);
  oc.I = &I;
  oc.scene = &scene;
  oc.org[0] = o;
  oc.dir[0] = d;
  oc.tnear[0] = tnear;
  oc.tfar[0] = tfar;
  const float slack = occlusion_slack(I);
  RTCRay r;
  r.org_x = o.x;
  r.org_y = o.y;
  r.org_z = o.z;
  r.tnear = std::max(0.f, tnear - slack);
  r.dir_x = d.x;
  r.dir_y = d.y;
  r.dir_z = d.z;
  r.time = 0.f;
  r.tfar = tfar + slack;
  r.mask = 0xffffffffu;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(I.top, &oc.ctx, &r);
  return r.tfar < 0.f;  // Embree sets tfar = -inf when blocked
}

}  // namespace

// One light's unshadowed contribution to a sample: Lambert (albedo * cos * E) + Blinn-Phong
// (ks * (n.h)^s * cos * E). Returns 0 if the light does not reach the sample, 1 if it does
// without a shadow test, 2 if a shadow ray (O + s L, s in [0, tfar]) decides.
struct SurfacePoint {
  glm::vec3 P, N, A, V, O;
  const Material* m;
};

inline int light_term(const LightNow& l, const SurfacePoint& sp, bool shadows, float eps,
                      glm::vec3& contrib, glm::vec3& L, float& tfar) {
  glm::vec3 E;
  float dist = kInf;
  if (l.type == Light::Type::Directional) {
    L = -l.dir;
    E = l.radiance;
  } else {
    glm::vec3 d = l.pos - sp.P;
    float r2 = glm::dot(d, d);
    if (!(r2 > 0.f)) return 0;
    dist = std::sqrt(r2);
    L = d / dist;
    E = l.radiance / r2;
    if (l.type == Light::Type::Spot) {
      float f = smooth01(l.cos_outer, l.cos_inner, glm::dot(-L, l.dir));
      if (f <= 0.f) return 0;
      E *= f;
    }
  }
  const float ndl = glm::dot(sp.N, L);
  if (ndl <= 0.f) return 0;
  glm::vec3 brdf = sp.A;
  if (sp.m && sp.m->specular > 0.f) {
    glm::vec3 H = glm::normalize(L + sp.V);
    float ndh = std::max(0.f, glm::dot(sp.N, H));
    brdf += glm::vec3(sp.m->specular * std::pow(ndh, sp.m->shininess));
  }
  contrib = brdf * E * ndl;
  if (!(shadows && l.shadows)) return 1;
  tfar = std::isinf(dist) ? kInf : std::max(0.f, dist - 2.f * eps);
  return 2;
}

// Ambient + emission, and the surface frame for the lights. False on a miss.
inline bool surface(const Scene& scene, const RenderState& I, const GBuffer& g, size_t i,
                    const glm::vec3& eye, SurfacePoint& sp, glm::vec3& base) {
  if (!g.hit(i)) {
    base = scene.background;
    return false;
  }
  sp.P = g.position[i];
  sp.N = g.normal[i];
  sp.A = g.albedo[i];
  const int mi = g.material[i];
  sp.m = (mi >= 0 && size_t(mi) < scene.materials.size()) ? &scene.materials[size_t(mi)] : nullptr;
  base = scene.ambient * sp.A;
  if (sp.m) base += sp.m->emission;
  sp.V = glm::normalize(eye - sp.P);
  sp.O = sp.P + sp.N * (2e-4f * I.scene_scale);
  return true;
}

// Direct lighting of one sample with single shadow rays (deterministic: no sampling).
static glm::vec3 shade_one(const Scene& scene, const RenderState& I, bool shadows, const GBuffer& g,
                           size_t i, const glm::vec3& eye, uint64_t* shadow_rays) {
  SurfacePoint sp;
  glm::vec3 col;
  if (!surface(scene, I, g, i, eye, sp, col)) return col;
  const float eps = 2e-4f * I.scene_scale;
  for (const LightNow& l : I.lights) {
    glm::vec3 contrib, L;
    float tfar = kInf;
    int k = light_term(l, sp, shadows, eps, contrib, L, tfar);
    if (k == 0) continue;
    if (k == 2) {
      if (shadow_rays) ++*shadow_rays;
      if (occluded_ray(scene, I, sp.O, L, 0.f, tfar)) continue;
    }
    col += contrib;
  }
  return col;
}

// The same for up to 16 samples at once, with one rtcOccluded16 packet per light (shadow
// rays from neighbouring samples towards one light are coherent). Accumulates in the same
// order as shade_one, so both give the same bits.
static void shade_block(const Scene& scene, const RenderState& I, bool shadows, const GBuffer& g,
                        const size_t* idx, int n, const glm::vec3& eye, Image& out,
                        uint64_t& shadow_rays, std::vector<glm::vec3>& contrib,
                        std::vector<uint8_t>& state) {
  const size_t nl = I.lights.size();
  contrib.resize(16 * nl);
  state.resize(16 * nl);
  SurfacePoint sp[16];
  glm::vec3 col[16];
  bool hit[16];
  const float eps = 2e-4f * I.scene_scale;
  for (int k = 0; k < n; ++k) hit[k] = surface(scene, I, g, idx[k], eye, sp[k], col[k]);
  alignas(64) RTCRay16 ray;
  alignas(64) int valid[16];
  OcclusionContext oc;
  oc.I = &I;
  oc.scene = &scene;
  const float slack = occlusion_slack(I);
  for (size_t li = 0; li < nl; ++li) {
    const LightNow& l = I.lights[li];
    int tests = 0;
    for (int k = 0; k < 16; ++k) {
      uint8_t st = 0;
      glm::vec3 L(0.f, 1.f, 0.f);
      float tfar = kInf;
      if (k < n && hit[k])
        st = uint8_t(light_term(l, sp[k], shadows, eps, contrib[size_t(k) * nl + li], L, tfar));
      state[size_t(k) * nl + li] = st;
      // Inactive lanes get a harmless ray too (Debian's Embree asserts on all lanes' fields).
      const glm::vec3 o = (k < n && hit[k]) ? sp[k].O : glm::vec3(0.f);
      ray.org_x[k] = o.x;
      ray.org_y[k] = o.y;
      ray.org_z[k] = o.z;
      ray.dir_x[k] = L.x;
      ray.dir_y[k] = L.y;
      ray.dir_z[k] = L.z;
      ray.tnear[k] = 0.f;
      ray.tfar[k] = st == 2 ? tfar + slack : kInf;
      oc.org[k] = o;
      oc.dir[k] = L;
      oc.tnear[k] = 0.f;
      oc.tfar[k] = st == 2 ? tfar : kInf;
      ray.time[k] = 0.f;
      ray.mask[k] = 0xffffffffu;
      ray.id[k] = unsigned(k);
      ray.flags[k] = 0;
      valid[k] = st == 2 ? -1 : 0;
      tests += st == 2;
    }
    if (tests == 0) continue;
    shadow_rays += uint64_t(tests);
    rtcInitIntersectContext(&oc.ctx);
    oc.ctx.flags = I.packet_flags;
    rtcOccluded16(valid, I.top, &oc.ctx, &ray);
    for (int k = 0; k < n; ++k)
      if (state[size_t(k) * nl + li] == 2 && ray.tfar[k] < 0.f) state[size_t(k) * nl + li] = 0;
  }
  for (int k = 0; k < n; ++k) {
    glm::vec3 c = col[k];
    if (hit[k])
      for (size_t li = 0; li < nl; ++li)
        if (state[size_t(k) * nl + li]) c += contrib[size_t(k) * nl + li];
    float* o = &out.data[idx[k] * 3];
    o[0] = c.x;
    o[1] = c.y;
    o[2] = c.z;
  }
}

glm::vec3 Renderer::shade_sample(const GBuffer& g, size_t i, const glm::vec3& eye) const {
  uint64_t n = 0;
  glm::vec3 c = shade_one(scene_, *impl_, settings_.shadows, g, i, eye, &n);
  rays_ += n;
  return c;
}

void Renderer::shade(const GBuffer& g, const glm::dvec3& eye_d, Image& out, const uint8_t* mask,
                     Counters* c) const {
  if (!g.has(kShadingChannels))
    throw Error("renderer",
                "shade() needs a G-buffer with depth, position, normal, albedo, material");
  if (out.width != g.width || out.height != g.height || out.channels != 3)
    out.resize(g.width, g.height, 3);
  const glm::vec3 eye(eye_d);
  const size_t n = g.size();
  const size_t B = 4096;
  const size_t nb = (n + B - 1) / B;
  std::vector<uint64_t> shadow(nb, 0), shaded(nb, 0);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, nb, 1),
      [&](const tbb::blocked_range<size_t>& r) {
        std::vector<glm::vec3> contrib;
        std::vector<uint8_t> state;
        size_t idx[16];
        for (size_t b = r.begin(); b != r.end(); ++b) {
          uint64_t sr = 0, ss = 0;
          int k = 0;
          for (size_t i = b * B, e = std::min(n, i + B); i < e; ++i) {
            if (mask && !mask[i]) continue;
            idx[k++] = i;
            ++ss;
            if (k == 16) {
              shade_block(scene_, *impl_, settings_.shadows, g, idx, k, eye, out, sr, contrib,
                          state);
              k = 0;
            }
          }
          if (k)
            shade_block(scene_, *impl_, settings_.shadows, g, idx, k, eye, out, sr, contrib, state);
          shadow[b] = sr;
          shaded[b] = ss;
        }
      },
      tbb::simple_partitioner());
  uint64_t sr = 0, ss = 0;
  for (size_t b = 0; b < nb; ++b) {
    sr += shadow[b];
    ss += shaded[b];
  }
  rays_ += sr;
  if (c) {
    c->add("shaded_samples", double(ss));
    c->add("shadow_rays", double(sr));
  }
}

bool Renderer::occluded(const glm::vec3& from, const glm::vec3& to) const {
  glm::vec3 d = to - from;
  float dist = glm::length(d);
  if (!(dist > 0.f)) return false;
  const float eps = 1e-4f * impl_->scene_scale;
  rays_ += 1;
  if (dist <= 2.f * eps) return false;
  return occluded_ray(scene_, *impl_, from, d / dist, eps, dist - eps);
}

float Renderer::intersect(const glm::vec3& org, const glm::vec3& dir_in, int* object, int* prim,
                          glm::vec3* normal, glm::vec2* uv) const {
  const Impl& I = *impl_;
  glm::vec3 dir = glm::normalize(dir_in);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  init_ray(rh, org, dir);
  rtcIntersect1(I.top, &ctx, &rh);
  rays_ += 1;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
    if (object) *object = -1;
    if (prim) *prim = -1;
    return kInf;
  }
  int obj = hit_object(I, rh.hit);
  if (object) *object = obj;
  if (prim) *prim = int(rh.hit.primID);
  refine_hit(I, scene_, obj, rh.hit.primID, org, dir, rh.ray.tfar, rh.hit.u, rh.hit.v);
  if (normal || uv) {
    GBuffer g;
    g.resize(1, 1, kNormal | kUV);
    SampleWriter w{scene_, I, nullptr, g.channels};
    w.hit(g, 0, org, dir, rh.ray.tfar, obj, rh.hit.primID, rh.hit.u, rh.hit.v, glm::vec2(0.f));
    if (normal) *normal = g.normal[0];
    if (uv) *uv = g.uv[0];
  }
  return rh.ray.tfar;
}

AABB Renderer::submodel_bounds_world(size_t i) const {
  const SubModel& sm = scene_.submodels[i];
  const glm::mat4& xf = impl_->objs[size_t(sm.object)].xf;
  AABB b;
  if (sm.bounds.empty()) return b;
  for (int k = 0; k < 8; ++k) {
    glm::vec3 p((k & 1) ? sm.bounds.hi.x : sm.bounds.lo.x,
                (k & 2) ? sm.bounds.hi.y : sm.bounds.lo.y,
                (k & 4) ? sm.bounds.hi.z : sm.bounds.lo.z);
    b.extend(xform_point(xf, p));
  }
  return b;
}

// ---- tone mapping -------------------------------------------------------------------------

namespace {

inline float aces(float x) {
  // Narkowicz 2015 fit of the ACES filmic curve.
  const float a = 2.51f, b = 0.03f, c = 2.43f, d = 0.59f, e = 0.14f;
  return clamp01((x * (a * x + b)) / (x * (c * x + d) + e));
}

inline float srgb_oetf(float x) {
  x = clamp01(x);
  if (x >= 1.f) return 1.f;  // exact white (the formula rounds to 0.99999994)
  return clamp01(x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.f / 2.4f) - 0.055f);
}

}  // namespace

void ToneMap::apply(const Image& linear, Image& display) const {
  if (display.width != linear.width || display.height != linear.height ||
      display.channels != linear.channels)
    display.resize(linear.width, linear.height, linear.channels);
  const float ex = float(exposure);
  const Curve cv = curve;
  const size_t n = linear.data.size();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 14),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i) {
                        float x = linear.data[i] * ex;
                        if (!(x > 0.f)) x = 0.f;  // negatives and NaN -> black
                        float y;
                        switch (cv) {
                          case Curve::Reinhard:
                            y = std::isinf(x) ? 1.f : x / (1.f + x);
                            break;
                          case Curve::Aces:
                            y = std::isinf(x) ? 1.f : aces(x);
                            break;
                          default:
                            y = clamp01(x);
                            break;
                        }
                        display.data[i] = srgb_oetf(y);
                      }
                    });
}

}  // namespace fovsim
