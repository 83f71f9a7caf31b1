// The supersampled reference (render.spp, sim/render/reference.cpp) and the ray-cone texture
// footprint (render_trace.cpp).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "sim/core/error.h"
#include "sim/render/embree_device.h"
#include "sim/render/renderer.h"
#include "sim/scene/mesh_builder.h"

using namespace fovsim;

namespace {

const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";

Display square_display(int w) {
  Display d;
  d.width = w;
  d.height = w;
  d.fov_h_deg = 90;
  d.fov_v_deg = 90;
  return d;
}

// Plane z = -1 facing the camera with vertical stripes (1 where fract(12 x) < 0.5, else 0),
// lit by ambient 1 only: a pixel's value is its albedo.
Scene stripes_scene(float scale) {
  Scene s;
  Material m;
  m.tex = TexKind::Stripes;
  m.scale = scale;
  m.base_color = glm::vec3(1.f);
  m.color2 = glm::vec3(0.f);
  m.specular = 0.f;
  s.materials.push_back(m);
  Mesh mesh;
  MeshBuilder b(mesh);
  b.grid({-10, -10, -1}, {20, 0, 0}, {0, 20, 0}, 2, 2, 0);
  s.meshes.push_back(std::move(mesh));
  s.objects.push_back(Object{});
  s.ambient = glm::vec3(1.f);
  s.background = glm::vec3(0.f);
  s.build_submodels();
  return s;
}

// Exact fraction of [a, b] where fract(f x) < 0.5.
double stripe_fraction(double a, double b, double f) {
  auto I = [f](double x) {  // integral from 0 of the indicator
    const double p = x * f, k = std::floor(p);
    return (k * 0.5 + std::min(p - k, 0.5)) / f;
  };
  return (I(b) - I(a)) / (b - a);
}

Image reference(const Scene& s, const Display& d, int spp, const Camera& cam) {
  RenderSettings rs;
  rs.spp = spp;
  Renderer r(s, rs);
  GBuffer g;
  Image img;
  r.trace_gbuffer(cam, kShadingChannels, g);
  r.render_reference(cam, g, img);
  return img;
}

template <class F>
void with_embree_isa(const std::string& isa, F f) {
  const char* old = std::getenv("FOVSIM_EMBREE_ISA");
  const std::string saved = old ? old : "";
  ::setenv("FOVSIM_EMBREE_ISA", isa.c_str(), 1);
  f();
  if (old)
    ::setenv("FOVSIM_EMBREE_ISA", saved.c_str(), 1);
  else
    ::unsetenv("FOVSIM_EMBREE_ISA");
}

// The former render_reference, kept as the specification of the chunked pass: per stratum a
// frame of jittered points through trace_points, shade() of that frame, a frame-sized double
// sum; then times 1 / spp.
void reference_whole_frame(const Renderer& r, const Camera& cam, Image& out, Counters* c) {
  const int spp = r.settings().spp;
  const int n = int(std::lround(std::sqrt(double(spp))));
  const int W = cam.width, H = cam.height;
  const size_t np = size_t(W) * size_t(H);
  out.resize(W, H, 3);
  std::vector<double> acc(np * 3, 0.0);
  std::vector<glm::vec2> pts(np);
  GBuffer g;
  Image col;
  for (int s = 0; s < spp; ++s) {
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const glm::vec2 o = stratified_offset(x, y, s, n);
        pts[size_t(y) * size_t(W) + size_t(x)] = glm::vec2(float(x) + o.x, float(y) + o.y);
      }
    r.trace_points(cam, pts, kShadingChannels, g, c, 1.f / float(n));
    r.shade(g, cam.position, col, nullptr, c);
    for (size_t i = 0; i < np * 3; ++i) acc[i] += col.data[i];
  }
  const double inv = 1.0 / double(spp);
  for (size_t i = 0; i < np * 3; ++i) out.data[i] = float(acc[i] * inv);
}

// The jitter hash stratified_offset had when the reference was introduced (its values are part
// of every reference image).
uint32_t mix32_v1(uint32_t h) {
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}
float jitter_v1(uint32_t x, uint32_t y, uint32_t s, uint32_t axis) {
  const uint32_t h =
      mix32_v1(x * 0x9e3779b1u ^ mix32_v1(y * 0x85ebca77u ^ mix32_v1(s * 2u + axis)));
  return float(h >> 8) * (1.f / 16777216.f);
}

}  // namespace

TEST(Reference, StratifiedOffsetKeepsItsValues) {
  for (int n : {1, 2, 3, 4})
    for (int s = 0; s < n * n; ++s)
      for (int y : {0, 1, 7, 399})
        for (int x : {0, 3, 16, 359}) {
          const glm::vec2 o = stratified_offset(x, y, s, n);
          const float ex =
              (float(s % n) + jitter_v1(uint32_t(x), uint32_t(y), uint32_t(s), 0u)) / float(n);
          const float ey =
              (float(s / n) + jitter_v1(uint32_t(x), uint32_t(y), uint32_t(s), 1u)) / float(n);
          EXPECT_EQ(o.x, ex);
          EXPECT_EQ(o.y, ey);
        }
}

// The chunked pass (packets of 16 pixels x all strata, shaded from the packet's own buffer)
// gives the former whole-frame passes' image bit for bit, and the same counters and ray count:
// image sizes that are not multiples of the 16-pixel packets or of the 256-pixel tasks, one
// narrower than a packet (packets span rows), a dynamic (instanced) scene, spp 4 and 16.
TEST(Reference, ChunkedEqualsWholeFramePasses) {
  struct Case {
    bool dynamic;
    int w, h, spp;
  };
  const Case cases[] = {{false, 37, 23, 4},  {false, 37, 23, 16}, {false, 7, 5, 16},
                        {false, 53, 41, 16}, {true, 29, 19, 4},   {true, 29, 19, 16}};
  for (const Case& k : cases) {
    SCOPED_TRACE(testing::Message()
                 << "dynamic " << k.dynamic << " " << k.w << "x" << k.h << " spp " << k.spp);
    Params p(Json{{"type", "atrium"}, {"complexity", 1}, {"dynamic", k.dynamic}});
    Scene s = make_scene(p, kModels);
    ASSERT_FALSE(s.lights.empty());
    Display d;
    d.width = k.w;
    d.height = k.h;
    d.fov_h_deg = 100;
    d.fov_v_deg = 80;
    Camera cam =
        Camera::from_pose(d, glm::dvec3(s.default_eye), glm::angleAxis(-0.3, glm::dvec3(0, 1, 0)));
    RenderSettings rs;
    rs.spp = k.spp;
    Renderer r(s, rs);
    if (k.dynamic) r.set_time(0.37);
    GBuffer g1;
    r.trace_gbuffer(cam, kShadingChannels, g1);
    Image chunked, whole;
    Counters cc, cw;
    const uint64_t r0 = r.rays_traced();
    r.render_reference(cam, g1, chunked, &cc);
    const uint64_t r1 = r.rays_traced();
    reference_whole_frame(r, cam, whole, &cw);
    const uint64_t r2 = r.rays_traced();
    ASSERT_EQ(chunked.width, k.w);
    ASSERT_EQ(chunked.height, k.h);
    ASSERT_EQ(chunked.data.size(), whole.data.size());
    EXPECT_EQ(
        std::memcmp(chunked.data.data(), whole.data.data(), whole.data.size() * sizeof(float)), 0);
    // Not a flat image: the comparison covers textures, lights and shadows.
    float lo = chunked.data[0], hi = lo;
    for (float v : chunked.data) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    EXPECT_LT(lo, hi);
    ASSERT_EQ(cc.items().size(), cw.items().size());
    for (size_t i = 0; i < cc.items().size(); ++i) {
      EXPECT_EQ(cc.items()[i].first, cw.items()[i].first);
      EXPECT_EQ(cc.items()[i].second, cw.items()[i].second) << cc.items()[i].first;
    }
    const double samples = double(k.w) * k.h * k.spp;
    EXPECT_EQ(cc.get(Counter::primary_rays), samples);
    EXPECT_EQ(cc.get(Counter::shaded_samples), samples);
    EXPECT_GT(cc.get(Counter::shadow_rays), 0.0);
    EXPECT_EQ(r1 - r0, r2 - r1);
  }
}

TEST(Reference, StratifiedOffsetsCoverTheirStrata) {
  for (int n : {1, 2, 4, 8})
    for (int s = 0; s < n * n; ++s) {
      glm::vec2 o = stratified_offset(17, 5, s, n);
      EXPECT_GE(o.x, float(s % n) / n);
      EXPECT_LT(o.x, float(s % n + 1) / n);
      EXPECT_GE(o.y, float(s / n) / n);
      EXPECT_LT(o.y, float(s / n + 1) / n);
    }
}

// The spp average approaches the analytic box integral of each pixel; more samples, closer.
TEST(Reference, SupersampledStripesMatchAnalyticPixelIntegral) {
  const float f = 12.f;  // stripe period 2.67 pixels at W = 64
  Scene s = stripes_scene(f);
  Display d = square_display(64);
  Camera cam = Camera::from_pose(d, {0, 0, 0}, {1, 0, 0, 0});
  double err[3] = {0, 0, 0}, worst[3] = {0, 0, 0};
  const int spps[3] = {1, 16, 64};
  for (int k = 0; k < 3; ++k) {
    Image img = reference(s, d, spps[k], cam);
    for (int y = 0; y < d.height; ++y)
      for (int x = 0; x < d.width; ++x) {
        const double a = (2.0 * x / d.width - 1.0), b = (2.0 * (x + 1) / d.width - 1.0);
        const double e = std::fabs(img.at(x, y)[0] - stripe_fraction(a, b, f));
        err[k] += e / (d.width * d.height);
        worst[k] = std::max(worst[k], e);
      }
  }
  // 1 spp with the filtered texture is already the pixel's box integral here (head-on plane,
  // footprint = pixel). n x n jittered strata, each box-filtered over 1/n pixel, leave an
  // error where an edge crosses a stratum column (the jittered boxes overlap or leave gaps),
  // shrinking like n^-1.5: measured 0.029 (16 spp) and 0.013 (64 spp) mean absolute error.
  EXPECT_LT(err[0], 0.01);
  EXPECT_LT(err[1], 0.04);
  EXPECT_LT(err[2], 0.02);
  EXPECT_LT(err[2], err[1]);
  EXPECT_LT(worst[2], 0.1);
}

// The footprint of a pixel-centre ray on a head-on plane is one pixel wide (in uv = world).
TEST(Reference, RayConeFootprintIsOnePixelOnAHeadOnPlane) {
  Scene s = stripes_scene(12.f);
  Display d = square_display(64);
  Camera cam = Camera::from_pose(d, {0, 0, 0}, {1, 0, 0, 0});
  Renderer r(s, RenderSettings{});
  GBuffer g;
  r.trace_gbuffer(cam, kShadingChannels | kFootprint, g);
  for (size_t i : {size_t(0), size_t(33 * 64 + 7), size_t(64 * 64 - 1)})
    EXPECT_NEAR(g.footprint[i], 2.0 / 64.0, 1e-5);
  // trace_points with a coarser spacing passes a proportionally larger footprint.
  GBuffer p;
  r.trace_points(cam, {glm::vec2(10.5f, 20.5f)}, kShadingChannels | kFootprint, p, nullptr, 4.f);
  EXPECT_NEAR(p.footprint[0], 4.0 * 2.0 / 64.0, 1e-5);
}

TEST(Render, DeterministicSupersampledAcrossThreadCounts) {
  Params p(Json{{"type", "atrium"}, {"complexity", 1}});
  Scene s = make_scene(p, kModels);
  Display d = square_display(48);
  Camera cam = Camera::from_pose(d, glm::dvec3(s.default_eye), {1, 0, 0, 0});
  Image a, b;
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
    a = reference(s, d, 4, cam);
  }
  b = reference(s, d, 4, cam);
  ASSERT_EQ(a.data.size(), b.data.size());
  EXPECT_EQ(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)), 0);
}

TEST(Render, DeterministicSupersampledOnEveryEmbreeIsa) {
  Params p(Json{{"type", "atrium"}, {"complexity", 1}, {"dynamic", true}});
  Scene s = make_scene(p, kModels);
  Display d = square_display(40);
  Camera cam = Camera::from_pose(d, glm::dvec3(s.default_eye), {1, 0, 0, 0});
  std::vector<std::string> isas = embree_supported_isas();
  ASSERT_FALSE(isas.empty());
  Image base;
  with_embree_isa(isas.front(), [&] { base = reference(s, d, 4, cam); });
  for (size_t k = 1; k < isas.size(); ++k) {
    Image o;
    with_embree_isa(isas[k], [&] { o = reference(s, d, 4, cam); });
    SCOPED_TRACE(isas[k]);
    EXPECT_EQ(std::memcmp(base.data.data(), o.data.data(), o.data.size() * sizeof(float)), 0);
  }
}

TEST(Reference, SppMustBeASquare) {
  Params ok(Json{{"spp", 16}});
  EXPECT_EQ(RenderSettings::from_params(ok).spp, 16);
  Params bad(Json{{"spp", 8}});
  EXPECT_THROW(RenderSettings::from_params(bad), Error);
}
