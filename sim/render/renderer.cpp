// Embree 3 ray caster (docs/architecture.md "Rendering and the shared reference"), scene side.
// Static objects are flattened into one BVH (world-space vertices); when the scene has dynamic
// objects, the static BVH becomes one instance and each dynamic object another, so a frame's
// recommit only rebuilds the small top level. Tracing is in render_trace.cpp, shading in
// render_shade.cpp (render_internal.h).
#include "sim/render/renderer.h"

#include "sim/core/param_table.h"
#include "sim/render/embree_device.h"
#include "sim/render/render_internal.h"

namespace fovsim {

namespace {

void embree_error(void*, RTCError code, const char* str) {
  // Errors are collected by check() after each build step; nothing to do here.
  (void)code;
  (void)str;
}

}  // namespace

const ParamTable<RenderSettings>& render_settings_table() {
  using S = RenderSettings;
  static const auto t =
      ParamTable<S>()
          .boolean("shadows", true, &S::shadows)
          .doc("", "shadow rays for lights with shadows")
          .integer("tile", 32, Range::closed(4, 256), &S::tile)
          .doc("", "TBB tile edge in pixels")
          // Default from the convergence study (docs/metrics.md "Reference convergence"): at 16
          // spp every quickstart method's means move by < 0.06 dB (FLIP < 0.0011) to 64 spp
          // and the ranking no longer changes; 4 spp still moves TWFR by 0.32 dB.
          .integer("spp", kDefaultReferenceSpp, Range::closed(1, 1024), &S::spp)
          .shown("16", "1, 4, 9, ..., 1024 (n^2)")
          .doc("",
               "samples per pixel of the shared **reference**: n x n stratified sub-pixel "
               "samples (each jittered inside its stratum by a fixed hash of pixel and "
               "stratum), each shaded once, reconstructed with a box filter over the pixel "
               "in linear light (tone mapping after). Methods are not supersampled: they "
               "shade each of their own samples once. The default comes from the "
               "convergence study in `docs/metrics.md`; tests and quick looks may use "
               "`render.spp=1`")
          .validate([](const S& s, Params& p) {
            const int n = int(std::lround(std::sqrt(double(s.spp))));
            if (n * n != s.spp)
              p.fail("spp",
                     "must be a perfect square (1, 4, 9, 16, 25, ..., 1024: n x n stratified "
                     "samples per pixel), got " +
                         std::to_string(s.spp));
          });
  return t;
}

RenderSettings RenderSettings::from_params(Params& p) {
  return render_settings_table().read(p);
}

namespace {

// Shared vertex buffers need 16 readable bytes past the last vertex (Embree SIMD loads).
// The geometry's user data is its GeomUser (object index, state; for the filters).
void attach_mesh(RTCDevice dev, RTCScene sc, const std::vector<glm::vec3>& pos, const Mesh& m,
                 const Scene& scene, RenderState::GeomUser* user, unsigned* geom_id) {
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryUserData(g, user);
  rtcSetGeometryOccludedFilterFunction(g, occlusion_filter);
  bool cutout = scene.materials[size_t(m.material)].cutout();
  for (int mi : m.tri_material) cutout = cutout || scene.materials[size_t(mi)].cutout();
  user->cutout = cutout;
  if (cutout) rtcSetGeometryIntersectFilterFunction(g, alpha_filter);
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
  I.geom_user.resize(scene.objects.size());
  for (size_t oi = 0; oi < scene.objects.size(); ++oi) I.geom_user[oi] = {&I, &scene, int(oi)};
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
      attach_mesh(I.device, I.static_scene, ob.pos, m, scene, &I.geom_user[oi], &gid);
      if (I.static_geom_object.size() <= gid) I.static_geom_object.resize(gid + 1, -1);
      I.static_geom_object[gid] = int(oi);
    } else {
      RTCScene child = rtcNewScene(I.device);
      rtcSetSceneBuildQuality(child, RTC_BUILD_QUALITY_HIGH);
      unsigned gid;
      attach_mesh(I.device, child, ob.pos, m, scene, &I.geom_user[oi], &gid);
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

}  // namespace fovsim
