// FLC per-frame CPU time split by stage, like the seed's Table 2 (Google Benchmark; not a test).
//   BM_FlcFrame/<budget>/<visibility>: one FLC frame at 1024x1024 (seed §7) on the Cornell box,
//     64x64 RSM, gaze on the red wall; the RSMs, VPLs and ground truth are the shared frame data
//     (rendered before timing), so the Time column is FLC's own frame time. Counters: ms per
//     stage (importance_ms, sampling_ms, contribution_ms, culling_ms, shading_ms, compose_ms),
//     vpls_total, vpls_kept. visibility: 0 none, 1 blso, 2 exact.
//   BM_VplShading/<path>: indirect light of every pixel from all VPLs (the reference's TBDS
//     pass) on ONE thread; counter ns_per_pair = ns per shaded sample x VPL. path 0: the scalar
//     loop (shade_vpls_point, sim/render/vpl.cpp, the code before the SIMD kernel), 1: the SIMD
//     loop on the generic (SSE2) path, 2: on the AVX2 path (lighting.cpp, vpl_kernels.inc). All
//     three give the same bits (tests/foveation/lighting_test.cpp).
// Environment: FLC_BENCH_SIZE (default 1024) changes the resolution; FLC_BENCH_IMAGES=DIR writes
// the FLC image, the ground truth and the importance map of the first BM_FlcFrame run.
// Run: build/bench_flc [--benchmark_filter=...]
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <cstdlib>
#include <memory>

#include "sim/foveation/factory.h"
#include "sim/foveation/flc.h"
#include "sim/foveation/frame.h"
#include "sim/foveation/simd_kernels.h"

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
    Params p(Json{{"type", "cornell"}, {"vpl", {{"rsm_size", 64}}}});
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
  tm.apply(cornell().fd.reference, d);
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
    FrameOutput warm;
    render_with_lighting(*m, ctx, warm);
    write_debug(warm, f.tm);
  }
  FlcStageTimes acc;
  FrameOutput out;
  for (auto _ : st) {
    out = FrameOutput();
    render_with_lighting(*m, ctx, out);
    const FlcStageTimes& t = *flc_stage_times(*m);
    acc.importance += t.importance;
    acc.sampling += t.sampling;
    acc.contribution += t.contribution;
    acc.culling += t.culling;
    acc.shading += t.shading;
    acc.compose += t.compose;
  }
  const double n = double(st.iterations());
  st.counters["importance_ms"] = acc.importance / n;
  st.counters["sampling_ms"] = acc.sampling / n;
  st.counters["contribution_ms"] = acc.contribution / n;
  st.counters["culling_ms"] = acc.culling / n;
  st.counters["shading_ms"] = acc.shading / n;
  st.counters["compose_ms"] = acc.compose / n;
  st.counters["vpls_total"] = out.counters.get(Counter::vpls_total);
  st.counters["vpls_kept"] = out.counters.get(Counter::vpls_kept);
  st.counters["flc_tau"] = out.counters.get(Counter::flc_tau);
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

void BM_VplShading(benchmark::State& st) {
  Fixture& f = cornell();
  const GBuffer& g = f.fd.gbuffer;
  const FrameVpls& fv = f.fd.vpls;
  const int path = int(st.range(0));
  if (path == 2 && simd_paths_available().size() < 2) {
    st.SkipWithError("no AVX2 on this CPU");
    return;
  }
  const SimdPath saved = simd_path();
  set_simd_path(path == 2 ? SimdPath::Avx2 : SimdPath::Generic);
  Image col(g.width, g.height, 3);
  double hits = 0;
  for (size_t i = 0; i < g.size(); ++i) hits += g.hit(i) ? 1 : 0;
  tbb::task_arena one(1);
  for (auto _ : st) {
    one.execute([&] {
      if (path == 0) {
        for (size_t i = 0; i < g.size(); ++i) {
          if (!g.hit(i)) continue;
          const glm::vec3 L = shade_vpls_point(fv.all, g.position[i], g.normal[i], g.albedo[i],
                                               fv.shading, nullptr);
          col.data[3 * i] += L.x;
        }
      } else {
        add_indirect(g, fv.all, fv.shading, nullptr, nullptr, col);
      }
    });
    benchmark::DoNotOptimize(col.data.data());
  }
  set_simd_path(saved);
  st.counters["vpls"] = double(fv.all.size());
  st.counters["samples"] = hits;
  st.counters["ns_per_pair"] = benchmark::Counter(
      hits * double(fv.all.size()) * 1e-9,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
// CPU time (one thread): the counter is ns of CPU per pair, robust to a loaded machine.
BENCHMARK(BM_VplShading)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
