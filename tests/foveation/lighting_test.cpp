// Lighting strategies (sim/foveation/lighting.h): the frame's VPL set is shared, all_vpls at
// full sampling is the reference exactly, fir/flc keep at most their budget, the SIMD VPL loop
// gives the scalar loop's bits on every path, bad `lighting` keys name their JSON path, a
// scene without indirect light has no VPLs at all, and shading through an index view of the
// G-buffer gives a copied buffer's bits.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <memory>
#include <string>

#include "sim/core/error.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/frame.h"
#include "sim/foveation/simd_kernels.h"

using namespace fovsim;

namespace {

struct World {
  Scene scene;
  std::unique_ptr<Renderer> renderer;
  Display display;
  FrameData fd;
  explicit World(const Json& scene_json, int size = 40) {
    Params sp(scene_json);
    scene = make_scene(sp, "");
    renderer = std::make_unique<Renderer>(scene, RenderSettings{});
    display.width = display.height = size;
    display.fov_h_deg = display.fov_v_deg = 60;
    TraceSample s;
    s.head_pos = glm::dvec3(0, 1, 2.2);
    s.gaze_dir = glm::normalize(glm::dvec3(-0.3, 0.0, -1.0));
    renderer->set_time(0);
    prepare_frame(*renderer, display, s, 0, kShadingChannels, nullptr, fd);
  }
  FrameOutput run(const std::string& method, const Json& params, int frame = 0) {
    Params p(params, "cfg.json", "methods[0]");
    auto m = make_method(method, p);
    FrameContext ctx = fd.context(scene, *renderer, display, false);
    ctx.frame = frame;
    FrameOutput out;
    render_with_lighting(*m, ctx, out);
    return out;
  }
  const Image& image(const FrameOutput& o) const {
    return o.image_is_reference ? fd.reference : o.image;
  }
};

World& cornell() {
  static World w(Json{{"type", "cornell"}, {"vpl", {{"rsm_size", 12}}}});
  return w;
}

double max_abs_diff(const Image& a, const Image& b) {
  double m = 0;
  for (size_t i = 0; i < a.data.size(); ++i)
    m = std::max(m, double(std::fabs(a.data[i] - b.data[i])));
  return m;
}

std::string error_of(const std::string& method, const Json& j) {
  try {
    Params p(j, "cfg.json", "methods[1]");
    make_method(method, p);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Lighting, FrameHasOneVplSetAndTheReferenceIncludesIt) {
  World& w = cornell();
  ASSERT_TRUE(w.fd.has_vpls);
  EXPECT_GT(w.fd.vpls.vpls.size(), 50u);
  EXPECT_EQ(w.fd.vpls.all.size(), w.fd.vpls.vpls.size());
  EXPECT_GT(w.fd.counters.get(Counter::rsm_texels), 0.0);
  double ind = 0;
  for (size_t i = 0; i < w.fd.reference.data.size(); ++i)
    ind += w.fd.reference.data[i] - w.fd.direct.data[i];
  EXPECT_GT(ind, 0.0);
}

TEST(Lighting, AllVplsAtFullSamplingIsTheReferenceExactly) {
  World& w = cornell();
  FrameOutput f = w.run("full", Json{{"lighting", {{"method", "all_vpls"}}}});
  EXPECT_EQ(max_abs_diff(w.image(f), w.fd.reference), 0.0);
  EXPECT_EQ(f.counters.get(Counter::vpls_kept), double(w.fd.vpls.vpls.size()));
  // The strategy's own loop over the full G-buffer gives the same bits (no shortcut).
  FrameContext ctx = w.fd.context(w.scene, *w.renderer, w.display, false);
  auto L = default_lighting();
  Counters c;
  L->begin_frame(ctx, c);
  Image col = w.fd.direct;
  L->shade(ctx, w.fd.gbuffer, nullptr, col, c);
  EXPECT_EQ(max_abs_diff(col, w.fd.reference), 0.0);
  EXPECT_GT(c.get(Counter::shaded_sample_vpls), 0.0);
}

TEST(Lighting, SamplingMethodsShadeTheIndirectLight) {
  World& w = cornell();
  // KFR with all VPLs adds the indirect light at its samples: the mean indirect light of its
  // image (image - direct) is near the reference's (without it the ratio would be ~0).
  FrameOutput k = w.run("kfr", Json{{"sigma", 1.5}});
  EXPECT_GT(k.counters.get(Counter::shaded_sample_vpls), 0.0);
  EXPECT_EQ(k.counters.get(Counter::vpls_kept), double(w.fd.vpls.vpls.size()));
  double ind_k = 0, ind_ref = 0;
  for (size_t i = 0; i < k.image.data.size(); ++i) {
    ind_k += k.image.data[i] - w.fd.direct.data[i];
    ind_ref += w.fd.reference.data[i] - w.fd.direct.data[i];
  }
  EXPECT_GT(ind_ref, 0.0);
  EXPECT_NEAR(ind_k / ind_ref, 1.0, 0.5);  // 0 without the indirect light; measured 1.24
}

TEST(Lighting, FirAndFlcKeepAtMostTheirBudget) {
  World& w = cornell();
  const double n = double(w.fd.vpls.vpls.size());
  for (const char* strat : {"fir", "flc", "uniform"})
    for (int budget : {0, 1, 7, 40, 1000000}) {
      FrameOutput o = w.run("kfr", Json{{"lighting", {{"method", strat}, {"vpl_budget", budget}}}});
      EXPECT_LE(o.counters.get(Counter::vpls_kept), std::min(double(budget), n)) << strat << budget;
      EXPECT_EQ(o.counters.get(Counter::vpls_total), n);
      for (float v : o.image.data) ASSERT_TRUE(std::isfinite(v));
      if (budget >= n) {
        EXPECT_EQ(o.counters.get(Counter::vpls_kept), n);
      }
    }
  // FIR has no importance map (only per-VPL importance and culling); FLC has both.
  FrameOutput fir = w.run("full", Json{{"lighting", {{"method", "fir"}, {"vpl_budget", 16}}}});
  EXPECT_FALSE(fir.counters.has(Counter::importance_samples));
  EXPECT_TRUE(fir.counters.has(Counter::contribution_evals));
}

// `uniform`: every VPL equally likely. With the whole set as budget it is all_vpls exactly;
// with a quarter of it, the Horvitz-Thompson weights make it unbiased: the mean indirect light
// over 64 seeds is within 3% of all_vpls' (measured: one seed's sd 4.0%, so the mean's 0.5%:
// the bound is 6 standard errors).
TEST(Lighting, UniformSubsetIsUnbiasedAndExactAtFullBudget) {
  World& w = cornell();
  const int n = int(w.fd.vpls.vpls.size());
  ASSERT_GT(n, 8);
  // full with all VPLs is the reference itself (image_is_reference).
  const Image& all = w.fd.reference;
  FrameOutput full = w.run("full", Json{{"lighting", {{"method", "uniform"}, {"vpl_budget", n}}}});
  EXPECT_EQ(full.counters.get(Counter::vpls_kept), double(n));
  EXPECT_EQ(max_abs_diff(full.image, all), 0.0);
  double ind_all = 0;
  for (size_t i = 0; i < all.data.size(); ++i) ind_all += all.data[i] - w.fd.direct.data[i];
  ASSERT_GT(ind_all, 0.0);
  double mean = 0;
  const int seeds = 64;
  for (int seed = 1; seed <= seeds; ++seed) {
    FrameOutput o = w.run(
        "full", Json{{"lighting", {{"method", "uniform"}, {"vpl_budget", n / 4}, {"seed", seed}}}});
    EXPECT_EQ(o.counters.get(Counter::vpls_kept), double(n / 4));
    double ind = 0;
    for (size_t i = 0; i < o.image.data.size(); ++i) ind += o.image.data[i] - w.fd.direct.data[i];
    mean += ind / seeds;
  }
  EXPECT_NEAR(mean / ind_all, 1.0, 0.03);
}

TEST(Lighting, DeterministicAcrossThreadCounts) {
  World& w = cornell();
  for (const char* strat : {"fir", "flc", "uniform", "all_vpls"}) {
    const Json p{{"lighting", {{"method", strat}, {"vpl_budget", 30}}}};
    const Json q = std::string(strat) == "all_vpls" ? Json{{"lighting", {{"method", strat}}}} : p;
    FrameOutput a, b;
    tbb::task_arena(1).execute([&] { a = w.run("rmfr", q); });
    tbb::task_arena(2).execute([&] { b = w.run("rmfr", q); });
    EXPECT_EQ(max_abs_diff(a.image, b.image), 0.0) << strat;
  }
}

TEST(Lighting, SimdVplLoopMatchesTheScalarLoopOnEveryPath) {
  World& w = cornell();
  const FrameVpls& fv = w.fd.vpls;
  const SimdPath saved = simd_path();
  for (SimdPath path : simd_paths_available()) {
    set_simd_path(path);
    for (size_t i = 0; i < w.fd.gbuffer.size(); i += 7) {
      if (!w.fd.gbuffer.hit(i)) continue;
      const GBuffer& g = w.fd.gbuffer;
      // Every remainder length of the 8-lane loop.
      for (size_t m : {size_t(0), size_t(1), size_t(7), size_t(8), size_t(13), fv.all.size()}) {
        VplSoA sub;
        for (size_t k = 0; k < std::min(m, fv.vpls.size()); ++k) sub.push(fv.vpls[k], 1.f);
        const glm::vec3 a =
            shade_vpls(sub, g.position[i], g.normal[i], g.albedo[i], fv.shading, nullptr);
        const glm::vec3 b =
            shade_vpls_point(sub, g.position[i], g.normal[i], g.albedo[i], fv.shading, nullptr);
        ASSERT_EQ(a.x, b.x) << simd_path_name(path) << " m=" << m;
        ASSERT_EQ(a.y, b.y);
        ASSERT_EQ(a.z, b.z);
      }
    }
  }
  set_simd_path(saved);
}

TEST(Lighting, BadLightingKeysNameTheJsonPath) {
  std::string e = error_of("kfr", Json{{"lighting", {{"method", "flc"}, {"vpl_budgte", 1}}}});
  EXPECT_NE(e.find("methods[1].lighting.vpl_budgte"), std::string::npos) << e;
  e = error_of("kfr", Json{{"lighting", {{"method", "tbds"}}}});
  EXPECT_NE(e.find("methods[1].lighting.method"), std::string::npos) << e;
  EXPECT_NE(e.find("all_vpls, flc, fir"), std::string::npos) << e;
  e = error_of("kfr", Json{{"lighting", {{"method", "fir"}, {"vpl_budget", -3}}}});
  EXPECT_NE(e.find("methods[1].lighting.vpl_budget"), std::string::npos) << e;
  e = error_of("kfr", Json{{"lighting", "flc"}});
  EXPECT_NE(e.find("methods[1].lighting"), std::string::npos) << e;
  // The flc method brings its own lighting.
  e = error_of("flc", Json{{"lighting", {{"method", "fir"}}}});
  EXPECT_NE(e.find("methods[1].lighting"), std::string::npos) << e;
}

TEST(Lighting, SceneWithoutIndirectHasNoVplPass) {
  World w(Json{{"type", "atrium"}, {"complexity", 1}}, 24);
  EXPECT_FALSE(w.fd.has_vpls);
  EXPECT_FALSE(w.fd.counters.has(Counter::rsm_texels));
  EXPECT_TRUE(w.fd.vpls.vpls.empty());
  FrameOutput o = w.run("kfr", Json{{"lighting", {{"method", "flc"}, {"vpl_budget", 8}}}});
  for (Counter k : {Counter::vpls_total, Counter::vpls_kept, Counter::shaded_sample_vpls,
                    Counter::rsm_texels, Counter::importance_samples, Counter::contribution_evals})
    EXPECT_FALSE(o.counters.has(k)) << counter_name(k);
  // `vpl` settings on a scene without indirect light are an error naming the key.
  try {
    Params sp(Json{{"type", "atrium"}, {"vpl", {{"rsm_size", 8}}}}, "cfg.json", "scene");
    make_scene(sp, "");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scene.vpl"), std::string::npos) << e.what();
  }
}

TEST(Lighting, CachedAllVplIndirectEqualsEvaluatingIt) {
  // prepare_frame keeps the all-VPL indirect light of every pixel (FrameVpls::all_indirect,
  // visibility off); all_vpls strategies add it through their view of the shared G-buffer
  // instead of evaluating shade_vpls again. Same bits and counters as add_indirect, for the
  // G-buffer itself, a mask and an index view with cleared slots; not used for another
  // G-buffer or with visibility on.
  World& w = cornell();
  const GBuffer& g = w.fd.gbuffer;
  ASSERT_FALSE(w.fd.vpls.shading.visibility);
  ASSERT_EQ(w.fd.vpls.all_indirect_of, &g);  // prepare_frame filled it
  ASSERT_EQ(w.fd.vpls.all_indirect.data.size(), g.size() * 3);
  const int bw = 17, bh = 9;
  std::vector<uint32_t> index(size_t(bw) * bh);
  for (size_t i = 0; i < index.size(); ++i)
    index[i] = i % 6 == 2 ? GBufferRef::kNone : uint32_t((i * 2654435761u) % g.size());
  std::vector<uint8_t> mask_full(g.size()), mask_view(index.size());
  for (size_t i = 0; i < mask_full.size(); ++i) mask_full[i] = i % 3 != 0;
  for (size_t i = 0; i < mask_view.size(); ++i) mask_view[i] = i % 4 != 1;
  const FrameVpls& fv = w.fd.vpls;
  struct Case {
    GBufferRef view;
    const uint8_t* mask;
  };
  for (const Case& c : {Case{GBufferRef(g), nullptr}, Case{GBufferRef(g), mask_full.data()},
                        Case{GBufferRef(g, index.data(), bw, bh), nullptr},
                        Case{GBufferRef(g, index.data(), bw, bh), mask_view.data()}}) {
    Image a(c.view.width, c.view.height, 3, 0.25f), b = a;
    Counters ca, cb;
    add_indirect(c.view, fv.all, fv.shading, w.renderer.get(), c.mask, a, &ca);
    add_cached_indirect(c.view, fv, c.mask, b, &cb);
    EXPECT_EQ(a.data, b.data);
    EXPECT_EQ(ca.items(), cb.items());
    EXPECT_GT(cb.get(Counter::shaded_sample_vpls), 0.0);
    // Through the strategy: the all_vpls default takes the cache and gives the same.
    FrameContext ctx = w.fd.context(w.scene, *w.renderer, w.display, false);
    auto L = default_lighting();
    ASSERT_TRUE(L->uses_all_vpls());
    Counters cl, cs;
    L->begin_frame(ctx, cl);
    Image s(c.view.width, c.view.height, 3, 0.25f);
    L->shade(ctx, c.view, c.mask, s, cs);
    EXPECT_EQ(s.data, a.data);
    EXPECT_EQ(cs.get(Counter::shaded_sample_vpls), ca.get(Counter::shaded_sample_vpls));
  }
  // Another G-buffer: refused by add_cached_indirect (the strategy evaluates instead).
  GBuffer other = g;
  Image o(g.width, g.height, 3);
  EXPECT_THROW(add_cached_indirect(other, fv, nullptr, o, nullptr), InternalError);
  // Visibility on: no cache.
  FrameVpls vis = fv;
  vis.shading.visibility = true;
  EXPECT_FALSE(cache_all_indirect(g, w.renderer.get(), vis));
  EXPECT_EQ(vis.all_indirect_of, nullptr);
  EXPECT_TRUE(vis.all_indirect.data.empty());
}

TEST(Lighting, IndexViewShadesLikeACopiedBuffer) {
  // Reduced buffers (KFR's LP-buffer, ...) are shaded through an index into the frame's
  // G-buffer (GBufferRef): direct light, indirect light and counters equal those of a buffer
  // holding copies of the same samples, bit for bit, cleared slots (kNone) being misses.
  World& w = cornell();
  const GBuffer& g = w.fd.gbuffer;
  const int bw = 13, bh = 11;
  std::vector<uint32_t> index(size_t(bw) * bh);
  std::vector<uint8_t> mask(index.size());
  GBuffer copy;
  copy.resize(bw, bh, kShadingChannels);
  for (size_t i = 0; i < index.size(); ++i) {
    index[i] = i % 7 == 3 ? GBufferRef::kNone : uint32_t((i * 2654435761u) % g.size());
    mask[i] = i % 5 != 1;
    if (index[i] == GBufferRef::kNone)
      copy.clear_sample(i);
    else
      copy.copy_sample(g, index[i], i);
  }
  const GBufferRef view(g, index.data(), bw, bh);
  FrameContext ctx = w.fd.context(w.scene, *w.renderer, w.display, false);
  auto L = default_lighting();
  Counters cl;
  L->begin_frame(ctx, cl);
  for (bool vis : {false, true}) {
    FrameVpls fv = w.fd.vpls;
    fv.shading.visibility = vis;
    Image a(bw, bh, 3), b(bw, bh, 3);  // zero: masked-out slots stay 0 in both
    Counters ca, cb;
    w.renderer->shade(view, ctx.camera->position, a, mask.data(), &ca);
    w.renderer->shade(copy, ctx.camera->position, b, mask.data(), &cb);
    add_indirect(view, fv.all, fv.shading, w.renderer.get(), mask.data(), a, &ca);
    add_indirect(copy, fv.all, fv.shading, w.renderer.get(), mask.data(), b, &cb);
    EXPECT_EQ(a.data, b.data) << vis;
    EXPECT_EQ(ca.items(), cb.items()) << vis;
    EXPECT_GT(ca.get(Counter::shaded_sample_vpls), 0.0);
  }
}
