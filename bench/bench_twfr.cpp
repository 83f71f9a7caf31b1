// TWFR per-frame CPU time at the FOVE resolution (1280x1440, Franke et al. 2021 §8.4), split into
// its stages: reprojection, push-pull, confidence, culling, redraw (masked shading + composition).
// Each iteration renders a full-redraw frame (untimed) then a reprojected frame (timed) after
// a small head motion on the atrium; stage times are reported as counters (ms per frame).
#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>

#include "sim/foveation/frame.h"
#include "sim/foveation/twfr.h"
#include "sim/scene/scene.h"

using namespace fovsim;

namespace {

struct Setup {
  Scene scene;
  Display display;
  std::unique_ptr<Renderer> renderer;
  FrameData a, b;
  explicit Setup(int complexity) {
    Params p(Json{{"type", "atrium"}, {"complexity", complexity}});
    scene = make_scene(p, "");
    display.width = 1280;
    display.height = 1440;
    display.fov_h_deg = 90;
    display.fov_v_deg = 100;
    display.refresh_hz = 70;
    renderer = std::make_unique<Renderer>(scene, RenderSettings{});
    const uint32_t ch = kShadingChannels | kObjectId | kSubModel;
    TraceSample s0, s1;
    s0.head_pos = glm::dvec3(scene.default_eye);
    s1 = s0;
    s1.t = 1.0 / 70.0;
    s1.head_pos += glm::dvec3(0.004, 0, -0.014);                           // ~1 m/s walk
    s1.head_rot = glm::angleAxis(glm::radians(0.6), glm::dvec3(0, 1, 0));  // 42 deg/s turn
    s0.gaze_dir = s1.gaze_dir = glm::normalize(glm::dvec3(0.1, -0.05, -1));
    renderer->set_time(s0.t);
    prepare_frame(*renderer, display, s0, 0, ch, nullptr, a);
    renderer->set_time(s1.t);
    prepare_frame(*renderer, display, s1, 1, ch, &a.camera, b);
  }
};

Setup& setup() {
  static Setup s(3);
  return s;
}

void BM_TwfrFrame(benchmark::State& state) {
  Setup& S = setup();
  TwfrParams p;
  p.conf.epsilon = float(state.range(0)) / 100.f;
  TwfrMethod m(p);
  FrameContext ca = S.a.context(S.scene, *S.renderer, S.display, false);
  FrameContext cb = S.b.context(S.scene, *S.renderer, S.display, false);
  TwfrTimings sum;
  double redrawn = 0, culled = 0, submitted = 0;
  int64_t frames = 0;
  for (auto _ : state) {
    m.reset();
    FrameOutput oa, ob;
    m.render(ca, oa);
    auto t0 = std::chrono::steady_clock::now();
    m.render(cb, ob);
    auto t1 = std::chrono::steady_clock::now();
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
    const TwfrTimings& t = m.timings();
    sum.reproject_ms += t.reproject_ms;
    sum.pushpull_ms += t.pushpull_ms;
    sum.confidence_ms += t.confidence_ms;
    sum.cull_ms += t.cull_ms;
    sum.redraw_ms += t.redraw_ms;
    redrawn += ob.counters.get(Counter::pixels_redrawn);
    culled += ob.counters.get(Counter::prims_foveation_culled);
    submitted += ob.counters.get(Counter::prims_submitted);
    ++frames;
  }
  const double f = double(std::max<int64_t>(frames, 1));
  state.counters["reproject_ms"] = sum.reproject_ms / f;
  state.counters["pushpull_ms"] = sum.pushpull_ms / f;
  state.counters["confidence_ms"] = sum.confidence_ms / f;
  state.counters["cull_ms"] = sum.cull_ms / f;
  state.counters["redraw_ms"] = sum.redraw_ms / f;
  state.counters["redrawn_frac"] = redrawn / f / double(S.b.gbuffer.size());
  state.counters["fov_culled_frac"] = culled / std::max(1.0, culled + submitted);
}
BENCHMARK(BM_TwfrFrame)
    ->Arg(20)
    ->Arg(100)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// Reference point: the full-resolution shading of the same frame (what epsilon = 1 redraws).
void BM_FullShade(benchmark::State& state) {
  Setup& S = setup();
  Image out;
  for (auto _ : state) S.renderer->shade(S.b.gbuffer, S.b.camera.position, out);
}
BENCHMARK(BM_FullShade)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
