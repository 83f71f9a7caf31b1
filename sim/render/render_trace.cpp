// Primary rays (docs/architecture.md "Rendering and the shared reference"): Embree 4x4 packets
// (rtcIntersect16; coherent flag on static scenes, incoherent on instanced ones, see renderer.cpp),
// one tile at a time; tiles run in parallel with TBB. Every pixel is computed independently, so
// results are identical at any thread count. Hit distance and barycentrics are recomputed portably
// (refine_hit). The G-buffer pass traces a whole tile (a band of it, TileBatch: up to kBatchLanes
// rays) before shading any of it: ray generation and rtcIntersect16 packet after packet into
// per-ray hit arrays, then for all of its hits together the object and material lookups, for the
// common hits (static, uvs, no normal map) refinement, normals, uvs and footprints with the
// per-sample code's operations (SampleWriter::gather / finish and gbuffer_lanes.h: 4, 8 or 16
// lanes per instruction as the CPU allows, the same bits; other hits take SampleWriter::hit),
// the textures (eval_albedo_packet), and the band's samples, staged in pixel order, copied to
// the G-buffer a row at a time (TileBatch::flush). trace_points and the reference take one
// packet at a time (Packet::stage). Performance against Embree's own packet rate:
// bench/README.md.
#include <emmintrin.h>
#include <tbb/parallel_for.h>

#include <cstring>

#include "sim/render/gbuffer_lanes.h"
#include "sim/render/render_internal.h"
#include "sim/render/vec4.h"
#include "sim/scene/texture_packet.h"

namespace fovsim {

// Ray cones (Akenine-Moller et al., "Texture Level of Detail Strategies for Real-Time Ray
// Tracing", Ray Tracing Gems 2019, ch. 20), isotropic: a sample whose rays are `spacing` pixels
// apart covers the solid angle spacing^2 * dx * dy * cos^3(theta) (dx, dy: pixel size on the
// image plane at distance 1; theta: angle to the view axis); its cone width is the square
// root of that. At distance t on a surface seen at cos(n, d) the footprint's area is
// (t * cone)^2 / |cos|, and the filter is the isotropic box of the same area (a compromise
// between blur along the major axis and aliasing along the minor one). cos_axis = cos(theta).
// cone_scale() is the per-camera factor spacing * sqrt(dx * dy); cone_width(scale, cos_axis) the
// per-ray remainder, evaluated in the same order as the single expression it was split from.
inline double cone_scale(const Camera& cam, float spacing) {
  const double dx = 2.0 * cam.tan_half_h / cam.width, dy = 2.0 * cam.tan_half_v / cam.height;
  return double(spacing) * std::sqrt(dx * dy);
}
inline float cone_width(double scale, double cos_axis) {
  return float(scale * cos_axis * std::sqrt(cos_axis));
}

bool alpha_rejects(const RenderState& I, const Scene& scene, int obj, uint32_t prim, float u,
                   float v) {
  const Mesh& m = scene.meshes[size_t(scene.objects[size_t(obj)].mesh)];
  const int mi = m.tri_material.empty() ? m.material : m.tri_material[prim];
  const Material& mt = scene.materials[size_t(mi)];
  if (!mt.cutout()) return false;
  glm::vec2 uv(0.f);
  if (!m.uvs.empty()) {
    const glm::uvec3 tri = m.triangles[prim];
    uv = (1.f - u - v) * m.uvs[tri.x] + u * m.uvs[tri.y] + v * m.uvs[tri.z];
  }
  (void)I;
  return material_alpha(scene, mt, uv) < mt.alpha_cutoff;
}

void alpha_filter(const RTCFilterFunctionNArguments* args) {
  const auto* gu = static_cast<const RenderState::GeomUser*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
    const glm::vec3 org(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                        RTCRayN_org_z(args->ray, args->N, i));
    const glm::vec3 dir(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                        RTCRayN_dir_z(args->ray, args->N, i));
    float t = RTCRayN_tfar(args->ray, args->N, i), u = RTCHitN_u(args->hit, args->N, i),
          v = RTCHitN_v(args->hit, args->N, i);
    // The portable barycentrics (as the G-buffer uses), so the cut-out edge is ISA-free.
    refine_hit(*gu->I, *gu->scene, gu->object, prim, org, dir, t, u, v);
    if (alpha_rejects(*gu->I, *gu->scene, gu->object, prim, u, v)) args->valid[i] = 0;
  }
}

// G-buffer stores, one component at a time. GCC copies a glm vector by building it in a
// stack slot with 4-byte stores and moving it out with an 8-byte load + store; that load
// cannot be forwarded from the two narrower stores and waits for them to reach the cache
// (perf: 55-77% of SampleWriter::hit's samples on that load). Same values, same bits.
inline void put(glm::vec3& d, const glm::vec3& s) {
  d.x = s.x;
  d.y = s.y;
  d.z = s.z;
}
inline void put(glm::vec2& d, const glm::vec2& s) {
  d.x = s.x;
  d.y = s.y;
}

// Per object and per material, what the packet loop asks of every hit (SampleWriter::fast_hit,
// gather), read from one compact record instead of through Object -> Mesh -> Material and the
// renderer's per-object state (perf: that chain of dependent loads was most of the hit loop's
// time). Built per pass from the scene; the same values, so the same bits.
struct HitTable {
  struct Obj {
    const glm::uvec3* tri = nullptr;
    const glm::vec3* pos = nullptr;  // world space (static objects)
    const glm::vec3* nrm = nullptr;  // nullptr: no vertex normals
    const glm::vec2* uv = nullptr;
    // The triangle's material is mat_of[prim & mat_mask]: the mesh's per-triangle list (mask
    // ~0), or its one material (&mat, mask 0), without a branch.
    const int* mat_of = nullptr;
    uint32_t mat_mask = 0;
    const int32_t* tri_sub = nullptr;
    int mat = 0;
    bool fast = false;  // static, with per-vertex uvs
  };
  std::vector<Obj> objs;
  std::vector<uint8_t> plain;  // per material: 1 = no normal map
  HitTable(const Scene& scene, const RenderState& I) {
    objs.resize(scene.objects.size());
    for (size_t o = 0; o < objs.size(); ++o) {
      const Mesh& m = scene.meshes[size_t(scene.objects[o].mesh)];
      const RenderState::Obj& ob = I.objs[o];
      Obj& t = objs[o];
      t.tri = m.triangles.data();
      t.pos = ob.pos.data();
      t.nrm = ob.nrm.empty() ? nullptr : ob.nrm.data();
      t.uv = m.uvs.empty() ? nullptr : m.uvs.data();
      t.tri_sub = ob.tri_sub.empty() ? nullptr : ob.tri_sub.data();
      t.mat = m.material;
      t.mat_of = m.tri_material.empty() ? &t.mat : m.tri_material.data();
      t.mat_mask = m.tri_material.empty() ? 0u : ~0u;
      t.fast = !ob.dynamic && !m.uvs.empty();
    }
    plain.resize(scene.materials.size());
    for (size_t k = 0; k < plain.size(); ++k) {
      const Material& mt = scene.materials[k];
      plain[k] = !(mt.normal_image >= 0 && size_t(mt.normal_image) < scene.images.size());
    }
  }
};

// FastLanes (the common-path hits of a packet) and their arithmetic: gbuffer_lanes.h.

struct SampleWriter {
  const Scene& scene;
  const RenderState& I;
  const Camera* prev;
  uint32_t ch;
  const HitTable* tab = nullptr;  // nullptr: every hit takes hit()

  void albedo(GBuffer& g, size_t i, glm::vec2 uv, int mat, float fw) const {
    const Material& mt = scene.materials[size_t(mat)];
    put(g.albedo[i],
        eval_albedo(scene, mt, uv, I.mat_cs[size_t(mat)].x, I.mat_cs[size_t(mat)].y, fw));
  }

  // Texture filter width (uv units) of a hit at distance t: the cone's footprint on the
  // triangle times its uv density sqrt(uv area / world area). Without uvs the texture
  // coordinates are object-space positions (density 1, or 1 / the object's scale).
  float footprint(const RenderState::Obj& ob, const Mesh& m, const glm::uvec3& tri,
                  const glm::vec3& ng, const glm::vec3& dir, float t, float cone) const {
    if (!(cone > 0.f)) return 0.f;
    glm::vec3 ngw = ob.dynamic ? ob.nxf * ng : ng;
    const float ln = glm::length(ngw);
    if (!(ln > 0.f)) return 0.f;
    const float cosn = std::max(1e-3f, std::fabs(glm::dot(ngw, dir)) / ln);
    float density = 1.f;
    const glm::vec3 &p0 = ob.pos[tri.x], &p1 = ob.pos[tri.y], &p2 = ob.pos[tri.z];
    glm::vec3 e1 = p1 - p0, e2 = p2 - p0;
    const float a_own = glm::length(glm::cross(e1, e2));  // object (dynamic) or world space
    float a_world = a_own;
    if (ob.dynamic) a_world = glm::length(glm::cross(glm::mat3(ob.xf) * e1, glm::mat3(ob.xf) * e2));
    if (!(a_world > 0.f)) return 0.f;
    if (!m.uvs.empty()) {
      const glm::vec2 u1 = m.uvs[tri.y] - m.uvs[tri.x], u2 = m.uvs[tri.z] - m.uvs[tri.x];
      density = std::sqrt(std::fabs(u1.x * u2.y - u1.y * u2.x) / a_world);
    } else if (ob.dynamic) {
      density = std::sqrt(a_own / a_world);
    }
    const float fw = t * cone / std::sqrt(cosn) * density;
    return std::isfinite(fw) ? fw : 0.f;
  }

  // Tangent-space normal map (glTF: texel * 2 - 1, +x along +u, +y towards decreasing v,
  // i.e. up in the image), frame from the triangle's uv gradients, Gram-Schmidt against the
  // interpolated normal n (already facing the viewer); the result is bent to face it too.
  glm::vec3 normal_mapped(const RenderState::Obj& ob, const Mesh& m, const glm::uvec3& tri,
                          const glm::vec3& n, glm::vec2 uv, float fw, const Material& mt) const {
    const glm::vec3 &p0 = ob.pos[tri.x], &p1 = ob.pos[tri.y], &p2 = ob.pos[tri.z];
    const glm::vec2 d1 = m.uvs[tri.y] - m.uvs[tri.x], d2 = m.uvs[tri.z] - m.uvs[tri.x];
    const float det = d1.x * d2.y - d1.y * d2.x;
    if (!(std::fabs(det) > 1e-20f)) return n;
    glm::vec3 T = ((p1 - p0) * d2.y - (p2 - p0) * d1.y) / det;  // dP/du
    glm::vec3 B = ((p2 - p0) * d1.x - (p1 - p0) * d2.x) / det;  // dP/dv
    if (ob.dynamic) {
      T = glm::mat3(ob.xf) * T;
      B = glm::mat3(ob.xf) * B;
    }
    T -= n * glm::dot(n, T);
    const float lt = glm::length(T);
    if (!(lt > 0.f)) return n;
    T /= lt;
    glm::vec3 Bn = glm::cross(n, T);
    if (glm::dot(Bn, B) > 0.f) Bn = -Bn;  // +y of the map points along -dP/dv
    const glm::vec3 t = sample_image(scene.images[size_t(mt.normal_image)], uv, fw) * 2.f - 1.f;
    glm::vec3 r = T * (t.x * mt.normal_scale) + Bn * (t.y * mt.normal_scale) + n * t.z;
    const float lr = glm::length(r);
    return lr > 0.f && std::isfinite(lr) ? r / lr : n;
  }

  // A sample's texture inputs, for a packet's texture loop after its geometry (hit(), finish()).
  using Deferred = TexSample;  // {uv, mat, fw}: eval_albedo_packet's input

  // Whether a packet's hits may take the common path (gather / finish): the channels it writes
  // (not kMotion), and at least one that needs the surface attributes.
  bool fast_channels() const {
    return tab && !(ch & kMotion) && (ch & (kNormal | kAlbedo | kUV | kFootprint));
  }
  // Whether the hit takes the common path: a static object, per-vertex uvs, no normal map.
  // `mat`: the triangle's material.
  bool fast_hit(int obj, uint32_t prim, int& mat) const {
    const HitTable::Obj& t = tab->objs[size_t(obj)];
    mat = t.mat_of[prim & t.mat_mask];
    return t.fast & (tab->plain[size_t(mat)] != 0);
  }
  // The scalar part of hit() for a common-path lane: object, sub-model, material, and Embree's
  // hit and the triangle's vertices, normals and uvs into F; finish() does the rest. `tri`:
  // the triangle's vertex indices (tab->objs[obj].tri[prim], loaded by the caller).
  template <class L>
  void gather(L& F, GBuffer& g, int slot, const glm::vec3& dir, float t, int obj, uint32_t prim,
              const glm::uvec3& tri, float bu, float bv, float cone, int mat, int tex) const {
    const size_t i = size_t(slot);
    const HitTable::Obj& ob = tab->objs[size_t(obj)];
    if (ch & kObjectId) g.object_id[i] = obj;
    if (ch & kSubModel) g.submodel[i] = ob.tri_sub ? ob.tri_sub[prim] : -1;
    if (ch & kMaterial) g.material[i] = mat;
    const int j = F.m++;
    F.slot[j] = slot;
    F.tex[j] = tex;
    F.t[j] = t;
    F.bu[j] = bu;
    F.bv[j] = bv;
    F.dx[j] = dir.x;
    F.dy[j] = dir.y;
    F.dz[j] = dir.z;
    F.cone[j] = cone;
    const glm::vec3 &p0 = ob.pos[tri.x], &p1 = ob.pos[tri.y], &p2 = ob.pos[tri.z];
    F.p0x[j] = p0.x;
    F.p0y[j] = p0.y;
    F.p0z[j] = p0.z;
    F.p1x[j] = p1.x;
    F.p1y[j] = p1.y;
    F.p1z[j] = p1.z;
    F.p2x[j] = p2.x;
    F.p2y[j] = p2.y;
    F.p2z[j] = p2.z;
    const bool hasn = ob.nrm != nullptr;
    F.hasn[j] = hasn ? 1.f : 0.f;
    const glm::vec3 z(0.f);
    const glm::vec3 &n0 = hasn ? ob.nrm[tri.x] : z, &n1 = hasn ? ob.nrm[tri.y] : z,
                    &n2 = hasn ? ob.nrm[tri.z] : z;
    F.n0x[j] = n0.x;
    F.n0y[j] = n0.y;
    F.n0z[j] = n0.z;
    F.n1x[j] = n1.x;
    F.n1y[j] = n1.y;
    F.n1z[j] = n1.z;
    F.n2x[j] = n2.x;
    F.n2y[j] = n2.y;
    F.n2z[j] = n2.z;
    const glm::vec2 &u0 = ob.uv[tri.x], &u1 = ob.uv[tri.y], &u2 = ob.uv[tri.z];
    F.u0x[j] = u0.x;
    F.u0y[j] = u0.y;
    F.u1x[j] = u1.x;
    F.u1y[j] = u1.y;
    F.u2x[j] = u2.x;
    F.u2y[j] = u2.y;
  }
  // hit()'s and footprint()'s operations for the common-path lanes, refine_hit's included
  // (gbuffer_lanes: static objects, world space, ngw = ng, a_world = a_own = |ng|, the same
  // cross product; nv the same dot product as dot(ng, dir)); then the stores.
  template <class L>
  void finish(L& F, GBuffer& g, const glm::vec3& org, Deferred* tex) const {
    gbuffer_lanes(F, org.x, org.y, org.z);
    for (int j = 0; j < F.m; ++j) g.depth[size_t(F.slot[j])] = F.t[j];
    for (int j = 0; j < F.m; ++j) {
      const size_t i = size_t(F.slot[j]);
      if (ch & kPosition) put(g.position[i], glm::vec3(F.Px[j], F.Py[j], F.Pz[j]));
      if (ch & kUV) put(g.uv[i], glm::vec2(F.U[j], F.V[j]));
      if (ch & kFootprint) g.footprint[i] = F.fw[j];
      if (ch & kNormal) put(g.normal[i], glm::vec3(F.Nx[j], F.Ny[j], F.Nz[j]));
      if (F.tex[j] >= 0) {
        tex[F.tex[j]].uv = glm::vec2(F.U[j], F.V[j]);
        tex[F.tex[j]].fw = F.fw[j];
      }
    }
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
    if (ch & kFootprint) g.footprint[i] = 0.f;
  }

  // With `deferred` (a packet's pass), the albedo is not evaluated here: the texture inputs
  // go to deferred->uv / mat and the caller runs eval_albedo for the packet afterwards.
  // `cone`: the sample's ray-cone width in radians (its angular spacing, see cone_width), for
  // the texture footprint.
  void hit(GBuffer& g, size_t i, const glm::vec3& org, const glm::vec3& dir, float t, int obj,
           uint32_t prim, float bu, float bv, const glm::vec2& px, float cone,
           Deferred* deferred = nullptr) const {
    refine_hit(I, scene, obj, prim, org, dir, t, bu, bv);
    g.depth[i] = t;
    if (!(ch & ~kDepth)) return;
    const Object& o = scene.objects[size_t(obj)];
    const Mesh& m = scene.meshes[size_t(o.mesh)];
    const RenderState::Obj& ob = I.objs[size_t(obj)];
    const glm::uvec3 tri = m.triangles[prim];
    const glm::vec3 P = org + t * dir;
    if (ch & kPosition) put(g.position[i], P);
    if (ch & kObjectId) g.object_id[i] = obj;
    if (ch & kSubModel) g.submodel[i] = ob.tri_sub.empty() ? -1 : ob.tri_sub[prim];
    const int mat = m.tri_material.empty() ? m.material : m.tri_material[prim];
    if (ch & kMaterial) g.material[i] = mat;
    const float bw = 1.f - bu - bv;
    const bool need_uv = (ch & (kUV | kAlbedo | kFootprint | kNormal)) != 0;  // normal maps
    glm::vec3 ng(0.f);
    if ((ch & kNormal) || need_uv) {
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
      if (ch & kUV) put(g.uv[i], uv);
    }
    float fw = 0.f;
    if (need_uv) {
      fw = footprint(ob, m, tri, ng, dir, t, cone);
      if (ch & kFootprint) g.footprint[i] = fw;
    }
    if (ch & kAlbedo) {
      if (deferred)
        *deferred = {uv, mat, fw};
      else
        albedo(g, i, uv, mat, fw);
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
      const Material& mt = scene.materials[size_t(mat)];
      if (mt.normal_image >= 0 && size_t(mt.normal_image) < scene.images.size() && !m.uvs.empty())
        n = normal_mapped(ob, m, tri, n, uv, fw, mt);
      // Interpolated normals can still point away from the eye near silhouettes: bend them
      // just past the view-perpendicular so every normal faces the viewer.
      const float nv = glm::dot(n, dir);
      if (nv > 0.f) n = glm::normalize(n - dir * (nv + 1e-3f));
      put(g.normal[i], n);
    }
    if (ch & kMotion) {
      glm::vec2 mv(0.f);
      if (prev) {
        glm::vec3 Pp = ob.dynamic ? xform_point(ob.prev_xf, xform_point(ob.inv, P)) : P;
        glm::dvec2 pp;
        if (prev->project_world(glm::dvec3(Pp), pp)) mv = px - glm::vec2(pp);
      }
      put(g.motion[i], mv);
    }
  }
};

namespace {

// Asks for p's cache line with intent to write (PREFETCHW): the line arrives exclusive, so the
// store that follows needs no second request. GCC emits nothing for __builtin_prefetch(p, 1)
// on the x86-64 baseline (no PRFCHW flag), so the instruction is written out; CPUs without
// PRFCHW execute its opcode (0F 0D /1) as a no-op. A prefetch changes no result.
inline void prefetch_w(const void* p) {
  asm volatile("prefetchw %0" : : "m"(*static_cast<const char*>(p)));
}

// A packet of up to 16 primary rays from one origin (rtcIntersect16). 4x4 pixel blocks are
// the most coherent unit; measured ~15% faster than the rtcIntersect1M stream API here.
struct Packet {
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  size_t idx[16];
  glm::vec2 px[16];
  float cone[16];
  int n = 0;
  // The packet's samples, lane k in slot k, copied to the frame's G-buffer by flush().
  GBuffer st;

  // Fields rtcIntersect16 only reads (tnear, time, mask, id, flags) are set once here; add()
  // writes the rest (Embree writes tfar and the hit fields back).
  explicit Packet(uint32_t channels) {
    st.resize(16, 1, channels);
    for (int k = 0; k < 16; ++k) {
      rh.ray.tnear[k] = 0.f;
      rh.ray.time[k] = 0.f;
      rh.ray.mask[k] = 0xffffffffu;
      rh.ray.id[k] = unsigned(k);
      rh.ray.flags[k] = 0;
    }
  }
  void reset() { n = 0; }
  void add(const glm::vec3& o, const glm::vec3& d, size_t i, glm::vec2 p, float cn) {
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
    cone[k] = cn;
  }
  // Four lanes at once (a row of a 4x4 block): add() for lanes n..n+3 with d = the float
  // rounding of (dx, dy, dz)[j], cone = that of cw[j], sample i + j, screen point
  // (float(x + j) + 0.5, py). cvtpd2ps rounds as the scalar conversion does; the stores are
  // 4 wide instead of 13 scalar ones per lane.
  void add4(const glm::vec3& o, const double* dx, const double* dy, const double* dz,
            const double* cw, size_t i, int x, float py) {
    const int k = n;
    n += 4;
    auto f4 = [](const double* a) {
      return _mm_movelh_ps(_mm_cvtpd_ps(_mm_loadu_pd(a)), _mm_cvtpd_ps(_mm_loadu_pd(a + 2)));
    };
    _mm_store_ps(rh.ray.org_x + k, _mm_set1_ps(o.x));
    _mm_store_ps(rh.ray.org_y + k, _mm_set1_ps(o.y));
    _mm_store_ps(rh.ray.org_z + k, _mm_set1_ps(o.z));
    _mm_store_ps(rh.ray.dir_x + k, f4(dx));
    _mm_store_ps(rh.ray.dir_y + k, f4(dy));
    _mm_store_ps(rh.ray.dir_z + k, f4(dz));
    _mm_store_ps(rh.ray.tfar + k, _mm_set1_ps(kInf));
    const __m128i inv = _mm_set1_epi32(int(RTC_INVALID_GEOMETRY_ID));
    _mm_store_si128(reinterpret_cast<__m128i*>(rh.hit.geomID + k), inv);
    _mm_store_si128(reinterpret_cast<__m128i*>(rh.hit.instID[0] + k), inv);
    _mm_store_si128(reinterpret_cast<__m128i*>(valid + k), _mm_set1_epi32(-1));
    _mm_storeu_ps(cone + k, f4(cw));
    for (int j = 0; j < 4; ++j) {
      idx[k + j] = i + size_t(j);
      px[k + j] = glm::vec2(float(x + j) + 0.5f, py);
    }
  }
  // A full 4x4 block (pixels (x0 + j % 4, y0 + j / 4), sample i0 + (j / 4) * width + j % 4)
  // whose directions and cone widths gbuffer_block_rays wrote to rh.ray.dir_* and cone: the
  // lanes' other fields as add() sets them.
  void add16(const glm::vec3& o, size_t i0, size_t width, int x0, int y0) {
    n = 16;
    const __m128i inv = _mm_set1_epi32(int(RTC_INVALID_GEOMETRY_ID));
    for (int k = 0; k < 16; k += 4) {
      _mm_store_ps(rh.ray.org_x + k, _mm_set1_ps(o.x));
      _mm_store_ps(rh.ray.org_y + k, _mm_set1_ps(o.y));
      _mm_store_ps(rh.ray.org_z + k, _mm_set1_ps(o.z));
      _mm_store_ps(rh.ray.tfar + k, _mm_set1_ps(kInf));
      _mm_store_si128(reinterpret_cast<__m128i*>(rh.hit.geomID + k), inv);
      _mm_store_si128(reinterpret_cast<__m128i*>(rh.hit.instID[0] + k), inv);
      _mm_store_si128(reinterpret_cast<__m128i*>(valid + k), _mm_set1_epi32(-1));
    }
    for (int k = 0; k < 16; ++k) {
      idx[k] = i0 + size_t(k >> 2) * width + size_t(k & 3);
      px[k] = glm::vec2(float(x0 + (k & 3)) + 0.5f, float(y0 + (k >> 2)) + 0.5f);
    }
  }
  // Traces the packet and copies its samples to g (slot idx[k] of g gets lane k).
  void trace(const RenderState& I, const SampleWriter& w, const glm::vec3& o, GBuffer& g) {
    if (n == 0) return;
    prefetch(g, w.ch);
    stage(I, w, o);
    flush(g, w.ch);
    n = 0;
  }

  // Traces the packet (n >= 1 lanes) into the staging buffer st: slot k holds lane k.
  void stage(const RenderState& I, const SampleWriter& w, const glm::vec3& o) {
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
    // Hits on the common path (static, uvs, no normal map) go through gather / finish (the
    // same operations, 4 lanes at a time), the others through hit().
    SampleWriter::Deferred tex[16];
    int hits[16], nh = 0;
    const bool albedo = (w.ch & kAlbedo) != 0;
    const bool fast = w.fast_channels();
    FastLanes F;
    // Each lane's object, material and path first, with no branch on the loaded values (the
    // lanes' chains of dependent loads overlap), then the per-lane work.
    int lane_obj[16], lane_mat[16];
    bool lane_fast[16];
    for (int k = 0; k < n; ++k) {
      lane_obj[k] = -1;
      lane_mat[k] = 0;
      lane_fast[k] = false;
      if (rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) continue;
      RTCHit h;
      h.geomID = rh.hit.geomID[k];
      h.instID[0] = rh.hit.instID[0][k];
      lane_obj[k] = hit_object(I, h);
      lane_fast[k] = fast && w.fast_hit(lane_obj[k], rh.hit.primID[k], lane_mat[k]);
    }
    for (int k = 0; k < n; ++k) {
      if (rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) {
        w.miss(st, size_t(k));
        continue;
      }
      const int obj = lane_obj[k];
      const uint32_t prim = rh.hit.primID[k];
      glm::vec3 d(rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k]);
      const int mat = lane_mat[k];
      if (lane_fast[k]) {
        if (albedo) tex[nh].mat = mat;
        w.gather(F, st, k, d, rh.ray.tfar[k], obj, prim, w.tab->objs[size_t(obj)].tri[prim],
                 rh.hit.u[k], rh.hit.v[k], cone[k], mat, albedo ? nh : -1);
      } else {
        w.hit(st, size_t(k), o, d, rh.ray.tfar[k], obj, prim, rh.hit.u[k], rh.hit.v[k], px[k],
              cone[k], albedo ? &tex[nh] : nullptr);
      }
      hits[nh++] = k;
    }
    if (F.m > 0) w.finish(F, st, o, tex);
    if (albedo && nh > 0) {  // the packet's textures together (eval_albedo_packet)
      TexSample q[16];
      glm::vec3 a[16];
      for (int j = 0; j < nh; ++j) q[j] = {tex[j].uv, tex[j].mat, tex[j].fw};
      eval_albedo_packet(w.scene, I.mat_cs.data(), q, nh, a);
      for (int j = 0; j < nh; ++j) put(st.albedo[size_t(hits[j])], a[j]);
    }
  }

  // Asks for the lines flush() will write, before the traversal (a prefetch changes nothing).
  void prefetch(const GBuffer& g, uint32_t ch) const {
    auto pf = [&](const auto& dst) {
      using T = std::decay_t<decltype(dst[0])>;
      for (int k = 0; k < n;) {
        int j = k + 1;
        while (j < n && idx[j] == idx[j - 1] + 1) ++j;
        const char* a = reinterpret_cast<const char*>(dst.data() + idx[k]);
        for (size_t b = 0; b < size_t(j - k) * sizeof(T); b += 64) prefetch_w(a + b);
        prefetch_w(a + size_t(j - k) * sizeof(T) - 1);
        k = j;
      }
    };
    pf(g.depth);
    if (ch & kPosition) pf(g.position);
    if (ch & kNormal) pf(g.normal);
    if (ch & kAlbedo) pf(g.albedo);
    if (ch & kMaterial) pf(g.material);
    if (ch & kObjectId) pf(g.object_id);
    if (ch & kSubModel) pf(g.submodel);
    if (ch & kMotion) pf(g.motion);
    if (ch & kUV) pf(g.uv);
    if (ch & kFootprint) pf(g.footprint);
  }
  // Copies the staged samples to the G-buffer, one memcpy per run of consecutive indices (a
  // 4x4 block: 4 rows of 4 pixels per channel). Writing the frame's channels directly, sample
  // by sample, cost ~30 ns a ray (measured by redirecting them to a small scratch buffer):
  // each packet touches 4 rows x 5 arrays of lines not yet in the cache with ~180 scalar
  // stores, which likely fill the store buffer while those lines are fetched. Staged, the
  // same bytes leave in a few wide stores per row, to lines prefetch() asked for.
  void flush(GBuffer& g, uint32_t ch) const {
    auto copy = [&](auto& dst, const auto& src) {
      using T = std::decay_t<decltype(src[0])>;
      for (int k = 0; k < n;) {
        int j = k + 1;
        while (j < n && idx[j] == idx[j - 1] + 1) ++j;
        std::memcpy(&dst[idx[k]], &src[size_t(k)], size_t(j - k) * sizeof(T));
        k = j;
      }
    };
    copy(g.depth, st.depth);
    if (ch & kPosition) copy(g.position, st.position);
    if (ch & kNormal) copy(g.normal, st.normal);
    if (ch & kAlbedo) copy(g.albedo, st.albedo);
    if (ch & kMaterial) copy(g.material, st.material);
    if (ch & kObjectId) copy(g.object_id, st.object_id);
    if (ch & kSubModel) copy(g.submodel, st.submodel);
    if (ch & kMotion) copy(g.motion, st.motion);
    if (ch & kUV) copy(g.uv, st.uv);
    if (ch & kFootprint) copy(g.footprint, st.footprint);
  }
};

// One batch of trace_gbuffer's tile pass: whole 4x4 blocks of a tile (a band of its rows, at
// most kBatchLanes rays), traced first, block after block, into per-ray hit arrays; then all
// of the band's hits classified, gathered and given their surface attributes together
// (gbuffer_lanes, 64 lanes at a time: FastBatch), their textures (eval_albedo_packet: each
// block of 16 grouped by material), and the band's samples, staged in pixel order, copied to the
// frame a row at a time. Each sample's operations are those of Packet::stage, so the bits are the
// same. One per thread (allocated when the thread runs its first tile, then reused by every tile
// and frame). Its stages are not inlined (one call per packet or band), so a profile shows each
// apart (bench/profile_gbuffer.sh).
struct TileBatch {
  Packet pk{kDepth};                          // ray generation and rtcIntersect16 of one block
  int n = 0;                                  // rays in the batch
  static constexpr int P = kBatchLanes + 16;  // arrays padded by a line (as FastLanesN)
  // Per ray, in trace order: Embree's hit, the ray and the ray's staging slot (pixel
  // (x0 + slot % bw, y0 + slot / bw) of a band bw pixels wide from (x0, y0)).
  alignas(64) float t[P], u[P], v[P];
  alignas(64) float dx[P], dy[P], dz[P], cone[P];
  alignas(64) uint32_t geom[P], prim[P], inst[P];
  int slot[P];
  // Per ray: object, material and path (the common path: gather / finish).
  int obj[P], mat[P];
  uint8_t fast[P];
  FastBatch F;
  // The hits' texture inputs and staging slots (in hit order), and their albedos.
  SampleWriter::Deferred tex[kBatchLanes];
  int hit_slot[P];
  glm::vec3 alb[kBatchLanes];
  GBuffer st;  // kBatchLanes slots, every channel allocated (writes: w.ch)

  TileBatch() { st.resize(kBatchLanes, 1, ~0u); }

  // Traces pk's lanes and appends their hits; x0, y0: the band's first pixel, bw its width.
  __attribute__((noinline)) void trace(const RenderState& I, int x0, int y0, int bw) {
    Packet& p = pk;
    for (int k = p.n; k < 16; ++k) {  // as Packet::stage: inactive lanes get lane 0's ray
      p.valid[k] = 0;
      p.rh.ray.org_x[k] = p.rh.ray.org_x[0];
      p.rh.ray.org_y[k] = p.rh.ray.org_y[0];
      p.rh.ray.org_z[k] = p.rh.ray.org_z[0];
      p.rh.ray.dir_x[k] = p.rh.ray.dir_x[0];
      p.rh.ray.dir_y[k] = p.rh.ray.dir_y[0];
      p.rh.ray.dir_z[k] = p.rh.ray.dir_z[0];
      p.rh.ray.tfar[k] = kInf;
      p.rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      p.rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = I.packet_flags;
    rtcIntersect16(p.valid, I.top, &ctx, &p.rh);
    // All 16 lanes (the arrays have room past n + 16): fixed-size copies, a few vector moves.
    auto cp = [](auto* dst, const auto* src) { std::memcpy(dst, src, 16 * sizeof(*src)); };
    const int m = p.n;
    cp(t + n, p.rh.ray.tfar);
    cp(u + n, p.rh.hit.u);
    cp(v + n, p.rh.hit.v);
    cp(dx + n, p.rh.ray.dir_x);
    cp(dy + n, p.rh.ray.dir_y);
    cp(dz + n, p.rh.ray.dir_z);
    cp(cone + n, p.cone);
    cp(geom + n, p.rh.hit.geomID);
    cp(prim + n, p.rh.hit.primID);
    cp(inst + n, p.rh.hit.instID[0]);
    for (int k = 0; k < m; ++k) slot[n + k] = (int(p.px[k].y) - y0) * bw + (int(p.px[k].x) - x0);
    n += m;
    p.n = 0;
  }

  // Every sample of the batch into st (slot = pixel of the band), as Packet::stage does it
  // for a packet's lanes. x0, y0, bw as trace().
  __attribute__((noinline)) void shade(const RenderState& I, const SampleWriter& w,
                                       const glm::vec3& o, int x0, int y0, int bw) {
    const bool albedo = (w.ch & kAlbedo) != 0;
    const bool fastch = w.fast_channels();
    for (int k = 0; k < n; ++k) {
      obj[k] = -1;
      mat[k] = 0;
      fast[k] = 0;
      if (geom[k] == RTC_INVALID_GEOMETRY_ID) continue;
      RTCHit h;
      h.geomID = geom[k];
      h.instID[0] = inst[k];
      obj[k] = hit_object(I, h);
      fast[k] = fastch && w.fast_hit(obj[k], prim[k], mat[k]);
    }
    F.m = 0;
    int nh = 0;
    for (int k = 0; k < n; ++k) {
      const int sl = slot[k];
      if (geom[k] == RTC_INVALID_GEOMETRY_ID) {
        w.miss(st, size_t(sl));
        continue;
      }
      const glm::vec3 d(dx[k], dy[k], dz[k]);
      if (fast[k]) {
        if (albedo) tex[nh].mat = mat[k];
        w.gather(F, st, sl, d, t[k], obj[k], prim[k], w.tab->objs[size_t(obj[k])].tri[prim[k]],
                 u[k], v[k], cone[k], mat[k], albedo ? nh : -1);
        if (F.m == FastBatch::kCapacity) {  // a full chunk: its lanes while they are in L1
          w.finish(F, st, o, tex);
          F.m = 0;
        }
      } else {
        const glm::vec2 px(float(x0 + sl % bw) + 0.5f, float(y0 + sl / bw) + 0.5f);
        w.hit(st, size_t(sl), o, d, t[k], obj[k], prim[k], u[k], v[k], px, cone[k],
              albedo ? &tex[nh] : nullptr);
      }
      hit_slot[nh++] = sl;
    }
    if (F.m > 0) w.finish(F, st, o, tex);
    if (albedo && nh > 0) texture(w, nh);
    n = 0;
  }

  // The hits' albedos (eval_albedo_packet groups each block of 16 lookups by material;
  // sorting the band's lookups by material first measured no faster). Each lookup's value
  // depends only on its own inputs.
  __attribute__((noinline)) void texture(const SampleWriter& w, int nh) {
    eval_albedo_packet(w.scene, w.I.mat_cs.data(), tex, nh, alb);
    for (int j = 0; j < nh; ++j) put(st.albedo[size_t(hit_slot[j])], alb[j]);
  }

  // Asks for the lines of row i0 .. i0 + bw of every channel flush() writes (a prefetch
  // changes nothing): one row after each packet of the band, so the lines arrive during the
  // traversal, not while flush() waits for them.
  __attribute__((noinline)) static void prefetch_row(const GBuffer& g, uint32_t ch, size_t i0,
                                                     int bw) {
    auto pf = [&](const auto& dst) {
      using T = std::decay_t<decltype(dst[0])>;
      const char* a = reinterpret_cast<const char*>(dst.data() + i0);
      const size_t bytes = size_t(bw) * sizeof(T);
      for (size_t b = 0; b < bytes; b += 64) prefetch_w(a + b);
      prefetch_w(a + bytes - 1);
    };
    pf(g.depth);
    if (ch & kPosition) pf(g.position);
    if (ch & kNormal) pf(g.normal);
    if (ch & kAlbedo) pf(g.albedo);
    if (ch & kMaterial) pf(g.material);
    if (ch & kObjectId) pf(g.object_id);
    if (ch & kSubModel) pf(g.submodel);
    if (ch & kMotion) pf(g.motion);
    if (ch & kUV) pf(g.uv);
    if (ch & kFootprint) pf(g.footprint);
  }

  // Copies rows [0, rows) of the band (bw samples each) to g from pixel index i0, a row of
  // the frame (width pixels) after another.
  __attribute__((noinline)) void flush(GBuffer& g, uint32_t ch, size_t i0, size_t width, int bw,
                                       int rows) const {
    auto copy = [&](auto& dst, const auto& src) {
      using T = std::decay_t<decltype(src[0])>;
      for (int r = 0; r < rows; ++r)
        std::memcpy(&dst[i0 + size_t(r) * width], &src[size_t(r) * size_t(bw)],
                    size_t(bw) * sizeof(T));
    };
    copy(g.depth, st.depth);
    if (ch & kPosition) copy(g.position, st.position);
    if (ch & kNormal) copy(g.normal, st.normal);
    if (ch & kAlbedo) copy(g.albedo, st.albedo);
    if (ch & kMaterial) copy(g.material, st.material);
    if (ch & kObjectId) copy(g.object_id, st.object_id);
    if (ch & kSubModel) copy(g.submodel, st.submodel);
    if (ch & kMotion) copy(g.motion, st.motion);
    if (ch & kUV) copy(g.uv, st.uv);
    if (ch & kFootprint) copy(g.footprint, st.footprint);
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

// The primary ray through screen point p as the packet's next lane (sample i). trace_points
// and PointPacketTracer both use it: the same operations, so the same bits.
inline void add_point(Packet& pk, const Camera& cam, const glm::dmat3& R, const glm::vec3& org,
                      double cone_s, glm::vec2 p, size_t i) {
  const glm::dvec3 dh = cam.dir_head(p.x, p.y);
  glm::dvec3 d = R * dh;
  pk.add(org, glm::vec3(d), i, p, cone_width(cone_s, -dh.z));
}

}  // namespace

struct PointPacketTracer::Impl {
  const RenderState& I;
  const Camera& cam;
  HitTable tab;
  SampleWriter w;
  glm::vec3 org;
  glm::dmat3 R;
  double cone_s;
  Packet pk;
  Impl(const Scene& scene, const RenderState& I_, const Camera& c, uint32_t channels, float spacing)
      : I(I_),
        cam(c),
        tab(scene, I_),
        w{scene, I_, nullptr, (channels | kDepth) & ~uint32_t(kMotion), &tab},
        org(c.position),
        R(glm::mat3_cast(c.orientation)),
        cone_s(cone_scale(c, spacing)),
        pk(w.ch) {}
};

PointPacketTracer::PointPacketTracer(const Scene& scene, const RenderState& I, const Camera& cam,
                                     uint32_t channels, float spacing)
    : p_(std::make_unique<Impl>(scene, I, cam, channels, spacing)) {}
PointPacketTracer::~PointPacketTracer() = default;
PointPacketTracer::PointPacketTracer(PointPacketTracer&&) noexcept = default;

// The packet's rays as add_point computes them (Camera::dir_head, R * dh, cone_width), two
// lanes at a time in double (SSE2: the same IEEE operations per lane in the same order; the
// normalisation's z * z is (-1) * (-1) = 1 exactly, and -dh.z = s).
typedef double vd __attribute__((vector_size(16)));

const GBuffer& PointPacketTracer::trace(const glm::vec2* pts, int n) {
  Impl& m = *p_;
  m.pk.reset();
  const Camera& c = m.cam;
  const glm::dmat3& R = m.R;
  alignas(16) double px[16], py[16], dx[16], dy[16], dz[16], cs[16];
  for (int k = 0; k < n; ++k) {
    px[k] = double(pts[k].x);
    py[k] = double(pts[k].y);
  }
  if (n & 1) px[n] = py[n] = 0.5;  // a throw-away lane
  const vd one = {1.0, 1.0}, two = {2.0, 2.0};
  const vd W = {double(c.width), double(c.width)}, H = {double(c.height), double(c.height)};
  const vd th = {c.tan_half_h, c.tan_half_h}, tv = {c.tan_half_v, c.tan_half_v};
  const vd cone_s = {m.cone_s, m.cone_s};
  auto sp = [](double v) { return vd{v, v}; };
  for (int k = 0; k < n; k += 2) {
    vd x, y;
    __builtin_memcpy(&x, px + k, sizeof x);
    __builtin_memcpy(&y, py + k, sizeof y);
    x = (two * x / W - one) * th;
    y = (one - two * y / H) * tv;
    const vd s = one / __builtin_ia32_sqrtpd((x * x + y * y) + one);
    const vd hx = x * s, hy = y * s, hz = -s;
    const vd ox = (sp(R[0][0]) * hx + sp(R[1][0]) * hy) + sp(R[2][0]) * hz;
    const vd oy = (sp(R[0][1]) * hx + sp(R[1][1]) * hy) + sp(R[2][1]) * hz;
    const vd oz = (sp(R[0][2]) * hx + sp(R[1][2]) * hy) + sp(R[2][2]) * hz;
    const vd cw = cone_s * s * __builtin_ia32_sqrtpd(s);
    __builtin_memcpy(dx + k, &ox, sizeof ox);
    __builtin_memcpy(dy + k, &oy, sizeof oy);
    __builtin_memcpy(dz + k, &oz, sizeof oz);
    __builtin_memcpy(cs + k, &cw, sizeof cw);
  }
  for (int k = 0; k < n; ++k)
    m.pk.add(m.org, glm::vec3(float(dx[k]), float(dy[k]), float(dz[k])), size_t(k), pts[k],
             float(cs[k]));
  if (n > 0) m.pk.stage(m.I, m.w, m.org);
  m.pk.reset();
  return m.pk.st;
}

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
  std::vector<double> hx(size_t(cam.width) + 1, 0.0), hy(size_t(cam.height));
  std::vector<double> hx2(size_t(cam.width) + 1, 0.0), hy2(size_t(cam.height));
  for (int x = 0; x < cam.width; ++x) {
    hx[size_t(x)] = (2.0 * (x + 0.5) / cam.width - 1.0) * cam.tan_half_h;
    hx2[size_t(x)] = hx[size_t(x)] * hx[size_t(x)];
  }
  for (int y = 0; y < cam.height; ++y) {
    hy[size_t(y)] = (1.0 - 2.0 * (y + 0.5) / cam.height) * cam.tan_half_v;
    hy2[size_t(y)] = hy[size_t(y)] * hy[size_t(y)];
  }
  const HitTable tab(scene_, I);
  SampleWriter w{scene_, I, prev, channels, &tab};
  const double cone1 = cone_scale(cam, 1.f);
  auto sp = [](double v) { return vd{v, v}; };
  const vd one = sp(1.0), cone1v = sp(cone1);
  const vd R00 = sp(R[0][0]), R10 = sp(R[1][0]), R20 = sp(R[2][0]);
  const vd R01 = sp(R[0][1]), R11 = sp(R[1][1]), R21 = sp(R[2][1]);
  const vd R02 = sp(R[0][2]), R12 = sp(R[1][2]), R22 = sp(R[2][2]);
  const double Rc[9] = {R[0][0], R[0][1], R[0][2], R[1][0], R[1][1],
                        R[1][2], R[2][0], R[2][1], R[2][2]};
  // Bands of whole 4x4 blocks, as many rows as fit in a batch (a 32x32 tile is one band).
  const int band = 4 * std::max(1, kBatchLanes / (4 * T));
  tbb::parallel_for(
      tbb::blocked_range<int>(0, tx * ty, 1),
      [&](const tbb::blocked_range<int>& r) {
        static thread_local std::unique_ptr<TileBatch> tls;
        if (!tls) tls = std::make_unique<TileBatch>();
        TileBatch& tb = *tls;
        Packet& pk = tb.pk;
        pk.reset();
        tb.n = 0;
        for (int tile = r.begin(); tile != r.end(); ++tile) {
          const int x0 = (tile % tx) * T, ty0 = (tile / tx) * T;
          const int x1 = std::min(x0 + T, cam.width), ty1 = std::min(ty0 + T, cam.height);
          const int bw = x1 - x0;
          for (int y0 = ty0; y0 < ty1; y0 += band) {
            const int y1 = std::min(y0 + band, ty1);
            int pf_row = y0;  // the next row to prefetch (TileBatch::prefetch_row)
            auto traced = [&] {
              if (pf_row < y1)
                TileBatch::prefetch_row(out, w.ch,
                                        size_t(pf_row++) * size_t(cam.width) + size_t(x0), bw);
            };
            for (int by = y0; by < y1; by += 4)
              for (int bx = x0; bx < x1; bx += 4) {
                if (bx + 4 <= x1 && by + 4 <= y1) {  // a full block: 16 lanes at once
                  gbuffer_block_rays(&hx[size_t(bx)], &hx2[size_t(bx)], &hy[size_t(by)],
                                     &hy2[size_t(by)], Rc, cone1, pk.rh.ray.dir_x, pk.rh.ray.dir_y,
                                     pk.rh.ray.dir_z, pk.cone);
                  pk.add16(org, size_t(by) * size_t(cam.width) + size_t(bx), size_t(cam.width), bx,
                           by);
                  tb.trace(I, x0, y0, bw);
                  traced();
                  continue;
                }
                for (int y = by; y < std::min(by + 4, y1); ++y) {
                  // == Camera::dir_world(x + 0.5, y + 0.5) and cone_width(cone1, s), two
                  // pixels at a time in double (SSE2, the same operations per lane; hx, hx2
                  // are padded so the pair past the right edge reads valid, unused values).
                  const int xe = std::min(bx + 4, x1);
                  const vd hyv = sp(hy[size_t(y)]), hy2v = sp(hy2[size_t(y)]);
                  alignas(16) double dx[4], dy[4], dz[4], cw[4];
                  for (int x = bx; x < xe; x += 2) {
                    vd hxv, hx2v;
                    __builtin_memcpy(&hxv, &hx[size_t(x)], sizeof hxv);
                    __builtin_memcpy(&hx2v, &hx2[size_t(x)], sizeof hx2v);
                    const vd s = one / __builtin_ia32_sqrtpd((hx2v + hy2v) + one);
                    const vd ux = hxv * s, uy = hyv * s, uz = -s;
                    const vd ox = (R00 * ux + R10 * uy) + R20 * uz;
                    const vd oy = (R01 * ux + R11 * uy) + R21 * uz;
                    const vd oz = (R02 * ux + R12 * uy) + R22 * uz;
                    const vd c = cone1v * s * __builtin_ia32_sqrtpd(s);
                    const int j = x - bx;
                    __builtin_memcpy(dx + j, &ox, sizeof ox);
                    __builtin_memcpy(dy + j, &oy, sizeof oy);
                    __builtin_memcpy(dz + j, &oz, sizeof oz);
                    __builtin_memcpy(cw + j, &c, sizeof c);
                  }
                  if (xe - bx == 4) {
                    pk.add4(org, dx, dy, dz, cw, size_t(y) * size_t(cam.width) + size_t(bx), bx,
                            float(y) + 0.5f);
                    continue;
                  }
                  for (int x = bx; x < xe; ++x) {
                    const int j = x - bx;
                    pk.add(org, glm::vec3(float(dx[j]), float(dy[j]), float(dz[j])),
                           size_t(y) * size_t(cam.width) + size_t(x),
                           glm::vec2(float(x) + 0.5f, float(y) + 0.5f), float(cw[j]));
                  }
                }
                tb.trace(I, x0, y0, bw);
                traced();
              }
            tb.shade(I, w, org, x0, y0, bw);
            tb.flush(out, w.ch, size_t(y0) * size_t(cam.width) + size_t(x0), size_t(cam.width), bw,
                     y1 - y0);
          }
        }
      },
      tbb::simple_partitioner());
  const double n = double(cam.width) * double(cam.height);
  rays_ += uint64_t(n);
  if (c) c->add(Counter::primary_rays, n);
}

void Renderer::trace_points(const Camera& cam, const std::vector<glm::vec2>& pts_in,
                            uint32_t channels, GBuffer& out, Counters* c, float spacing) const {
  const RenderState& I = *impl_;
  channels |= kDepth;
  const int n_pts = int(pts_in.size());
  if (out.width != n_pts || out.height != 1 || out.channels != channels)
    out.resize(n_pts, 1, channels);
  const glm::vec3 org(cam.position);
  const glm::dmat3 R = glm::mat3_cast(cam.orientation);
  const HitTable tab(scene_, I);
  SampleWriter w{scene_, I, nullptr, channels & ~uint32_t(kMotion), &tab};
  const double cone_s = cone_scale(cam, spacing);
  if (channels & kMotion)
    for (auto& m : out.motion) m = glm::vec2(0.f);
  // Consecutive points in packets of 16 (callers usually pass them in scanline order).
  const int B = 256;
  tbb::parallel_for(
      tbb::blocked_range<int>(0, (n_pts + B - 1) / B, 1),
      [&](const tbb::blocked_range<int>& r) {
        Packet pk(w.ch);
        for (int b = r.begin(); b != r.end(); ++b) {
          const int i0 = b * B, i1 = std::min(n_pts, i0 + B);
          for (int i = i0; i < i1; ++i) {
            add_point(pk, cam, R, org, cone_s, pts_in[size_t(i)], size_t(i));
            if (pk.n == 16) pk.trace(I, w, org, out);
          }
          pk.trace(I, w, org, out);
        }
      },
      tbb::simple_partitioner());
  rays_ += uint64_t(n_pts);
  if (c) c->add(Counter::primary_rays, double(n_pts));
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
    w.hit(g, 0, org, dir, rh.ray.tfar, obj, rh.hit.primID, rh.hit.u, rh.hit.v, glm::vec2(0.f), 0.f);
    if (normal) *normal = g.normal[0];
    if (uv) *uv = g.uv[0];
  }
  return rh.ray.tfar;
}

}  // namespace fovsim
