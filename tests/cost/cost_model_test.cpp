// Cost model invariants: passes that do not exist cost nothing, every pass is
// non-decreasing in each counter, predictions stay finite, errors name their location.
#include "sim/cost/cost_model.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/core/error.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/workload.h"

using namespace fovsim;

namespace {
const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";

CostInputs base_inputs(const std::string& method, const Counters* c) {
  CostInputs in;
  in.method = method;
  in.counters = c;
  in.features.triangles = 100000;
  in.features.lights = 2;
  in.features.shadowed_lights = 1;
  in.display.width = 1440;
  in.display.height = 1600;
  in.display.eyes = 2;
  return in;
}
}  // namespace

TEST(CostModel, LoadsProfileAndEstimatesFull) {
  GpuProfile g = GpuProfile::load("gtx1080", kModels);
  EXPECT_EQ(g.name, "gtx1080");
  Counters c;
  CostInputs in = base_inputs("full", &c);
  FrameCost fc = estimate_frame(g, in);
  EXPECT_GT(fc.total_ms, 0);
  double sum = 0;
  for (auto& p : fc.passes) {
    EXPECT_GE(p.ms, 0) << p.pass;
    sum += p.ms;
  }
  EXPECT_NEAR(sum, fc.total_ms, 1e-9);
  EXPECT_GT(fc.pass_ms("lighting"), 0);
  EXPECT_EQ(fc.pass_ms("pass2"), 0);  // pass 2 only for mapping methods
}

namespace {
Workload twfr_like() {
  Workload w;
  w.triangles = 1e6;
  w.lights = 3;
  w.shadowed_lights = 1;
  w.pipeline.ssao = true;
  w.pipeline.taa = true;
  w.pipeline.skybox = true;
  return w;
}
}  // namespace

TEST(CostModel, PassesThatDoNotExistCostNothing) {
  GpuProfile g = GpuProfile::load("gtx1080", kModels);
  Counters c;
  c.set(Counter::shaded_samples, 1000);
  CostInputs in = base_inputs("full", &c);
  Workload w;  // generic: no ssao, no taa
  in.features.shadowed_lights = 0;
  in.workload = &w;
  FrameCost fc = estimate_frame(g, in);
  for (const char* p : {"shadow", "ssao", "taa", "rsm", "contribution", "importance", "reproject",
                        "pass2", "post_aa"})
    for (auto& pc : fc.passes) EXPECT_NE(pc.pass, p) << "pass " << p << " should not exist";
  // RSM/contribution only for FLC, reprojection only for TWFR, pass 2 only for mappings.
  in.method = "flc";
  fc = estimate_frame(g, in);
  EXPECT_GT(fc.pass_ms("rsm"), 0);
  EXPECT_EQ(fc.pass_ms("reproject"), 0);
  in.method = "twfr";
  fc = estimate_frame(g, in);
  EXPECT_GT(fc.pass_ms("reproject"), 0);
  EXPECT_EQ(fc.pass_ms("rsm"), 0);
  in.method = "kfr";
  fc = estimate_frame(g, in);
  EXPECT_GT(fc.pass_ms("pass2"), 0);
  in.method = "fvrs";
  fc = estimate_frame(g, in);
  EXPECT_EQ(fc.pass_ms("pass2"), 0);
}

TEST(CostModel, EveryPassNonDecreasingInEachCounter) {
  const char* names[] = {"shaded_samples",     "gbuffer_samples",    "buffer_pixels_allocated",
                         "buffer_pixels_used", "fullres_pixels",     "filter_taps",
                         "prims_submitted",    "prims_culled",       "pixels_redrawn",
                         "reprojected_pixels", "holes_mip0",         "holes_mip3",
                         "vpls_total",         "vpls_kept",          "importance_samples",
                         "contribution_evals", "shaded_sample_vpls", "rsm_texels"};
  Workload w = twfr_like();
  w.pipeline.post_aa = true;
  for (const std::string& gpu : GpuProfile::available(kModels)) {
    GpuProfile g = GpuProfile::load(gpu, kModels);
    for (const std::string& m : cost_methods()) {
      Counters base;
      for (auto* n : names) base.set_named(n, 1000);
      CostInputs in = base_inputs(m, &base);
      in.workload = &w;
      FrameCost f0 = estimate_frame(g, in);
      for (auto* n : names) {
        Counters more = base;
        more.set_named(n, 1e6);
        in.counters = &more;
        FrameCost f1 = estimate_frame(g, in);
        ASSERT_EQ(f0.passes.size(), f1.passes.size());
        for (size_t i = 0; i < f0.passes.size(); ++i)
          EXPECT_GE(f1.passes[i].ms, f0.passes[i].ms - 1e-12)
              << gpu << " " << m << " " << n << " " << f0.passes[i].pass;
      }
      // Scene features too: more triangles / lights never cost less.
      in.counters = &base;
      Workload w2 = w;
      w2.triangles *= 10;
      w2.lights += 5;
      w2.shadowed_lights += 1;
      in.workload = &w2;
      EXPECT_GE(estimate_frame(g, in).total_ms, f0.total_ms) << gpu << " " << m;
    }
  }
}

TEST(CostModel, FiniteForZeroAndHugeInputs) {
  GpuProfile g = GpuProfile::load("gtx1080", kModels);
  Workload w = twfr_like();
  for (const std::string& m : cost_methods()) {
    for (double v : {0.0, 1e15}) {
      Counters c;
      for (auto* n : {"shaded_samples", "fullres_pixels", "pixels_redrawn", "vpls_total",
                      "importance_samples", "shaded_sample_vpls", "prims_submitted"})
        c.set_named(n, v);
      CostInputs in = base_inputs(m, &c);
      in.workload = &w;
      in.display.width = v == 0 ? 0 : 100000;
      in.display.height = v == 0 ? 0 : 100000;
      in.pixel_scale = v == 0 ? 0 : 1e4;
      FrameCost fc = estimate_frame(g, in);
      EXPECT_TRUE(std::isfinite(fc.total_ms)) << m << " " << v;
      EXPECT_GE(fc.total_ms, 0) << m;
    }
    // A NaN counter is an error naming it, never charged as 0.
    Counters c;
    c.set(Counter::shaded_samples, std::nan(""));
    CostInputs in = base_inputs(m, &c);
    in.workload = &w;
    try {
      estimate_frame(g, in);
      ADD_FAILURE() << m;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("counter shaded_samples is nan"), std::string::npos)
          << e.what();
    }
  }
}

TEST(CostModel, PixelCountersScaleTrianglesDoNot) {
  GpuProfile g = GpuProfile::load("gtx1080", kModels);
  Counters c;
  c.set(Counter::shaded_samples, 1000);
  CostInputs in = base_inputs("kfr", &c);
  Workload w;
  w.triangles = 1e5;
  in.workload = &w;
  FrameCost a = estimate_frame(g, in);
  in.pixel_scale = 4;
  FrameCost b = estimate_frame(g, in);
  const double oh = g.passes.at("lighting").overhead_ms;
  EXPECT_NEAR(b.pass_ms("lighting") - oh, 4 * (a.pass_ms("lighting") - oh), 1e-9);
  EXPECT_NEAR(b.pass_ms("depth"), a.pass_ms("depth"),
              1e-12);  // display pixels + triangles: unchanged
}

TEST(CostModel, EyesChargePerEyePassesTwiceShadowOnce) {
  GpuProfile g = GpuProfile::load("gtx1080", kModels);
  CostInputs in = base_inputs("full", nullptr);
  Workload w = twfr_like();
  in.workload = &w;
  in.display.eyes = 1;
  FrameCost one = estimate_frame(g, in);
  in.display.eyes = 2;
  FrameCost two = estimate_frame(g, in);
  EXPECT_NEAR(two.pass_ms("shadow"), one.pass_ms("shadow"), 1e-12);
  const double oh = g.passes.at("lighting").overhead_ms;
  EXPECT_NEAR(two.pass_ms("lighting") - oh, 2 * (one.pass_ms("lighting") - oh), 1e-9);
}

TEST(CostModel, BadProfilesAndUnknownNamesNameTheLocation) {
  try {
    GpuProfile::load("no_such_gpu", kModels);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_gpu.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("gtx1080"), std::string::npos)
        << e.what();  // lists available
  }
  Json j = Params::parse_json_file(kModels + "/gpus/gtx1080.json");
  Json bad = j;
  bad["passes"]["lighting"]["terms"]["shade_flops"] = -1;
  try {
    GpuProfile::from_json(bad, "x.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x.json: passes.lighting.terms.shade_flops"),
              std::string::npos)
        << e.what();
  }
  bad = j;
  bad["passes"]["lightning"] = {{"overhead_ms", 0}};
  try {
    GpuProfile::from_json(bad, "x.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("passes.lightning"), std::string::npos) << e.what();
  }
  bad = j;
  bad["passes"]["depth"]["terms"]["pixels"] = 1e-9;
  EXPECT_THROW(GpuProfile::from_json(bad, "x.json"), Error);
  bad = j;
  bad["spec"].erase("fp32_gflops");
  try {
    GpuProfile::from_json(bad, "x.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("spec.fp32_gflops"), std::string::npos) << e.what();
  }
  // A pass must list every one of its terms: a profile written before the reprojection had
  // its sprites would otherwise warp for free.
  bad = j;
  bad["passes"]["reproject"]["terms"] = {{"pixels", 7e-7}, {"holes", 0.0}};
  try {
    GpuProfile::from_json(bad, "old.json");
    FAIL();
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("old.json: passes.reproject.terms"), std::string::npos) << m;
    EXPECT_NE(m.find("missing term(s) sprites, fill_pixels"), std::string::npos) << m;
    EXPECT_NE(m.find("write 0"), std::string::npos) << m;
  }
  bad = j;
  bad["typo_key"] = 1;
  EXPECT_THROW(GpuProfile::from_json(bad, "x.json"), Error);
  EXPECT_THROW(Workload::load("no_such_workload", kModels), Error);
  CostInputs in = base_inputs("nope", nullptr);
  EXPECT_THROW(estimate_frame(GpuProfile::load("gtx1080", kModels), in), Error);
}

TEST(CostModel, WhatIfScalingDividesOneResource) {
  GpuProfile g = GpuProfile::load("gtx1080", kModels);
  CostInputs in = base_inputs("full", nullptr);
  FrameCost a = estimate_frame(g, in);
  FrameCost b = estimate_frame(g.scaled(Resource::Shading, 2.0), in);
  EXPECT_NEAR(b.resource_ms["shading"], a.resource_ms["shading"] / 2, 1e-9);
  EXPECT_NEAR(b.resource_ms["geometry"], a.resource_ms["geometry"], 1e-12);
  EXPECT_THROW(g.scaled(Resource::Memory, 0.0), Error);
}

// Roofline: a pass costs its overhead plus the slowest resource's time; terms of
// the same resource add. Linear: everything adds.
TEST(CostModel, RooflineTakesTheBottleneckResource) {
  Json j = Json::parse(R"({"name": "toy", "model": "roofline",
    "spec": {"fp32_gflops": 1, "mem_gbps": 1, "fill_gpix": 1, "tri_gtris": 1},
    "passes": {"gbuffer": {"overhead_ms": 0.5, "terms": {"tris": 1e-6, "frags": 1e-7, "gbuffer_bytes": 1e-8}},
               "lighting": {"overhead_ms": 0, "terms": {"shade_flops": 0, "vpl_flops": 0}}},
    "interval": {"level": 0.8, "lo_factor": 0.9, "hi_factor": 1.3, "n": 10}})");
  GpuProfile roof = GpuProfile::from_json(j, "toy.json");
  j["model"] = "linear";
  GpuProfile lin = GpuProfile::from_json(j, "toy.json");
  Counters c;
  CostInputs in = base_inputs("full", &c);
  Workload w;
  w.triangles = 1e6, w.lights = 0, w.shadowed_lights = 0, w.overdraw = 1, w.gbuffer_bytes = 16;
  w.pipeline.depth_prepass = false, w.pipeline.tonemap = false;
  in.workload = &w;
  in.display.eyes = 1;
  const double P = 1440.0 * 1600.0;
  const double geo = 1e6 * 1e-6, ras = P * 1e-7, mem = P * 16 * 1e-8;
  FrameCost r = estimate_frame(roof, in), l = estimate_frame(lin, in);
  EXPECT_NEAR(r.pass_ms("gbuffer"), 0.5 + std::max({geo, ras, mem}), 1e-9);
  EXPECT_NEAR(l.pass_ms("gbuffer"), 0.5 + geo + ras + mem, 1e-9);
  EXPECT_NEAR(r.total_lo_ms, 0.9 * r.total_ms, 1e-12);
  EXPECT_NEAR(r.total_hi_ms, 1.3 * r.total_ms, 1e-12);
  j["model"] = "max";
  try {
    GpuProfile::from_json(j, "toy.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("model"), std::string::npos) << e.what();
  }
  j["model"] = "roofline";
  j["interval"]["hi_factor"] = 0.5;
  EXPECT_THROW(GpuProfile::from_json(j, "toy.json"), Error);
}

// A pass of several dependent dispatches costs the sum of their rooflines: TWFR's
// reprojection is the point-sprite warp (sprites vs. their bytes: the slower) and then
// push-pull with the confidence (Franke et al. 2021 §4-§5), so its time is overhead +
// max(sprites, warp bytes) + fill bytes, never the max of all three.
TEST(CostModel, RooflineAddsTheDispatchesOfAPass) {
  const std::vector<Term> terms = {{"sprites", Resource::Geometry, 0, 0},
                                   {"pixels", Resource::Memory, 0, 0},
                                   {"fill_pixels", Resource::Memory, 0, 1},
                                   {"holes", Resource::Memory, 0, 1}};
  std::vector<std::pair<Resource, double>> bound;
  EXPECT_DOUBLE_EQ(roofline_ms(terms, {2.0, 0.5, 1.0, 0.25}, &bound), 2.0 + 1.25);
  ASSERT_EQ(bound.size(), 2u);
  EXPECT_EQ(bound[0].first, Resource::Geometry);
  EXPECT_EQ(bound[1].first, Resource::Memory);
  EXPECT_DOUBLE_EQ(roofline_ms(terms, {0.5, 2.0, 1.0, 0.0}), 2.0 + 1.0);

  Json j = Json::parse(R"({"name": "toy", "model": "roofline",
    "spec": {"fp32_gflops": 1, "mem_gbps": 1, "fill_gpix": 1, "tri_gtris": 1, "l2_mb": 0},
    "passes": {"reproject": {"overhead_ms": 0.1, "terms": {"sprites": 3e-7, "pixels": 1e-7, "fill_pixels": 2e-7, "holes": 0}},
               "gbuffer": {"overhead_ms": 0, "terms": {"tris": 0, "frags": 0, "gbuffer_bytes": 0}},
               "lighting": {"overhead_ms": 0, "terms": {"shade_flops": 0, "vpl_flops": 0}}}})");
  const GpuProfile roof = GpuProfile::from_json(j, "toy.json");
  Counters c;
  CostInputs in = base_inputs("twfr", &c);
  Workload w;
  w.pipeline.depth_prepass = false, w.pipeline.tonemap = false, w.pipeline.ssao = false;
  w.pipeline.taa = false, w.pipeline.skybox = false, w.shadowed_lights = 0;
  in.workload = &w;
  in.display.eyes = 1;
  const double P = 1440.0 * 1600.0;  // every pixel reprojected (the analytic fallback)
  const FrameCost r = estimate_frame(roof, in);
  EXPECT_NEAR(r.pass_ms("reproject"), 0.1 + std::max(3e-7, 1e-7) * P + 2e-7 * P, 1e-9);
  EXPECT_NEAR(r.resource_ms.at("geometry"), 3e-7 * P, 1e-9);
  // A run's sprites are the previous pixels that carried a world position (hole-filled ones
  // are never warped, Franke et al. 2021 §4): counter reproject_splats; push-pull still runs
  // over every pixel.
  c.set(Counter::reproject_splats, 0.25 * P);
  c.set(Counter::reprojected_pixels, 0.2 * P);
  const FrameCost run = estimate_frame(roof, in);
  EXPECT_NEAR(run.pass_ms("reproject"), 0.1 + std::max(3e-7 * 0.25 * P, 1e-7 * 0.2 * P) + 2e-7 * P,
              1e-9);
}
