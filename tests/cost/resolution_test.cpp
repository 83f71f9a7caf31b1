// Resolution dependence of each pass (docs/cost_model.md "Resolution dependence"): fixed work
// (overheads, shadow maps, the frame's rest), per-pixel work (fragments, bytes, shaded samples,
// rays), per-triangle work, and the L2 working-set factor of gathering passes. Each test states
// what the slope rests on; the references are the seeds' figures that are not withheld (Meng
// 2018 Table 4.1 and §1, Ye et al. 2022 Table 3, Franke et al. 2021 §8.4), never a withheld one.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "sim/cost/analytic.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/workload.h"

using namespace fovsim;

namespace {
const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";

FrameCost predict(const std::string& gpu, const std::string& wl, const std::string& disp, int w,
                  int h, const std::string& method, const Json& params = Json::object()) {
  GpuProfile g = GpuProfile::load(gpu, kModels);
  Workload wk = Workload::load(wl, kModels);
  Display d = Display::load(disp, kModels);
  if (w) d.width = w, d.height = h;
  return analytic_frame(g, method, params, wk, d, "test");
}
FrameCost kfr(const std::string& wl, int w, int h, const std::string& method) {
  return predict("gtx1080", wl, "desktop_1920x1080", w, h, method,
                 method == "kfr" ? Json{{"sigma", 1.8}, {"alpha", 4.0}} : Json::object());
}
// d log(time) / d log(pixels) between two frames.
double slope(double t1, double t2, double pixel_ratio) {
  return std::log(t2 / t1) / std::log(pixel_ratio);
}
}  // namespace

// Meng 2018's pipeline (Falcor deferred, GTX 1080), full resolution, 1920x1080 -> 3840x2160:
// the shadow pass (one 2048^2 map and the scene's triangles) and the frame's rest (present, UI:
// "Total GPU Time" - "Total") do not grow; lighting and the depth prepass grow with the pixels
// (shaded samples, fragments); the G-buffer is triangle-bound at 1080p and byte-bound at 4K, so
// it grows less; the frame as a whole grows less than the pixel count.
TEST(ResolutionSlopes, KfrBistroPassesByKindOfWork) {
  const FrameCost a = kfr("kfr_bistro", 1920, 1080, "full");
  const FrameCost b = kfr("kfr_bistro", 3840, 2160, "full");
  auto s = [&](const char* p) { return slope(a.pass_ms(p), b.pass_ms(p), 4.0); };
  EXPECT_NEAR(s("shadow"), 0.0, 1e-9);
  EXPECT_NEAR(s("frame"), 0.0, 1e-9);
  EXPECT_GT(s("lighting"), 0.97);
  EXPECT_LE(s("lighting"), 1.0 + 1e-9);
  EXPECT_GT(s("depth"), 0.95);
  EXPECT_LE(s("depth"), 1.0 + 1e-9);
  EXPECT_GT(s("gbuffer"), 0.05);
  EXPECT_LT(s("gbuffer"), 0.6);
  const double total = slope(a.total_ms, b.total_ms, 4.0);
  EXPECT_GT(total, 0.8);
  EXPECT_LT(total, 0.97);
}

// The tables' own pixel slope: at one resolution each table shades two pixel counts (full and
// the reduced buffer), and the lighting rows scale with them: Meng 2018 Table 4.1 22.043 / 6.674
// = 3.30 for sigma^2 = 3.24 (slope 1.02), Ye et al. 2022 Table 3 14.63 / 2.04 = 7.17 for 6.76
// (slope 1.03). The model's lighting slope over the same pixel ratio is within 0.12 of both, and
// flatter than RMFR's: the lighting pass's fitted fixed overhead (0.32 ms, set mostly by TWFR's
// foveated shading rows) does not shrink with the buffer (docs/cost_model.md).
TEST(ResolutionSlopes, LightingFollowsShadedPixelsAsTheTablesDo) {
  const double k = slope(6.674, 22.043, 1.8 * 1.8), r = slope(2.04, 14.63, 2.6 * 2.6);
  const double km = slope(kfr("kfr_bistro", 1920, 1080, "kfr").pass_ms("lighting"),
                          kfr("kfr_bistro", 1920, 1080, "full").pass_ms("lighting"), 1.8 * 1.8);
  const FrameCost rf = predict("gtx980", "rmfr_bistro", "htc_vive_pro_eye", 0, 0, "full");
  const FrameCost rr =
      predict("gtx980", "rmfr_bistro", "htc_vive_pro_eye", 0, 0, "rmfr", Json{{"sigma", 2.6}});
  const double rm = slope(rr.pass_ms("lighting"), rf.pass_ms("lighting"), 2.6 * 2.6);
  EXPECT_NEAR(km, k, 0.12);
  EXPECT_NEAR(rm, r, 0.12);
  EXPECT_LT(rm, r);
  EXPECT_GT(km, 0.9);
  EXPECT_GT(rm, 0.9);
}

// Meng 2018: KFR's speedup on the textured meshes is 1.87x at 1920x1080 (Table 4.1, Total GPU
// Time) and "2.8X ... for 3840x2160 displays" (§1), a rise of 50%: the fixed passes' share falls
// as the per-pixel work grows. The model's rise is asserted to be at least 25% and below 60% (it
// reaches 1.86x -> 2.51x: the 4K figure is 10% short, docs/cost_model.md). The ray-casting scene
// is shading-bound at every resolution (its rays are its pixels x 16 samples): its speedup stays
// within 5% and does not fall (Meng 2018 §1: 3.2x at 3840x2160).
TEST(ResolutionSlopes, KfrMeshSpeedupRisesFrom1080pTo4K) {
  auto sp = [](const char* wl, int w, int h) {
    return kfr(wl, w, h, "full").total_ms / kfr(wl, w, h, "kfr").total_ms;
  };
  const double m1 = sp("kfr_bistro", 1920, 1080), m4 = sp("kfr_bistro", 3840, 2160);
  EXPECT_GT(m4 / m1, 1.25) << m1 << " -> " << m4;
  EXPECT_LT(m4 / m1, 1.6) << m1 << " -> " << m4;
  const double r1 = sp("kfr_raymarch", 1920, 1080), r4 = sp("kfr_raymarch", 3840, 2160);
  EXPECT_GE(r4, r1);
  EXPECT_NEAR(r4 / r1, 1.0, 0.05);
  // Ray casting: the lighting pass's time is proportional to the rays (shaded samples).
  const double l1 = kfr("kfr_raymarch", 1920, 1080, "full").pass_ms("lighting");
  const double l4 = kfr("kfr_raymarch", 3840, 2160, "full").pass_ms("lighting");
  EXPECT_NEAR(slope(l1, l4, 4.0), 1.0, 0.01);
}

// The working-set factor of TWFR's reprojection (Franke et al. 2021 §4 gathers the previous frame
// at reprojected positions): DRAM traffic is the L2 miss fraction max(0, 1 - L2 / (W H 16 B)) of
// the profile's own cache (spec.l2_mb); it grows with the resolution and shrinks with the cache,
// so reprojection grows slightly faster than the pixels (Franke et al. 2021 §8.4: "almost
// linearly"); streaming passes keep 1.
TEST(ResolutionSlopes, ReprojectionMissFractionFollowsTheProfilesL2) {
  GpuSpec s;
  s.l2_mb = 4;  // RTX 2070
  Display fove, k8;
  fove.width = 1280, fove.height = 1440;
  k8.width = 3840, k8.height = 1440;
  const double f1 = working_set_factor("reproject", "pixels", s, fove);
  const double f3 = working_set_factor("reproject", "pixels", s, k8);
  EXPECT_NEAR(f1, 1.0 - 4.0 * 1024 * 1024 / (1280.0 * 1440 * 16), 1e-12);
  EXPECT_GT(f3, f1);
  EXPECT_LT(f3, 1.0);
  GpuSpec big = s;
  big.l2_mb = 5.5;  // RTX 2080 Ti
  EXPECT_LT(working_set_factor("reproject", "pixels", big, fove), f1);
  GpuSpec none = s;
  none.l2_mb = 0;  // unknown cache: no working-set effect
  EXPECT_EQ(working_set_factor("reproject", "pixels", none, fove), 1.0);
  EXPECT_EQ(working_set_factor("taa", "pixels", s, k8), 1.0);
  // Both dispatches of the reprojection (the sprite warp and push-pull) see the same miss
  // fraction; the hole counts are already per mip level.
  EXPECT_EQ(working_set_factor("reproject", "sprites", s, fove), f1);
  EXPECT_EQ(working_set_factor("reproject", "fill_pixels", s, fove), f1);
  EXPECT_EQ(working_set_factor("reproject", "holes", s, fove), 1.0);
  // An L2 that holds the eye's buffers (RTX 4090, 72 MB) takes the DRAM traffic away, not the
  // sprites' primitive work: they still cost one primitive each at the peak rate.
  const GpuProfile g4090 = GpuProfile::load("rtx4090", kModels);
  EXPECT_EQ(working_set_factor("reproject", "sprites", g4090.spec, fove), 0.0);
  const double sprites_at_peak = 1280.0 * 1440 * 2 / g4090.spec.rate_per_ms(Resource::Geometry);
  EXPECT_GE(
      predict("rtx4090", "twfr_bistro", "fove_1280x1440", 1280, 1440, "twfr").pass_ms("reproject"),
      sprites_at_peak);
  // On the calibrated GPU the fitted sprite cost stays above the peak rate (the floor above is
  // not what the fit saw).
  const GpuProfile g2070 = GpuProfile::load("rtx2070", kModels);
  EXPECT_GT(g2070.coef("reproject", "sprites") * f1 * g2070.spec.rate_per_ms(Resource::Geometry),
            1.0);
  const double a =
      predict("rtx2070", "twfr_bistro", "fove_1280x1440", 1280, 1440, "twfr").pass_ms("reproject");
  const double b =
      predict("rtx2070", "twfr_bistro", "fove_1280x1440", 3840, 1440, "twfr").pass_ms("reproject");
  const double sl = slope(a, b, 3.0);
  EXPECT_GT(sl, 0.9);
  EXPECT_LT(sl, 1.15);
}

// Every calibrated GPU's profile carries its published L2 size (spec sheets: GM204 and GP104
// 2 MB, TU106 4 MB, TU102 5.5 MB).
TEST(ResolutionSlopes, CalibratedProfilesCarryTheirL2) {
  const std::pair<const char*, double> l2[] = {
      {"gtx980", 2}, {"gtx1080", 2}, {"rtx2070", 4}, {"rtx2080ti", 5.5}};
  for (auto& [gpu, mb] : l2) EXPECT_EQ(GpuProfile::load(gpu, kModels).spec.l2_mb, mb) << gpu;
}
