// FLC per-frame CPU time split by stage, like the seed's Table 2 (Google Benchmark; not a test).
//   BM_FlcFrame/<budget>/<visibility>: one FLC frame at 1024x1024 (seed §7) on the Cornell box,
//     64x64 RSM, gaze on the red wall; the ground truth is cached (rendered before timing), so
//     the Time column is FLC's own frame time. Counters: ms per stage (rsm_ms, importance_ms,
//     sampling_ms, contribution_ms, culling_ms, shading_ms, compose_ms), vpls_total, vpls_kept.
//     visibility: 0 none, 1 blso, 2 exact.
//   BM_FlcGroundTruth: shading with all VPLs (the seed's TBDS role) at 1024x1024.
// Environment: FLC_BENCH_SIZE (default 1024) changes the resolution; FLC_BENCH_IMAGES=DIR writes
// the FLC image, the ground truth and the importance map of the first BM_FlcFrame run.
// Run: build/bench_flc [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>

#include "sim/foveation/factory.h"
#include "sim/foveation/flc.h"
#include "sim/foveation/frame.h"

using namespace fovsim;

namespace {

struct Fixture {
  Scene scene;
  std::unique_ptr<Renderer> renderer;
  Display display;
  FrameData fd;
  ToneMap tm;
};

int bench_size() {
  const char* s = std::getenv("FLC_BENCH_SIZE");
  int n = s ? std::atoi(s) : 1024;
  return n > 0 ? n : 1024;
}

Fixture& cornell() {
  static std::unique_ptr<Fixture> f;
  if (!f) {
    f = std::make_unique<Fixture>();
    Params p(Json{{"type", "cornell"}});
    f->scene = make_scene(p, std::string(FOVSIM_SOURCE_DIR) + "/models");
    f->renderer = std::make_unique<Renderer>(f->scene, RenderSettings{});
    f->display.width = f->display.height = bench_size();
    f->display.fov_h_deg = f->display.fov_v_deg = 60;
    TraceSample s;
    s.head_pos = glm::dvec3(0, 1, 2.2);
    s.gaze_dir = glm::normalize(glm::dvec3(-0.35, 0.0, -1.0));  // on the red wall
    f->renderer->set_time(0);
    prepare_frame(*f->renderer, f->display, s, 0, kShadingChannels, nullptr, f->fd);
    f->tm.exposure = f->scene.exposure;
  }
  return *f;
}

void write_debug(const FrameOutput& o, const ToneMap& tm) {
  const char* dir = std::getenv("FLC_BENCH_IMAGES");
  static bool done = false;
  if (!dir || done) return;
  done = true;
  Image d;
  tm.apply(o.image, d);
  write_image(std::string(dir) + "/flc.png", d);
  tm.apply(*o.reference, d);
  write_image(std::string(dir) + "/ground_truth.png", d);
  for (auto& [name, img] : o.debug) write_image(std::string(dir) + "/flc_" + name + ".png", img);
}

void BM_FlcFrame(benchmark::State& st) {
  Fixture& f = cornell();
  const char* vis[] = {"none", "blso", "exact"};
  Params p(Json{{"vpl_budget", st.range(0)}, {"visibility", vis[st.range(1)]}});
  auto m = make_method("flc", p);
  FrameContext ctx =
      f.fd.context(f.scene, *f.renderer, f.display, std::getenv("FLC_BENCH_IMAGES") != nullptr);
  {
    FrameOutput warm;  // fills the ground-truth cache outside the timed loop
    m->render(ctx, warm);
    write_debug(warm, f.tm);
  }
  FlcStageTimes acc;
  FrameOutput out;
  for (auto _ : st) {
    out = FrameOutput();
    m->render(ctx, out);
    const FlcStageTimes& t = *flc_stage_times(*m);
    acc.rsm += t.rsm;
    acc.importance += t.importance;
    acc.sampling += t.sampling;
    acc.contribution += t.contribution;
    acc.culling += t.culling;
    acc.shading += t.shading;
    acc.compose += t.compose + t.ground_truth;
  }
  const double n = double(st.iterations());
  st.counters["rsm_ms"] = acc.rsm / n;
  st.counters["importance_ms"] = acc.importance / n;
  st.counters["sampling_ms"] = acc.sampling / n;
  st.counters["contribution_ms"] = acc.contribution / n;
  st.counters["culling_ms"] = acc.culling / n;
  st.counters["shading_ms"] = acc.shading / n;
  st.counters["compose_ms"] = acc.compose / n;
  st.counters["vpls_total"] = out.counters.get("vpls_total");
  st.counters["vpls_kept"] = out.counters.get("vpls_kept");
  st.counters["flc_tau"] = out.counters.get("flc_tau");
}
BENCHMARK(BM_FlcFrame)
    ->Args({1024, 1})
    ->Args({256, 1})
    ->Args({4096, 1})
    ->Args({1024, 0})
    ->Args({1024, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);

void BM_FlcGroundTruth(benchmark::State& st) {
  Fixture& f = cornell();
  Params p(Json{{"vpl_budget", 0}});
  auto m = make_method("flc", p);
  FrameContext ctx = f.fd.context(f.scene, *f.renderer, f.display, false);
  double gt = 0;
  for (auto _ : st) {
    flc_clear_ground_truth_cache();
    FrameOutput out;
    m->render(ctx, out);
    gt += flc_stage_times(*m)->ground_truth;
  }
  st.counters["ground_truth_ms"] = gt / double(st.iterations());
}
BENCHMARK(BM_FlcGroundTruth)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
