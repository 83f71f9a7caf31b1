// Shading (docs/architecture.md "Rendering and the shared reference"): ambient + emission, Lambert
// + Blinn-Phong per light, shadow rays as rtcOccluded16 packets with a portable occlusion decision
// (occlusion_filter), the lights of a packet computed 4 lanes at a time (shade_packet).
// Deterministic per sample: no sampling, the same bits at any thread count.
#include <tbb/parallel_for.h>

#include "sim/core/powf_det.h"
#include "sim/render/render_internal.h"
#include "sim/render/vec4.h"

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
    const glm::vec3 org(oc->org_x[id], oc->org_y[id], oc->org_z[id]);
    const glm::vec3 dir(oc->dir_x[id], oc->dir_y[id], oc->dir_z[id]);
    refine_hit(*oc->I, *oc->scene, obj, prim, org, dir, t, u, v);
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
  oc.org_x[0] = o.x;
  oc.org_y[0] = o.y;
  oc.org_z[0] = o.z;
  oc.dir_x[0] = d.x;
  oc.dir_y[0] = d.y;
  oc.dir_z[0] = d.z;
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
    brdf += glm::vec3(sp.m->specular * spec_pow(ndh, sp.m->shininess));
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

// 4-float helpers (vf, ld4, st4, splat, vsqrt, ...): sim/render/vec4.h.

// The same for up to 16 samples at once, with one rtcOccluded16 packet per light (shadow
// rays from neighbouring samples towards one light are coherent). The lanes' surfaces are read
// into per-component arrays (surface(), scalar: the G-buffer reads go through the view), then
// every light's geometry (light_geom), the shadow-ray fields and the BRDF (light_value) run 4
// lanes at a time with light_geom's and light_value's operations in their order; only the power
// stays scalar, on the lanes the light reaches. Inactive lanes (past n, misses, early returns
// of light_geom) compute throw-away values that are never selected. Each lane's colour adds the
// lights in order, as shade_one does, so both give the same bits.
// Long because: it is the shading hot path, and its lanes' arrays (positions, normals, albedo,
// view vectors, colours, activity) live on its stack for the whole packet; split into functions,
// they would be passed as a dozen pointers per call or spilled into a struct, and the order of
// floating-point operations that makes it bit-identical to shade_one would no longer read in one
// place. Its stages are marked inside: the per-packet ray fields, then per light its geometry,
// the shadow packet and the BRDF (light_value).
void shade_packet(const Scene& scene, const RenderState& I, bool shadows, const GBufferRef& g,
                  const size_t* idx, int n, const glm::vec3& eye, float* out, uint64_t& shadow_rays,
                  ShadeScratch& scratch) {
  (void)scratch;
  alignas(16) float Px[16], Py[16], Pz[16], Nx[16], Ny[16], Nz[16], Ax[16], Ay[16], Az[16];
  alignas(16) float Vx[16], Vy[16], Vz[16], Cx[16], Cy[16], Cz[16], spec[16], shin[16];
  alignas(16) int32_t act[16];
  const float eps = 2e-4f * I.scene_scale;
  const float off = 2e-4f * I.scene_scale;  // surface(): O = P + N * off
  for (int k = 0; k < 16; ++k) {
    SurfacePoint sp;
    glm::vec3 c(0.f);
    const bool on = k < n && surface(scene, I, g, idx[k], eye, sp, c);
    act[k] = on ? -1 : 0;
    Px[k] = on ? sp.P.x : 0.f;
    Py[k] = on ? sp.P.y : 0.f;
    Pz[k] = on ? sp.P.z : 0.f;
    Nx[k] = on ? sp.N.x : 0.f;
    Ny[k] = on ? sp.N.y : 0.f;
    Nz[k] = on ? sp.N.z : 0.f;
    Ax[k] = on ? sp.A.x : 0.f;
    Ay[k] = on ? sp.A.y : 0.f;
    Az[k] = on ? sp.A.z : 0.f;
    Cx[k] = c.x;
    Cy[k] = c.y;
    Cz[k] = c.z;
    spec[k] = on && sp.m ? sp.m->specular : 0.f;
    shin[k] = on && sp.m ? sp.m->shininess : 0.f;
  }
  alignas(64) RTCRay16 ray;
  alignas(64) int valid[16];
  OcclusionContext oc;
  oc.I = &I;
  oc.scene = &scene;
  const float slack = occlusion_slack(I);
  // The fields that do not depend on the light, once per packet (rtcOccluded16 writes tfar only).
  // Inactive lanes get a harmless ray too (Debian's Embree asserts on all lanes' fields).
  const vf ex = splat(eye.x), ey = splat(eye.y), ez = splat(eye.z), voff = splat(off);
  for (int o = 0; o < 16; o += 4) {
    const vi on = ldi4(act + o);
    const vf px = ld4(Px + o), py = ld4(Py + o), pz = ld4(Pz + o);
    // V = normalize(eye - P) = v * (1 / sqrt((x x + y y) + z z)) (glm), O = P + N * off.
    const vf vx = ex - px, vy = ey - py, vz = ez - pz;
    const vf iv = splat(1.f) / vsqrt((vx * vx + vy * vy) + vz * vz);
    st4(Vx + o, vx * iv);
    st4(Vy + o, vy * iv);
    st4(Vz + o, vz * iv);
    const vf zero = splat(0.f);
    const vf ox = on ? px + ld4(Nx + o) * voff : zero;
    const vf oy = on ? py + ld4(Ny + o) * voff : zero;
    const vf oz = on ? pz + ld4(Nz + o) * voff : zero;
    st4(ray.org_x + o, ox);
    st4(ray.org_y + o, oy);
    st4(ray.org_z + o, oz);
    st4(oc.org_x + o, ox);
    st4(oc.org_y + o, oy);
    st4(oc.org_z + o, oz);
    st4(ray.tnear + o, zero);
    st4(ray.time + o, zero);
    st4(oc.tnear + o, zero);
  }
  for (int k = 0; k < 16; ++k) {
    ray.mask[k] = 0xffffffffu;
    ray.id[k] = unsigned(k);
    ray.flags[k] = 0;
  }
  for (const LightNow& l : I.lights) {
    const bool directional = l.type == Light::Type::Directional;
    const bool spot = l.type == Light::Type::Spot;
    const bool test = shadows && l.shadows;
    alignas(16) float Ex[16], Ey[16], Ez[16], ndl[16];
    alignas(16) int32_t lit[16];
    int tests = 0;
    const vf inf = splat(kInf), zero = splat(0.f), one = splat(1.f);
    for (int o = 0; o < 16; o += 4) {
      vi ok = ldi4(act + o);
      vf lx, ly, lz, e_x, e_y, e_z, tfar;
      if (directional) {
        lx = splat(-l.dir.x);
        ly = splat(-l.dir.y);
        lz = splat(-l.dir.z);
        e_x = splat(l.radiance.x);
        e_y = splat(l.radiance.y);
        e_z = splat(l.radiance.z);
        tfar = inf;
      } else {
        const vf dx = splat(l.pos.x) - ld4(Px + o), dy = splat(l.pos.y) - ld4(Py + o),
                 dz = splat(l.pos.z) - ld4(Pz + o);
        const vf r2 = (dx * dx + dy * dy) + dz * dz;
        ok &= r2 > zero;
        const vf dist = vsqrt(r2);
        lx = dx / dist;
        ly = dy / dist;
        lz = dz / dist;
        e_x = splat(l.radiance.x) / r2;
        e_y = splat(l.radiance.y) / r2;
        e_z = splat(l.radiance.z) / r2;
        if (spot) {
          // smooth01(cos_outer, cos_inner, dot(-L, dir))
          const vf x = ((-lx) * splat(l.dir.x) + (-ly) * splat(l.dir.y)) + (-lz) * splat(l.dir.z);
          vf f;
          if (l.cos_inner <= l.cos_outer) {
            f = x >= splat(l.cos_inner) ? one : zero;
          } else {
            vf t = (x - splat(l.cos_outer)) / splat(l.cos_inner - l.cos_outer);
            t = t < zero ? zero : (t > one ? one : t);  // clamp01
            f = t * t * (splat(3.f) - splat(2.f) * t);
          }
          ok &= ~(f <= zero);
          e_x *= f;
          e_y *= f;
          e_z *= f;
        }
        // tfar = isinf(dist) ? inf : max(0, dist - 2 eps) (max(0, inf - c) is inf too).
        const vf y = dist - splat(2.f * eps);
        tfar = zero < y ? y : zero;
      }
      const vf nd = (ld4(Nx + o) * lx + ld4(Ny + o) * ly) + ld4(Nz + o) * lz;
      ok &= ~(nd <= zero);
      st4(Ex + o, e_x);
      st4(Ey + o, e_y);
      st4(Ez + o, e_z);
      st4(ndl + o, nd);
      sti4(lit + o, ok);
      // Lanes the light does not reach keep a harmless direction (light_geom's default).
      const vf dirx = ok ? lx : zero, diry = ok ? ly : one, dirz = ok ? lz : zero;
      st4(ray.dir_x + o, dirx);
      st4(ray.dir_y + o, diry);
      st4(ray.dir_z + o, dirz);
      st4(oc.dir_x + o, dirx);
      st4(oc.dir_y + o, diry);
      st4(oc.dir_z + o, dirz);
      const vi sh = test ? ok : vi{0, 0, 0, 0};
      st4(ray.tfar + o, sh ? tfar + splat(slack) : inf);
      st4(oc.tfar + o, sh ? tfar : inf);
      sti4(valid + o, sh);
    }
    if (test) {
      for (int k = 0; k < 16; ++k) tests += valid[k] != 0;
      if (tests > 0) {
        shadow_rays += uint64_t(tests);
        rtcInitIntersectContext(&oc.ctx);
        oc.ctx.flags = I.packet_flags;
        rtcOccluded16(valid, I.top, &oc.ctx, &ray);
        for (int k = 0; k < 16; ++k)
          if (valid[k] && ray.tfar[k] < 0.f) lit[k] = 0;
      }
    }
    // light_value: brdf = A (+ ks (n.h)^s where the material is specular), times E, times
    // ndl; added where the light arrives. The power (spec_pow, powf_det.h) per lane, only where
    // lit and specular.
    for (int o = 0; o < 16; o += 4) {
      const vi on = ldi4(lit + o);
      if (!(on[0] | on[1] | on[2] | on[3])) continue;
      const vf lx = ld4(ray.dir_x + o), ly = ld4(ray.dir_y + o), lz = ld4(ray.dir_z + o);
      const vf hx = lx + ld4(Vx + o), hy = ly + ld4(Vy + o), hz = lz + ld4(Vz + o);
      const vf ih = one / vsqrt((hx * hx + hy * hy) + hz * hz);
      const vf ndh0 = (ld4(Nx + o) * (hx * ih) + ld4(Ny + o) * (hy * ih)) + ld4(Nz + o) * (hz * ih);
      const vf ndh = zero < ndh0 ? ndh0 : zero;  // std::max(0, ndh)
      const vf ks = ld4(spec + o);
      const vi specular = on & (ks > zero);
      vf s = zero;
      for (int j = 0; j < 4; ++j)
        if (specular[j]) s[j] = ks[j] * spec_pow(ndh[j], shin[o + j]);
      vf bx = ld4(Ax + o), by = ld4(Ay + o), bz = ld4(Az + o);
      bx = specular ? bx + s : bx;
      by = specular ? by + s : by;
      bz = specular ? bz + s : bz;
      const vf nd = ld4(ndl + o);
      const vf cx = ld4(Cx + o), cy = ld4(Cy + o), cz = ld4(Cz + o);
      st4(Cx + o, on ? cx + (bx * ld4(Ex + o)) * nd : cx);
      st4(Cy + o, on ? cy + (by * ld4(Ey + o)) * nd : cy);
      st4(Cz + o, on ? cz + (bz * ld4(Ez + o)) * nd : cz);
    }
  }
  for (int k = 0; k < n; ++k) {
    float* o = out + idx[k] * 3;
    o[0] = Cx[k];
    o[1] = Cy[k];
    o[2] = Cz[k];
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
  FOVSIM_CHECK(g.g->has(kShadingChannels),
               "Renderer::shade needs a G-buffer with depth, position, normal, albedo, material");
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
    c->add(Counter::shaded_samples, double(ss));
    c->add(Counter::shadow_rays, double(sr));
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
