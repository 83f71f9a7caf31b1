// Frame VPLs, the VPL shading loop and the lighting-strategy table (lighting.h).
#include "sim/foveation/lighting.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>

#include "sim/core/error.h"
#include "sim/core/lane_choice.h"  // FOVSIM_HAVE_AVX2_PATH
#include "sim/foveation/method.h"
#include "sim/foveation/simd_kernels.h"
#include "sim/render/renderer.h"

namespace fovsim {
namespace {

#define FOVSIM_KERNEL(name) name##_generic
#define FOVSIM_KERNEL_ATTR
#include "sim/foveation/vpl_kernels.inc"
#undef FOVSIM_KERNEL
#undef FOVSIM_KERNEL_ATTR
#if FOVSIM_HAVE_AVX2_PATH
#define FOVSIM_KERNEL(name) name##_avx2
#define FOVSIM_KERNEL_ATTR __attribute__((target("avx2")))
#include "sim/foveation/vpl_kernels.inc"
#undef FOVSIM_KERNEL
#undef FOVSIM_KERNEL_ATTR
#endif

using VplSumFn = void (*)(const VplSoA&, const float*, float, float*);
VplSumFn vpl_sum_fn() {
#if FOVSIM_HAVE_AVX2_PATH
  if (simd_path() == SimdPath::Avx2) return vpl_sum_avx2;
#endif
  return vpl_sum_generic;
}

}  // namespace

void build_frame_vpls(const Renderer& r, FrameVpls& out, Counters* c) {
  const Scene& scene = r.scene();
  const AABB bounds = scene_bounds(r);
  out.scene_diag = bounds.empty() ? 1.f : std::max(1e-6f, glm::length(bounds.hi - bounds.lo));
  out.rsms.resize(scene.lights.size());
  out.vpls.clear();
  for (size_t li = 0; li < scene.lights.size(); ++li) {
    render_rsm(r, int(li), scene.vpl.rsm_size, bounds, out.rsms[li], c);
    vpls_from_rsm(out.rsms[li], out.vpls);
  }
  out.all.clear();
  for (const VPL& v : out.vpls) out.all.push(v, 1.f);
  out.shading = VplShading();
  out.shading.min_dist = float(scene.vpl.min_dist) * out.scene_diag;
  out.shading.visibility = scene.vpl.shadow_rays;
  out.shading.ray_offset = 1e-4f * out.scene_diag;
}

namespace {
inline glm::vec3 shade_with(VplSumFn fn, const VplSoA& v, const glm::vec3& p, const glm::vec3& n,
                            const glm::vec3& a, const VplShading& s, const Renderer* r, float scale,
                            uint64_t* rays) {
  if ((s.visibility && r) || v.size() == 0) return shade_vpls_point(v, p, n, a, s, r, scale, rays);
  const float q[6] = {p.x, p.y, p.z, n.x, n.y, n.z};
  float rgb[3];
  fn(v, q, s.min_dist * s.min_dist, rgb);
  return a * glm::vec3(rgb[0], rgb[1], rgb[2]) * scale;
}
}  // namespace

glm::vec3 shade_vpls(const VplSoA& v, const glm::vec3& p, const glm::vec3& n, const glm::vec3& a,
                     const VplShading& s, const Renderer* r, float scale, uint64_t* rays) {
  return shade_with(vpl_sum_fn(), v, p, n, a, s, r, scale, rays);
}

void add_indirect(GBufferRef g, const VplSoA& v, const VplShading& s, const Renderer* r,
                  const uint8_t* mask, Image& col, Counters* c) {
  FOVSIM_CHECK(col.width == g.width && col.height == g.height && col.channels == 3,
               "add_indirect: colour buffer does not match the G-buffer");
  std::atomic<uint64_t> shaded{0}, rays{0};
  const size_t N = g.size();
  const VplSumFn fn = vpl_sum_fn();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, N, 1024),
                    [&](const tbb::blocked_range<size_t>& b) {
                      uint64_t ns = 0, nr = 0;
                      for (size_t i = b.begin(); i < b.end(); ++i) {
                        if ((mask && !mask[i]) || !g.hit(i)) continue;
                        const size_t si = g.src(i);
                        const glm::vec3 L = shade_with(fn, v, g.g->position[si], g.g->normal[si],
                                                       g.g->albedo[si], s, r, 1.f, &nr);
                        float* o = &col.data[i * 3];
                        o[0] += L.x;
                        o[1] += L.y;
                        o[2] += L.z;
                        ++ns;
                      }
                      shaded += ns;
                      rays += nr;
                    });
  if (c) {
    c->add(Counter::shaded_sample_vpls, double(shaded.load()) * double(v.size()));
    if (s.visibility) c->add(Counter::vpl_shadow_rays, double(rays.load()));
  }
}

bool cache_all_indirect(const GBuffer& g, const Renderer* r, FrameVpls& vp) {
  vp.all_indirect_of = nullptr;
  if (vp.shading.visibility) {
    vp.all_indirect.data.clear();
    vp.all_indirect.width = vp.all_indirect.height = 0;
    return false;
  }
  Image& ind = vp.all_indirect;
  if (ind.width != g.width || ind.height != g.height || ind.channels != 3)
    ind.resize(g.width, g.height, 3);
  const VplSumFn fn = vpl_sum_fn();
  const size_t N = g.size();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, N, 1024),
                    [&](const tbb::blocked_range<size_t>& b) {
                      uint64_t no_rays = 0;  // visibility is off: no shadow rays to count
                      for (size_t i = b.begin(); i < b.end(); ++i) {
                        float* o = &ind.data[i * 3];
                        if (!g.hit(i)) {
                          o[0] = o[1] = o[2] = 0.f;
                          continue;
                        }
                        // The same call add_indirect makes for sample i (no shadow rays: r is not
                        // consulted).
                        const glm::vec3 L = shade_with(fn, vp.all, g.position[i], g.normal[i],
                                                       g.albedo[i], vp.shading, r, 1.f, &no_rays);
                        o[0] = L.x;
                        o[1] = L.y;
                        o[2] = L.z;
                      }
                    });
  vp.all_indirect_of = &g;
  return true;
}

void add_cached_indirect(GBufferRef g, const FrameVpls& vp, const uint8_t* mask, Image& col,
                         Counters* c) {
  FOVSIM_CHECK(col.width == g.width && col.height == g.height && col.channels == 3,
               "add_indirect: colour buffer does not match the G-buffer");
  FOVSIM_CHECK(vp.all_indirect_of && g.g == vp.all_indirect_of,
               "add_cached_indirect: the cached indirect light belongs to another G-buffer");
  std::atomic<uint64_t> shaded{0};
  const float* ind = vp.all_indirect.data.data();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, g.size(), 1024),
                    [&](const tbb::blocked_range<size_t>& b) {
                      uint64_t ns = 0;
                      for (size_t i = b.begin(); i < b.end(); ++i) {
                        if ((mask && !mask[i]) || !g.hit(i)) continue;
                        const float* L = ind + g.src(i) * 3;
                        float* o = &col.data[i * 3];
                        o[0] += L[0];
                        o[1] += L[1];
                        o[2] += L[2];
                        ++ns;
                      }
                      shaded += ns;
                    });
  if (c) c->add(Counter::shaded_sample_vpls, double(shaded.load()) * double(vp.all.size()));
}

void LightingStrategy::shade(const FrameContext& ctx, GBufferRef g, const uint8_t* mask, Image& col,
                             Counters& c) const {
  if (!ctx.vpls) return;
  // All VPLs on samples of the frame's shared G-buffer: the reference already evaluated them.
  if (uses_all_vpls() && ctx.vpls->all_indirect_of && g.g == ctx.vpls->all_indirect_of) {
    add_cached_indirect(g, *ctx.vpls, mask, col, &c);
    return;
  }
  add_indirect(g, selected(ctx), ctx.vpls->shading, ctx.renderer, mask, col, &c);
}

void render_with_lighting(FoveationMethod& m, FrameContext ctx, FrameOutput& out) {
  LightingStrategy* L = ctx.vpls ? m.lighting() : nullptr;
  ctx.lighting = L;
  if (L) L->begin_frame(ctx, out.counters);
  m.render(ctx, out);
  if (L) {
    L->end_frame(ctx, out.image_is_reference ? *ctx.reference : out.image);
    if (ctx.want_debug) L->debug_images(out.debug);
  }
  // The shared TAA post pass (taa.h) on the final image, unless the method runs its own.
  const TaaSettings taa = m.taa();
  if (taa.enabled && !m.own_taa()) {
    if (out.image_is_reference) {  // `full` at 1 spp: its image is the reference, before TAA
      out.image = *ctx.reference;
      out.image_is_reference = false;
    }
    m.taa_pass().apply(taa, ctx, out.image, out.counters);
  }
}

// ---- all_vpls ------------------------------------------------------------------------------
namespace {

class AllVpls final : public LightingStrategy {
 public:
  std::string name() const override { return "all_vpls"; }
  bool uses_all_vpls() const override { return true; }
  void begin_frame(const FrameContext& ctx, Counters& c) override {
    c.set(Counter::vpls_total, double(ctx.vpls->vpls.size()));
    c.set(Counter::vpls_kept, double(ctx.vpls->vpls.size()));
  }
  const VplSoA& selected(const FrameContext& ctx) const override { return ctx.vpls->all; }
};

}  // namespace

std::unique_ptr<LightingStrategy> create_lighting_all_vpls(Params&) {
  return std::make_unique<AllVpls>();
}
const std::vector<ParamInfo>& lighting_all_vpls_params() {
  static const std::vector<ParamInfo> t;
  return t;
}

// Defined in lighting_flc.cpp / lighting_fir.cpp.
#define FOVSIM_LIGHTING(name, summary)                                 \
  std::unique_ptr<LightingStrategy> create_lighting_##name(Params& p); \
  const std::vector<ParamInfo>& lighting_##name##_params();
#include "sim/foveation/lighting_list.h"
#undef FOVSIM_LIGHTING

const std::vector<LightingEntry>& lighting_table() {
  static const std::vector<LightingEntry> t = {
#define FOVSIM_LIGHTING(name, summary) \
  {#name, summary, create_lighting_##name, lighting_##name##_params},
#include "sim/foveation/lighting_list.h"
#undef FOVSIM_LIGHTING
  };
  return t;
}

std::unique_ptr<LightingStrategy> make_lighting(Params& p) {
  const std::string name = p.string("method", "all_vpls");
  std::string names;
  for (const auto& e : lighting_table()) {
    if (name == e.name) {
      auto l = e.create(p);
      p.finish();
      return l;
    }
    names += (names.empty() ? "" : ", ") + std::string(e.name);
  }
  p.fail("method", "unknown lighting strategy \"" + name + "\" (available: " + names + ")");
}

std::unique_ptr<LightingStrategy> default_lighting() {
  return std::make_unique<AllVpls>();
}

std::string lighting_markdown() {
  auto cell = [](const char* s) {
    std::string r;
    for (const char* c = s; *c; ++c) r += (*c == '|') ? std::string("\\|") : std::string(1, *c);
    return r.empty() ? std::string(" ") : r;
  };
  std::string md;
  for (const auto& e : lighting_table()) {
    md += "#### lighting `" + std::string(e.name) + "`\n\n" + e.summary + ".\n\n";
    const auto& ps = e.params();
    if (ps.empty()) {
      md += "No parameters.\n\n";
      continue;
    }
    md += "| key | type | default | range | source | meaning |\n|---|---|---|---|---|---|\n";
    for (const ParamInfo& q : ps)
      md += "| `" + std::string(q.name) + "` | " + cell(q.type) + " | " + cell(q.def) + " | " +
            cell(q.range) + " | " + cell(q.source) + " | " + cell(q.doc) + " |\n";
    md += "\n";
  }
  return md;
}

}  // namespace fovsim
