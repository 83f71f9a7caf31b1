// CPU time of the image metrics of one frame pair at the quickstart's resolution
// (configs/quickstart.json: htc_vive_pro_eye at render.scale 0.25 = 360x400, atrium complexity
// 1), the "metrics" phase of `fovsim run` split per metric. The pair is the display-encoded
// (ACES + sRGB, the run's tone map) reference of a frame and KFR's output for it (default
// parameters, sigma 1.8), built once and not timed.
//
// metrics/<name>: compute_metrics with only that metric enabled, as the run calls it (one
// MetricsScratch kept across iterations, so FLIP's prepared reference is reused as it is for
// every method of a frame). all = every metric (the run's default config); errsums = psnr +
// fpsnr + regions (one fused pass over the error); ssim (the reference's statistics prepared
// once, as in a run); flip = preparing the test image + the FLIP map and its mean (the FLIP bands
// need regions, so they are only in all); temporal = the temporal error after a first frame.
// BM_FlipRefPrepare = preparing the reference for FLIP, done once per frame.
// FovVideoVDP (Mantiuk et al. 2021), foveated, as a video at the display's 90 Hz with the gaze
// of the frame: BM_FvvdpMethodFrame = one method-frame with the reference side of the frame
// prepared (the per-method marginal cost: the test's temporal filtering, pyramid, masking and
// pooling); BM_FvvdpReference = the reference side of one frame (temporal filtering, pyramid,
// adaptation, CSF), done once per frame for all methods; BM_FvvdpImage = the still-image path
// (test side) for comparison. Time column: ms per call at the given TBB thread count (1: the
// calling thread's CPU time). The `_native` cases are the same at the headset's own 1440x1600
// per eye (render.scale 1, the resolution the perceptual verdicts need): FovVideoVDP's cost per
// megapixel and as a ratio to FLIP on that frame (bench/report.sh prints both).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <memory>
#include <string>

#include "sim/foveation/factory.h"
#include "sim/foveation/frame.h"
#include "sim/metrics/frame_metric.h"
#include "sim/metrics/fvvdp.h"
#include "sim/metrics/metrics.h"
#include "sim/scene/scene.h"

using namespace fovsim;

namespace {

struct Setup {
  Display display;
  Camera camera;
  std::vector<float> ecc;
  Image ref, test;  // display-encoded

  explicit Setup(double scale) {
    const std::string models = std::string(FOVSIM_SOURCE_DIR) + "/models";
    Params sp(Json{{"type", "atrium"}, {"complexity", 1}}, "bench");
    Scene scene = make_scene(sp, models);
    display = Display::load("htc_vive_pro_eye", models).scaled(scale);
    Renderer renderer(scene, RenderSettings{});
    Params mp(Json::object(), "bench");
    std::unique_ptr<FoveationMethod> kfr = make_method("kfr", mp);
    TraceSample s;
    s.head_pos = glm::dvec3(scene.default_eye);
    s.gaze_dir = glm::normalize(glm::dvec3(0.15, -0.05, -1));
    FrameData fd;
    prepare_frame(renderer, display, s, 0, kShadingChannels | kfr->required_channels(), nullptr,
                  fd);
    FrameOutput out;
    kfr->render(fd.context(scene, renderer, display, false), out);
    ToneMap tm;
    tm.exposure = scene.exposure;
    tm.apply(fd.reference, ref);
    tm.apply(out.image_is_reference ? fd.reference : out.image, test);
    camera = fd.camera;
    ecc = fd.eccentricity;
  }
};

// The quickstart's render.scale 0.25 (360x400), or the display's own resolution.
Setup& setup(bool native = false) {
  static Setup quarter(0.25);
  if (!native) return quarter;
  static Setup full(1.0);
  return full;
}

MetricsConfig only(const std::string& name) {
  MetricsConfig c;
  if (name == "all") return c;
  for (const FrameMetric& m : frame_metrics()) c.set(m.toggle.key, false);
  if (name == "errsums")
    for (const char* k : {"psnr", "fpsnr", "regions"}) c.set(k, true);
  if (name == "ssim") c.set("ssim", true);
  if (name == "flip") c.set("flip", true);  // the mean only (its bands come with regions, in "all")
  if (name == "temporal") c.set("temporal", true);
  return c;
}

void BM_Metrics(benchmark::State& state, std::string name, bool native = false) {
  Setup& S = setup(native);
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
  const MetricsConfig cfg = only(name);
  MetricsScratch scratch;
  TemporalState temporal;
  // Warm-up: the reference is prepared, the scratch sized, the temporal state has a frame.
  compute_metrics(cfg, S.test, S.ref, S.camera, S.ecc, &temporal, &scratch);
  for (auto _ : state) {
    MetricValues c = compute_metrics(cfg, S.test, S.ref, S.camera, S.ecc, &temporal, &scratch);
    benchmark::DoNotOptimize(c);
  }
  state.counters["pixels"] = double(S.ref.pixels());
}

void BM_FlipRefPrepare(benchmark::State& state) {
  Setup& S = setup();
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
  FlipPrepared p;
  FlipWorkspace ws;
  const double ppd = flip_ppd(S.camera);
  flip_prepare(S.ref, ppd, p, &ws);
  for (auto _ : state) {
    flip_prepare(S.ref, ppd, p, &ws);
    benchmark::DoNotOptimize(p.L.data());
  }
  state.counters["ppd"] = ppd;
}

struct FvvdpSetup {
  FvvdpDisplay display;
  double gx = 0, gy = 0;
  explicit FvvdpSetup(const Setup& S) {
    const std::string models = std::string(FOVSIM_SOURCE_DIR) + "/models";
    display = FvvdpDisplay::from_display(Display::load("htc_vive_pro_eye", models))
                  .scaled_to(S.ref.width, S.ref.height);
    glm::dvec2 px;
    if (S.camera.project_head(glm::normalize(glm::dvec3(0.15, -0.05, -1)), px)) {
      gx = px.x;
      gy = px.y;
    }
  }
};

void BM_FvvdpMethodFrame(benchmark::State& state, bool video, bool native = false) {
  Setup& S = setup(native);
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
  FvvdpSetup F(S);
  FvvdpOptions opt;
  opt.fps = video ? 90.0 : 0.0;
  opt.foveated = true;
  FvvdpReferenceStream ref(F.display, S.ref.width, S.ref.height, opt);
  FvvdpTestStream test(ref);
  ref.push(S.ref, F.gx, F.gy);
  test.push(S.test, ref);
  for (auto _ : state) {  // steady state: the histories are full
    state.PauseTiming();
    ref.push(S.ref, F.gx, F.gy);
    state.ResumeTiming();
    benchmark::DoNotOptimize(test.push(S.test, ref));
  }
  state.counters["bands"] = ref.bands();
  state.counters["ppd"] = F.display.ppd;
  state.counters["pixels"] = double(S.ref.pixels());
}

void BM_FvvdpReference(benchmark::State& state, bool native = false) {
  Setup& S = setup(native);
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
  FvvdpSetup F(S);
  FvvdpReferenceStream ref(F.display, S.ref.width, S.ref.height, {90.0, true});
  ref.push(S.ref, F.gx, F.gy);
  for (auto _ : state) ref.push(S.ref, F.gx, F.gy);
  state.counters["pixels"] = double(S.ref.pixels());
}

}  // namespace

BENCHMARK_CAPTURE(BM_FvvdpMethodFrame, video, true)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FvvdpMethodFrame, image, false)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FvvdpReference, quarter, false)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FvvdpMethodFrame, video_native, true, true)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FvvdpReference, native, true)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Metrics, flip_native, std::string("flip"), true)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Metrics, all, std::string("all"))->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Metrics, errsums, std::string("errsums"))
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Metrics, ssim, std::string("ssim"))->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Metrics, flip, std::string("flip"))->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Metrics, temporal, std::string("temporal"))
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FlipRefPrepare)->Arg(1)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
