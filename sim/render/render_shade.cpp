// Shading (DESIGN §4): ambient + emission, Lambert + Blinn-Phong per light, shadow rays as
// rtcOccluded16 packets with a portable occlusion decision (occlusion_filter). Deterministic
// per sample: no sampling, the same bits at any thread count.
#include <tbb/parallel_for.h>

#include "sim/render/render_internal.h"

namespace fovsim {

// Without a cut-out material and with an interval [tnear <= 0, +inf] (directional lights) the
// refined hit cannot change the decision, so it is not computed: refine_hit either leaves
// Embree's t (accepted here only when t >= 0) or sets t = float(tt) with tt >= 0 and finite;
// either way tnear <= 0 <= t < inf = tfar, and alpha_rejects is false for every triangle of the
// geometry. The same hits are accepted as with the refinement, so the same bits.
void occlusion_filter(const RTCFilterFunctionNArguments* args) {
  const auto* oc = reinterpret_cast<const OcclusionContext*>(args->context);
  const auto* gu = static_cast<const RenderState::GeomUser*>(args->geometryUserPtr);
  const int obj = gu->object;
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned id = RTCRayN_id(args->ray, args->N, i);
    float t = RTCRayN_tfar(args->ray, args->N, i);
    if (!gu->cutout && oc->tfar[id] == kInf && !(oc->tnear[id] > 0.f) && t >= 0.f) continue;
    const uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
    float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    refine_hit(*oc->I, *oc->scene, obj, prim, oc->org[id], oc->dir[id], t, u, v);
    if (!(t >= oc->tnear[id] && t <= oc->tfar[id]) ||
        alpha_rejects(*oc->I, *oc->scene, obj, prim, u, v))
      args->valid[i] = 0;
  }
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

// The geometric part of light_term: direction L, irradiance E (before the cosine), cosine ndl
// and the shadow interval; the same return values. L is set as light_term sets it (also on
// some early returns: shade_packet hands every lane's L to Embree, used or not).
inline int light_geom(const LightNow& l, const SurfacePoint& sp, bool shadows, float eps,
                      glm::vec3& L, glm::vec3& E, float& ndl, float& tfar) {
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
  ndl = glm::dot(sp.N, L);
  if (ndl <= 0.f) return 0;
  if (!(shadows && l.shadows)) return 1;
  tfar = std::isinf(dist) ? kInf : std::max(0.f, dist - 2.f * eps);
  return 2;
}

// The BRDF part: (albedo + ks (n.h)^s) * E * ndl.
inline glm::vec3 light_value(const SurfacePoint& sp, const glm::vec3& L, const glm::vec3& E,
                             float ndl) {
  glm::vec3 brdf = sp.A;
  if (sp.m && sp.m->specular > 0.f) {
    glm::vec3 H = glm::normalize(L + sp.V);
    float ndh = std::max(0.f, glm::dot(sp.N, H));
    brdf += glm::vec3(sp.m->specular * std::pow(ndh, sp.m->shininess));
  }
  return brdf * E * ndl;
}

inline int light_term(const LightNow& l, const SurfacePoint& sp, bool shadows, float eps,
                      glm::vec3& contrib, glm::vec3& L, float& tfar) {
  glm::vec3 E;
  float ndl;
  const int k = light_geom(l, sp, shadows, eps, L, E, ndl, tfar);
  if (k != 0) contrib = light_value(sp, L, E, ndl);
  return k;
}

// Component-wise store (see surface()).
inline void put3(glm::vec3& d, const glm::vec3& v) {
  d.x = v.x;
  d.y = v.y;
  d.z = v.z;
}

// Ambient + emission, and the surface frame for the lights. False on a miss. Slot i of the
// view reads sample g.src(i) of the G-buffer (the same values a copied buffer would hold).
inline bool surface(const Scene& scene, const RenderState& I, const GBufferRef& g, size_t i,
                    const glm::vec3& eye, SurfacePoint& sp, glm::vec3& base) {
  if (!g.hit(i)) {
    base = scene.background;
    return false;
  }
  const GBuffer& b = *g.g;
  const size_t s = g.src(i);
  // Channels read one float at a time into locals and V, O computed from those: copying a
  // glm::vec3 into sp and reading it back for V and O made GCC reload 8 bytes across two
  // narrower stores, a failed store-to-load forward (perf: ~12% of shade_packet's samples on
  // those two reloads). Same values, same operations.
  const glm::vec3 P(b.position[s].x, b.position[s].y, b.position[s].z);
  const glm::vec3 N(b.normal[s].x, b.normal[s].y, b.normal[s].z);
  const glm::vec3 A(b.albedo[s].x, b.albedo[s].y, b.albedo[s].z);
  const int mi = b.material[s];
  sp.m = (mi >= 0 && size_t(mi) < scene.materials.size()) ? &scene.materials[size_t(mi)] : nullptr;
  glm::vec3 c = scene.ambient * A;
  if (sp.m) c += sp.m->emission;
  const glm::vec3 V = glm::normalize(eye - P);
  const glm::vec3 O = P + N * (2e-4f * I.scene_scale);
  put3(sp.P, P);
  put3(sp.N, N);
  put3(sp.A, A);
  put3(sp.V, V);
  put3(sp.O, O);
  put3(base, c);
  return true;
}

// Direct lighting of one sample with single shadow rays (deterministic: no sampling).
static glm::vec3 shade_one(const Scene& scene, const RenderState& I, bool shadows,
                           const GBufferRef& g, size_t i, const glm::vec3& eye,
                           uint64_t* shadow_rays) {
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
void shade_packet(const Scene& scene, const RenderState& I, bool shadows, const GBufferRef& g,
                  const size_t* idx, int n, const glm::vec3& eye, float* out, uint64_t& shadow_rays,
                  ShadeScratch& scratch) {
  std::vector<glm::vec3>& contrib = scratch.contrib;
  std::vector<uint8_t>& state = scratch.state;
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
  // The fields that do not depend on the light, once per packet (rtcOccluded16 writes tfar only).
  // Inactive lanes get a harmless ray too (Debian's Embree asserts on all lanes' fields).
  for (int k = 0; k < 16; ++k) {
    const bool on = k < n && hit[k];
    const float ox = on ? sp[k].O.x : 0.f, oy = on ? sp[k].O.y : 0.f, oz = on ? sp[k].O.z : 0.f;
    ray.org_x[k] = ox;
    ray.org_y[k] = oy;
    ray.org_z[k] = oz;
    ray.tnear[k] = 0.f;
    ray.time[k] = 0.f;
    ray.mask[k] = 0xffffffffu;
    ray.id[k] = unsigned(k);
    ray.flags[k] = 0;
    oc.org[k].x = ox;
    oc.org[k].y = oy;
    oc.org[k].z = oz;
    oc.tnear[k] = 0.f;
  }
  for (size_t li = 0; li < nl; ++li) {
    const LightNow& l = I.lights[li];
    glm::vec3 E[16];
    float ndl[16];
    int tests = 0;
    for (int k = 0; k < 16; ++k) {
      uint8_t st = 0;
      glm::vec3 L(0.f, 1.f, 0.f);
      float tfar = kInf;
      if (k < n && hit[k]) st = uint8_t(light_geom(l, sp[k], shadows, eps, L, E[k], ndl[k], tfar));
      state[size_t(k) * nl + li] = st;
      ray.dir_x[k] = L.x;
      ray.dir_y[k] = L.y;
      ray.dir_z[k] = L.z;
      ray.tfar[k] = st == 2 ? tfar + slack : kInf;
      // Component-wise: a glm::vec3 copy goes through a stack slot whose 8-byte reload waits
      // for its 4-byte stores (render_trace.cpp's put()).
      oc.dir[k].x = L.x;
      oc.dir[k].y = L.y;
      oc.dir[k].z = L.z;
      oc.tfar[k] = st == 2 ? tfar : kInf;
      valid[k] = st == 2 ? -1 : 0;
      tests += st == 2;
    }
    if (tests > 0) {
      shadow_rays += uint64_t(tests);
      rtcInitIntersectContext(&oc.ctx);
      oc.ctx.flags = I.packet_flags;
      rtcOccluded16(valid, I.top, &oc.ctx, &ray);
      for (int k = 0; k < n; ++k)
        if (state[size_t(k) * nl + li] == 2 && ray.tfar[k] < 0.f) state[size_t(k) * nl + li] = 0;
    }
    // The BRDF (its powf) only where the light arrives; the same operations as light_term.
    for (int k = 0; k < n; ++k)
      if (state[size_t(k) * nl + li]) {
        const glm::vec3 L(ray.dir_x[k], ray.dir_y[k], ray.dir_z[k]);
        const glm::vec3 v = light_value(sp[k], L, E[k], ndl[k]);
        glm::vec3& d = contrib[size_t(k) * nl + li];
        d.x = v.x;
        d.y = v.y;
        d.z = v.z;
      }
  }
  for (int k = 0; k < n; ++k) {
    glm::vec3 c = col[k];
    if (hit[k])
      for (size_t li = 0; li < nl; ++li)
        if (state[size_t(k) * nl + li]) c += contrib[size_t(k) * nl + li];
    float* o = out + idx[k] * 3;
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

// Through an index view the channel reads are scattered over the full-res G-buffer (KFR's
// LP-buffer: about 15% more shading time than from a compact copy at 1440x1600, see
// bench/README.md); software prefetching of the next block's sources did not measurably help.
void Renderer::shade(GBufferRef g, const glm::dvec3& eye_d, Image& out, const uint8_t* mask,
                     Counters* c) const {
  if (!g.g->has(kShadingChannels))
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
        ShadeScratch scratch;
        size_t idx[16];
        for (size_t b = r.begin(); b != r.end(); ++b) {
          uint64_t sr = 0, ss = 0;
          int k = 0;
          for (size_t i = b * B, e = std::min(n, i + B); i < e; ++i) {
            if (mask && !mask[i]) continue;
            idx[k++] = i;
            ++ss;
            if (k == 16) {
              shade_packet(scene_, *impl_, settings_.shadows, g, idx, k, eye, out.data.data(), sr,
                           scratch);
              k = 0;
            }
          }
          if (k)
            shade_packet(scene_, *impl_, settings_.shadows, g, idx, k, eye, out.data.data(), sr,
                         scratch);
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

}  // namespace fovsim
