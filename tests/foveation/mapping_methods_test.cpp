// Rendering tests of kfr, rmfr, hyperbolic, linear, fvrs: the extremes suite (finite output,
// counts in [0, W H] at sigma/alpha/fx/fy extremes and gaze on centre, pixel centre, edges,
// corners, off-screen), identity settings, monotonic quality in sigma, and the seed trends
// (1/sigma^2 shading, RMFR vs KFR FPSNR on rotating patterns, KFR alpha on the atrium).
// PSNR / FPSNR are computed locally (test_foveation links only fovsim_foveation).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "sim/foveation/density.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/frame.h"
#include "sim/trace/tracking.h"
#include "tests/common/method_lists.h"

using namespace fovsim;

namespace {

Display small_display(int W, int H, double fov_h = 90.0) {
  Display d;
  d.width = W;
  d.height = H;
  d.fov_h_deg = fov_h;
  d.fov_v_deg = rad2deg(2.0 * std::atan(std::tan(deg2rad(fov_h) * 0.5) * H / W));  // square pixels
  return d;
}

struct World {
  Display d;
  Scene scene;
  std::unique_ptr<Renderer> r;
  FrameData fd;
  ToneMap tm;
  World(const Json& scene_json, int W, int H, double fov_h = 90.0) : d(small_display(W, H, fov_h)) {
    Params p(scene_json, "test");
    scene = make_scene(p, std::string(FOVSIM_SOURCE_DIR) + "/models");
    r = std::make_unique<Renderer>(scene, RenderSettings{});
    tm.exposure = scene.exposure;
    TraceSample s;
    s.head_pos = glm::dvec3(scene.default_eye);
    prepare_frame(*r, d, s, 0, kShadingChannels, nullptr, fd);
  }
  // Moves the gaze to an exact pixel point (may be off-screen) and rebuilds the eccentricity.
  void set_gaze(glm::dvec2 g) {
    fd.gaze_px = g;
    fd.gaze_dir = glm::normalize(fd.camera.dir_head(g.x, g.y));
    fd.eccentricity = eccentricity_map(fd.camera, fd.gaze_dir);
  }
  FrameOutput run(const std::string& method, Json params, int frame = 0) {
    Params p(params, "test");
    auto m = make_method(method, p);
    FrameContext ctx = fd.context(scene, *r, d, false);
    ctx.frame = frame;
    FrameOutput out;
    m->render(ctx, out);
    return out;
  }
  Image display(const Image& lin) const {
    Image o;
    tm.apply(lin, o);
    return o;
  }
  // Writes an image to $FOVSIM_TEST_DUMP/<name>.png when that variable is set (debugging aid).
  void dump(const std::string& name, const Image& lin) const {
    if (const char* dir = std::getenv("FOVSIM_TEST_DUMP"))
      write_image(std::string(dir) + "/" + name + ".png", display(lin));
  }
};

double psnr(const Image& a, const Image& b) {
  double se = 0;
  for (size_t i = 0; i < a.data.size(); ++i)
    se += double(a.data[i] - b.data[i]) * (a.data[i] - b.data[i]);
  double mse = se / double(a.data.size());
  return mse <= 0 ? 200.0 : 10.0 * std::log10(1.0 / mse);
}

// FPSNR (Lee, Pattichis, Bovik 2002): weights f_c(e) = e2 ln(1/CT0) / (alpha (e + e2)),
// CT0 = 1/64, alpha = 0.106, e2 = 2.3 deg, clipped at the local Nyquist ppd/2.
double fpsnr(const Image& a, const Image& b, const World& w) {
  const Camera& cam = w.fd.camera;
  double num = 0, den = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const double e = w.fd.eccentricity[size_t(y) * size_t(a.width) + size_t(x)];
      double fc = 2.3 * std::log(64.0) / (0.106 * (e + 2.3));
      fc = std::min(fc, 0.5 * cam.ppd_at(x + 0.5, y + 0.5));
      double se = 0;
      for (int c = 0; c < 3; ++c) {
        double d = a.at(x, y)[c] - b.at(x, y)[c];
        se += d * d;
      }
      num += fc * fc * se / 3.0;
      den += fc * fc;
    }
  double mse = num / den;
  return mse <= 0 ? 200.0 : 10.0 * std::log10(1.0 / mse);
}

double rmse_periphery(const Image& a, const Image& b, const World& w, double fovea_deg) {
  double se = 0, n = 0;
  for (size_t i = 0; i < a.pixels(); ++i) {
    if (w.fd.eccentricity[i] <= fovea_deg) continue;
    for (int c = 0; c < 3; ++c) {
      double d = a.data[i * 3 + size_t(c)] - b.data[i * 3 + size_t(c)];
      se += d * d;
    }
    n += 3;
  }
  return std::sqrt(se / std::max(n, 1.0));
}

void expect_sane(const FrameOutput& out, int W, int H, const std::string& what) {
  ASSERT_EQ(out.image.width, W) << what;
  ASSERT_EQ(out.image.height, H) << what;
  for (float v : out.image.data) ASSERT_TRUE(std::isfinite(v)) << what;
  const double total = double(W) * H;
  for (Counter k : {Counter::shaded_samples, Counter::gbuffer_samples, Counter::buffer_pixels_used,
                    Counter::fullres_pixels}) {
    ASSERT_TRUE(out.counters.has(k)) << what << " " << counter_name(k);
    double v = out.counters.get(k);
    ASSERT_TRUE(std::isfinite(v)) << what;
    ASSERT_GE(v, 0) << what << " " << counter_name(k);
    ASSERT_LE(v, total) << what << " " << counter_name(k);
  }
  ASSERT_LE(out.counters.get(Counter::buffer_pixels_used),
            out.counters.get(Counter::buffer_pixels_allocated))
      << what;
  ASSERT_TRUE(std::isfinite(out.counters.get(Counter::filter_taps))) << what;
}

const int kW = 96, kH = 80;
std::vector<glm::dvec2> gazes() {
  return {{kW * 0.5, kH * 0.5},
          {30.5, 20.5},
          {0, kH * 0.5},
          {kW, kH * 0.5},
          {kW * 0.5, 0},
          {kW * 0.5, kH},
          {0, 0},
          {kW, 0},
          {0, kH},
          {kW, kH},
          {-50, 30},
          {kW + 1e6, -1e6}};
}
// Grating (3 octaves from `frequency` cycles per metre on a plane 1 m away): resolvable at 96 px.
const Json kPatterns = {{"type", "patterns"}, {"pattern", "grating"}, {"frequency", 1.5}};

}  // namespace

TEST(MappingExtremes, KfrSigmaAlphaGazeGrid) {
  World w(kPatterns, kW, kH);
  for (auto g : gazes()) {
    w.set_gaze(g);
    for (double sg : {1.0, 1.0 + 1e-9, 1.8, 2.6, 8.0, 32.0})
      for (double a : {0.25, 0.5, 1.0, 4.0, 8.0, 16.0}) {
        char what[128];
        std::snprintf(what, sizeof what, "kfr sigma=%g alpha=%g gaze=(%g,%g)", sg, a, g.x, g.y);
        auto out = w.run("kfr", {{"sigma", sg}, {"alpha", a}});
        expect_sane(out, kW, kH, what);
        ASSERT_LE(out.counters.get(Counter::buffer_pixels_allocated), double(kW) * kH) << what;
      }
    for (const char* k : {"sine", "exp"}) expect_sane(w.run("kfr", {{"kernel", k}}), kW, kH, k);
  }
}

TEST(MappingExtremes, RmfrSigmaFxFyGazeGrid) {
  World w(kPatterns, kW, kH);
  // 0.01: the smallest f RMFR's table accepts (below it the samples collapse onto the gaze).
  const double fs[] = {0.01, 0.05, 0.38, 1.0, 1e9};
  for (auto g : gazes()) {
    w.set_gaze(g);
    for (double sg : {1.0, 1.0 + 1e-9, 1.8, 2.6, 8.0, 32.0})
      for (double fx : fs)
        for (double fy : fs) {
          if (sg != 1.0 && sg != 2.6 && sg != 32.0 && (fx != 0.38 || fy != 0.38)) continue;
          char what[160];
          std::snprintf(what, sizeof what, "rmfr sigma=%g fx=%g fy=%g gaze=(%g,%g)", sg, fx, fy,
                        g.x, g.y);
          auto out = w.run("rmfr", {{"sigma", sg}, {"fx", fx}, {"fy", fy}});
          expect_sane(out, kW, kH, what);
          // RMFR fills its whole buffer.
          ASSERT_EQ(out.counters.get(Counter::buffer_pixels_used),
                    out.counters.get(Counter::buffer_pixels_allocated))
              << what;
        }
  }
}

TEST(MappingExtremes, BaselinesGazeGrid) {
  World w(kPatterns, kW, kH);
  for (auto g : gazes()) {
    w.set_gaze(g);
    for (double rs : {1e-3, 1.0, 1e3})
      for (const std::string& m : test::radial_methods()) {
        char what[128];
        std::snprintf(what, sizeof what, "%s radius_scale=%g gaze=(%g,%g)", m.c_str(), rs, g.x,
                      g.y);
        expect_sane(w.run(m, {{"radius_scale", rs}}), kW, kH, what);
      }
  }
}

// Identity-like settings reproduce the reference: rmfr sigma = 1 with fx, fy -> inf is the
// identity map (bound: exact, PSNR capped at 200 dB); the baselines at full rate likewise.
// kfr has no identity setting: at sigma = 1, alpha = 1, without filters it stays >= 20 dB
// (measured 23.1 dB on this grating; log-polar undersampling of the periphery remains).
TEST(MappingIdentity, SigmaOneReproducesReference) {
  World w(kPatterns, kW, kH);
  w.set_gaze({30.5, 20.5});
  const Image ref = w.display(w.fd.reference);
  auto p_rmfr = psnr(
      w.display(w.run("rmfr", {{"sigma", 1.0}, {"fx", 1e9}, {"fy", 1e9}, {"taa", false}}).image),
      ref);  // TAA's jitter moves the samples off the pixel centres
  EXPECT_GE(p_rmfr, 100.0);
  EXPECT_GE(psnr(w.display(w.run("hyperbolic", {{"s2", 1.0}, {"s3", 1.0}}).image), ref), 100.0);
  EXPECT_GE(psnr(w.display(w.run("linear", {{"p_min", 1.0}}).image), ref), 100.0);
  EXPECT_GE(psnr(w.display(w.run("fvrs", {{"r1", 180.0}, {"r2", 180.0}}).image), ref), 100.0);
  auto kfr =
      w.run("kfr", {{"sigma", 1.0}, {"alpha", 1.0}, {"internal_aa", false}, {"post_aa", false}});
  double p_kfr = psnr(w.display(kfr.image), ref);
  w.dump("identity_ref", w.fd.reference);
  w.dump("identity_kfr", kfr.image);
  std::printf("[identity] kfr sigma=1 alpha=1 no AA: PSNR %.2f dB\n", p_kfr);
  EXPECT_GE(p_kfr, 20.0);
}

// PSNR and FPSNR do not increase with sigma (tolerance 0.05 dB for resampling noise).
TEST(MappingTrends, QualityNonIncreasingInSigma) {
  World w({{"type", "patterns"}, {"pattern", "grating"}, {"frequency", 3.0}}, 192, 160);
  w.set_gaze({96, 80});
  const Image ref = w.display(w.fd.reference);
  // The subset with one buffer of W/sigma x H/sigma (rmfr_auto: f chosen per frame).
  for (const char* m : {"kfr", "rmfr"}) {
    double prev_p = 1e9, prev_f = 1e9;
    for (double sg : {1.0, 1.8, 2.6, 8.0, 32.0}) {
      Image img = w.display(w.run(m, {{"sigma", sg}}).image);
      double p = psnr(img, ref), f = fpsnr(img, ref, w);
      std::printf("[sigma] %s sigma=%g PSNR %.2f FPSNR %.2f\n", m, sg, p, f);
      EXPECT_LE(p, prev_p + 0.05) << m << " sigma=" << sg;
      EXPECT_LE(f, prev_f + 0.05) << m << " sigma=" << sg;
      prev_p = p;
      prev_f = f;
    }
  }
}

// Ye et al. 2022 §6.1 / Meng 2018 eq. 2.8: shaded samples fall as 1/sigma^2.
TEST(MappingTrends, ShadedSamplesFallAsInverseSigmaSquared) {
  World w({{"type", "patterns"}, {"pattern", "grating"}, {"frequency", 3.0}}, 192, 160);
  w.set_gaze({96, 80});
  // The subset with one buffer of W/sigma x H/sigma (rmfr_auto: f chosen per frame).
  for (const char* m : {"kfr", "rmfr"}) {
    double a = w.run(m, {{"sigma", 1.3}}).counters.get(Counter::shaded_samples);
    double b = w.run(m, {{"sigma", 2.6}}).counters.get(Counter::shaded_samples);
    double c = w.run(m, {{"sigma", 5.2}}).counters.get(Counter::shaded_samples);
    std::printf("[1/sigma^2] %s shaded 1.3: %.0f 2.6: %.0f 5.2: %.0f ratios %.3f %.3f\n", m, a, b,
                c, a / b, b / c);
    EXPECT_NEAR(a / b, 4.0, 0.15) << m;
    EXPECT_NEAR(b / c, 4.0, 0.2) << m;
  }
}

// Ye et al. 2022 §6.1, Fig. 12: on rotating patterns (0..180 deg), RMFR's mean FPSNR exceeds KFR's
// at sigma = 2.6 (KFR alpha = 4, RMFR fx = fy = 0.38, the Fig. 7 settings).
TEST(MappingTrends, RmfrBeatsKfrOnRotatingPatterns) {
  double sum_k = 0, sum_r = 0;
  int n = 0;
  for (double ang = 0; ang <= 180; ang += 30) {
    World w({{"type", "patterns"}, {"pattern", "stripes"}, {"frequency", 8.0}, {"angle", ang}}, 192,
            160);
    w.set_gaze({96, 80});
    const Image ref = w.display(w.fd.reference);
    sum_k += fpsnr(w.display(w.run("kfr", {{"sigma", 2.6}, {"alpha", 4.0}}).image), ref, w);
    sum_r += fpsnr(w.display(w.run("rmfr", {{"sigma", 2.6}}).image), ref, w);
    ++n;
  }
  std::printf("[fig12] mean FPSNR over %d angles: rmfr %.2f dB, kfr %.2f dB\n", n, sum_r / n,
              sum_k / n);
  EXPECT_GT(sum_r / n, sum_k / n);
}

// Meng 2018 Fig. 1.17: at sigma = 1.8 on the atrium, KFR's peripheral error falls as alpha
// grows from 1 to 4.
TEST(MappingTrends, KfrPeripheralErrorFallsWithAlpha) {
  World w({{"type", "atrium"}, {"complexity", 1}}, 256, 144, 100.0);  // 2560x1440 / 10, FOVE FOV
  w.set_gaze({128, 72});
  const Image ref = w.display(w.fd.reference);
  double prev = 1e9, first = 0, last = 0;
  for (double a : {1.0, 2.0, 3.0, 4.0}) {
    double e =
        rmse_periphery(w.display(w.run("kfr", {{"sigma", 1.8}, {"alpha", a}}).image), ref, w, 5.0);
    std::printf("[fig1.17] kfr sigma=1.8 alpha=%g peripheral RMSE %.5f\n", a, e);
    EXPECT_LE(e, prev * 1.01) << "alpha=" << a;
    if (a == 1.0) first = e;
    last = e;
    prev = e;
  }
  EXPECT_LT(last, first);
}

TEST(MappingMethods, DebugBuffersAndDeterminism) {
  World w(kPatterns, kW, kH);
  w.set_gaze({40.5, 30.5});
  // Without TAA: its jitter moves the LP samples (the analytic count is of the unjittered map).
  Params p(Json{{"sigma", 2.0}, {"taa", false}}, "t");
  auto m = make_method("kfr", p);
  FrameContext ctx = w.fd.context(w.scene, *w.r, w.d, true);
  FrameOutput a, b;
  m->render(ctx, a);
  m->render(ctx, b);
  EXPECT_EQ(a.image.data, b.image.data);
  std::vector<std::string> names;
  for (auto& kv : a.debug) names.push_back(kv.first);
  EXPECT_NE(std::find(names.begin(), names.end(), "lp_buffer"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "sample_density"), names.end());
  // KFR leaves LP pixels unused; analytic count == measured count.
  EXPECT_LT(a.counters.get(Counter::buffer_pixels_used),
            a.counters.get(Counter::buffer_pixels_allocated));
  MappingSpec s = MappingSpec::from_params("kfr", *std::make_unique<Params>(Json{{"sigma", 2.0}}));
  MappingView v = MappingView::at(w.fd.camera, w.fd.gaze_px);
  EXPECT_EQ(expected_shaded_samples(s, v), a.counters.get(Counter::shaded_samples));
  // The iso-budget target reports its resolved sigma.
  Params q(Json{{"target_shaded_fraction", 0.25}}, "t");
  auto iso = make_method("rmfr", q);
  FrameOutput c;
  iso->render(ctx, c);
  EXPECT_NEAR(iso->param_columns()[0].second, 2.0, 1e-9);
  EXPECT_NEAR(c.counters.get(Counter::shaded_samples) / (kW * kH), 0.25, 0.01);
}

// rmfr_auto (f_x*, f_y* from the previous frame's peripheral edge orientation): the first
// frame splits f_sum evenly; then stripes at 0 and 90 degrees get opposite axis preferences
// (Ye et al. 2022 §4.4.1: flat lines -> small f_x, steep lines -> small f_y); shading and counters
// are RMFR's at the same sigma; the method exposes an RMFR sampling geometry.
TEST(RmfrAuto, AxisPreferenceFollowsEdgeOrientation) {
  double fx[2], fy[2];
  for (int k = 0; k < 2; ++k) {
    World w({{"type", "patterns"}, {"pattern", "stripes"}, {"frequency", 8.0}, {"angle", 90.0 * k}},
            192, 160);
    w.set_gaze({96, 80});
    // Without TAA: frame 1's jitter would differ from the fixed RMFR's frame 0 below.
    Params p(Json{{"sigma", 2.6}, {"adapt", 1.0}, {"taa", false}}, "t");
    auto m = make_method("rmfr_auto", p);
    FrameContext ctx = w.fd.context(w.scene, *w.r, w.d, false);
    FrameOutput o0, o1;
    m->render(ctx, o0);
    auto cols = m->param_columns();
    EXPECT_DOUBLE_EQ(cols[1].second, 0.38);  // f_sum / 2
    EXPECT_DOUBLE_EQ(cols[2].second, 0.38);
    ctx.frame = 1;
    m->render(ctx, o1);
    cols = m->param_columns();
    fx[k] = cols[1].second;
    fy[k] = cols[2].second;
    EXPECT_GE(std::min(fx[k], fy[k]), 0.1);  // f_min, f_max clamps
    EXPECT_LE(std::max(fx[k], fy[k]), 0.8);
    ASSERT_NE(m->mapping_spec(), nullptr);
    EXPECT_EQ(m->mapping_spec()->method(), "rmfr");
    const FrameOutput r =
        w.run("rmfr", {{"sigma", 2.6}, {"fx", fx[k]}, {"fy", fy[k]}, {"taa", false}});
    EXPECT_EQ(o1.counters.get(Counter::shaded_samples), r.counters.get(Counter::shaded_samples));
    EXPECT_EQ(o1.image.data, r.image.data);
    std::printf("[rmfr_auto] stripes at %d deg: fx %.2f fy %.2f\n", 90 * k, fx[k], fy[k]);
  }
  // Opposite preferences, each well away from the even split.
  EXPECT_LT((fx[0] - fy[0]) * (fx[1] - fy[1]), 0.0);
  EXPECT_GT(std::fabs(fx[0] - fy[0]), 0.2);
  EXPECT_GT(std::fabs(fx[1] - fy[1]), 0.2);
}

// Ye et al. 2022 §6.1's rotating patterns: choosing f_x, f_y per frame from the image beats RMFR's
// fixed 0.38 / 0.38 in mean FPSNR at the same sigma (the same shading cost).
TEST(RmfrAuto, BeatsFixedRmfrOnRotatingPatterns) {
  double sum_a = 0, sum_r = 0;
  int n = 0;
  for (double ang = 0; ang <= 180; ang += 30) {
    World w({{"type", "patterns"}, {"pattern", "stripes"}, {"frequency", 8.0}, {"angle", ang}}, 192,
            160);
    w.set_gaze({96, 80});
    const Image ref = w.display(w.fd.reference);
    Params p(Json{{"sigma", 2.6}}, "t");
    auto m = make_method("rmfr_auto", p);
    FrameContext ctx = w.fd.context(w.scene, *w.r, w.d, false);
    FrameOutput o;
    for (int f = 0; f < 4; ++f) {
      ctx.frame = f;
      o = FrameOutput();
      m->render(ctx, o);
    }
    sum_a += fpsnr(w.display(o.image), ref, w);
    sum_r += fpsnr(w.display(w.run("rmfr", {{"sigma", 2.6}}).image), ref, w);
    ++n;
  }
  std::printf("[rmfr_auto] mean FPSNR over %d angles: rmfr_auto %.2f dB, rmfr %.2f dB\n", n,
              sum_a / n, sum_r / n);
  EXPECT_GT(sum_a / n, sum_r / n);
}

// Tracking loss with trace.on_invalid = widen (docs/tracking.md): every foveated method's
// shaded fraction grows with the time since the last valid sample. kfr and rmfr (and
// rmfr_auto, which renders through rmfr) shrink sigma (rmfr also grows fx, fy); the baselines
// divide eccentricity by k (the map the engine hands them, and MappingView::ecc_deg). A valid
// frame (k = 1) is bit-identical to a frame rendered without the policy.
TEST(TrackingWiden, ShadedFractionGrowsWithTimeSinceLastValidSample) {
  World w(kPatterns, kW, kH);
  w.set_gaze({40.5, 35.5});
  Trace tr;  // 90 Hz: samples 0-2 valid, then tracking is lost
  for (int k = 0; k < 12; ++k) {
    TraceSample s;
    s.t = k / 90.0;
    s.valid = k < 3;
    tr.samples.push_back(s);
  }
  TrackingPolicy pol;
  pol.on_invalid = OnInvalid::Widen;
  pol.widen_per_s = 4;  // k = 1.1 ... 1.4 over the lost frames: kfr's sigma stays above 1
  auto run = [&](const std::string& m, const TrackedGaze& g) {
    std::vector<float> ecc = w.fd.eccentricity;
    for (float& e : ecc) e = float(double(e) * g.ecc_scale);  // as the engine does
    Params p(Json::object(), "test");
    auto meth = make_method(m, p);
    FrameContext ctx = w.fd.context(w.scene, *w.r, w.d, false);
    ctx.widen = g.widen;
    if (!g.valid) ctx.eccentricity = &ecc;
    FrameOutput out;
    meth->render(ctx, out);
    return out;
  };
  // Every method with a sampling geometry, from the registry (a new one is covered).
  for (const std::string& name : methods_with_sampling_geometry()) {
    const char* m = name.c_str();
    const FrameOutput plain = w.run(m, Json::object());
    const FrameOutput valid = run(m, tracked_gaze(tr, 2, pol));
    EXPECT_EQ(valid.counters.get(Counter::shaded_samples),
              plain.counters.get(Counter::shaded_samples))
        << m;
    EXPECT_EQ(valid.image.data, plain.image.data) << m;
    double prev = plain.counters.get(Counter::shaded_samples);
    for (size_t i : {3, 5, 8, 11}) {
      const TrackedGaze g = tracked_gaze(tr, i, pol);
      const double n = run(m, g).counters.get(Counter::shaded_samples);
      std::printf("[widen] %s dt=%.3f s k=%.3f shaded %.0f\n", m, g.since_valid_s, g.widen, n);
      EXPECT_GT(n, prev) << m << " k=" << g.widen;
      prev = n;
    }
  }
}
