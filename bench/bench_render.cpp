// Renderer benchmarks (Google Benchmark; not a test).
//   BM_PrimaryVsBare/<complexity>/<threads>: the G-buffer pass (kShadingChannels) against the
//     real limit, Embree's own packet rate: rtcIntersect16 over 4x4 coherent packets of the
//     same rays (directions precomputed in float, in packet order, outside the timing), the
//     same scene, the same tiles and TBB partitioning, writing only the hit distance. A second
//     baseline is single-ray rtcIntersect1 over the same rays. The three passes run in turn in
//     every iteration (interleaved, so load on a shared machine affects them alike); counters
//     gbuf_Mrays_s, packet_Mrays_s, single_Mrays_s, ratio_packet = gbuf/packet (the target is
//     >= 0.5), ratio_single = gbuf/single.
//   BM_GBufferChannels/<complexity>/<k> (complexity 3, 6): the G-buffer pass at one thread with
//     the shading channels added one at a time (depth, +position, +material, +normal, +albedo);
//     counter ns_per_ray: the per-ray cost of each channel is the difference between rows
//     (bench/profile_gbuffer.sh splits row 4 into stages).
//   BM_ReferenceFrame/<complexity>/<threads>: one reference frame (G-buffer + shading with
//     shadow rays) at 1440x1600 (HTC Vive Pro Eye per eye) on the atrium; counters frame_ms,
//     gbuffer_ms.
//   BM_ReferencePhase/<threads>: the quickstart's shared reference of one frame (what
//     prepare_frame does for configs/quickstart.json, without the tone map): the atrium
//     (complexity 1, indirect light, 16x16 RSMs) at render.scale 0.25 of the Vive Pro Eye
//     (360x400), G-buffer, 1-spp direct shading, the 16-spp supersampled direct light
//     (render_reference), the frame's VPLs (RSMs) and the indirect light of all VPLs at pixel
//     centres (add_indirect); counters gbuffer_ms, direct_ms, supersample_ms, vpls_ms,
//     indirect_ms, frame_ms.
//   BM_ReferenceVsPacket/<complexity>/<spp>: the shared reference (render_reference, one
//     thread) per sample against Embree's bare rtcIntersect16 over the same sub-sample rays in
//     the same packets plus bare rtcOccluded16 over its shadow rays; /1/16 is the quickstart's
//     frame, /6/16 the 1.06M-triangle atrium, /1/4 4 spp; counters ref_ns_per_sample,
//     packet_ns_per_ray, ratio_ref_packet, bare_shadow_ns_per_sample, ratio_ref_bare (the
//     issue's measure: per sample over the bare traversal of all of its rays).
// Run: build/bench_render [--benchmark_filter=...] [--benchmark_min_time=...] (no MinTime is
// fixed in the code, so the command-line minimum applies). <threads> 1 = one TBB thread, timed
// by the calling thread's CPU time (meaningful on a busy machine); 0 = all cores, wall clock.
// Results and commands: bench/README.md.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <limits>
#include <map>
#include <memory>
#include <vector>

#include "sim/foveation/lighting.h"
#include "sim/render/renderer.h"

using namespace fovsim;

namespace {

struct Fixture {
  Scene scene;
  std::unique_ptr<Renderer> renderer;
  Display display;
  Camera cam;
};

Fixture& atrium(int complexity) {
  static std::map<int, std::unique_ptr<Fixture>> cache;
  auto& f = cache[complexity];
  if (!f) {
    f = std::make_unique<Fixture>();
    Params p(Json{{"type", "atrium"}, {"complexity", complexity}});
    f->scene = make_scene(p, std::string(FOVSIM_SOURCE_DIR) + "/models");
    f->renderer = std::make_unique<Renderer>(f->scene, RenderSettings{});
    f->display = Display::load("htc_vive_pro_eye", std::string(FOVSIM_SOURCE_DIR) + "/models");
    f->cam = Camera::from_pose(f->display, glm::dvec3(f->scene.default_eye),
                               glm::angleAxis(deg2rad(-8.0), glm::dvec3(0, 1, 0)));
  }
  return *f;
}

// Seconds of this thread's CPU time: with one TBB thread all work runs on the calling thread,
// so single-threaded numbers stay meaningful on a shared, busy machine.
double thread_cpu_s() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
double wall_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The camera's primary rays in 4x4 packet order per tile (the renderer's order), as floats:
// the same directions the renderer hands Embree (Camera::dir_world in double, rounded).
struct RaySet {
  int W = 0, H = 0, T = 0, tx = 0, ty = 0;
  glm::vec3 org{0.f};
  std::vector<size_t> tile_begin;  // first ray of each tile
  std::vector<float> dx, dy, dz;
  std::vector<uint32_t> pix;  // pixel index of each ray
  std::vector<uint8_t> pk_n;  // rays in each packet (1..16), packets in order
};

RaySet make_rays(const Camera& cam, int T) {
  RaySet s;
  s.W = cam.width;
  s.H = cam.height;
  s.T = T;
  s.tx = (cam.width + T - 1) / T;
  s.ty = (cam.height + T - 1) / T;
  s.org = glm::vec3(cam.position);
  for (int tile = 0; tile < s.tx * s.ty; ++tile) {
    s.tile_begin.push_back(s.pix.size());
    const int x0 = (tile % s.tx) * T, y0 = (tile / s.tx) * T;
    const int x1 = std::min(x0 + T, cam.width), y1 = std::min(y0 + T, cam.height);
    for (int by = y0; by < y1; by += 4)
      for (int bx = x0; bx < x1; bx += 4) {
        int n = 0;
        for (int y = by; y < std::min(by + 4, y1); ++y)
          for (int x = bx; x < std::min(bx + 4, x1); ++x, ++n) {
            const glm::vec3 d(cam.dir_world(x + 0.5, y + 0.5));
            s.dx.push_back(d.x);
            s.dy.push_back(d.y);
            s.dz.push_back(d.z);
            s.pix.push_back(uint32_t(size_t(y) * size_t(cam.width) + size_t(x)));
          }
        s.pk_n.push_back(uint8_t(n));
      }
  }
  s.tile_begin.push_back(s.pix.size());
  return s;
}

// Packets per tile, for walking s.pk_n in parallel.
std::vector<size_t> packet_begin(const RaySet& s) {
  std::vector<size_t> pb(1, 0);
  size_t ray = 0, pk = 0;
  for (size_t t = 0; t + 1 < s.tile_begin.size(); ++t) {
    while (ray < s.tile_begin[t + 1]) ray += s.pk_n[pk++];
    pb.push_back(pk);
  }
  return pb;
}

// Embree's packet limit: rtcIntersect16 on 4x4 coherent packets of precomputed rays.
void packet_embree(RTCScene sc, const RaySet& s, const std::vector<size_t>& pb,
                   std::vector<float>& depth) {
  tbb::parallel_for(
      tbb::blocked_range<int>(0, s.tx * s.ty, 1),
      [&](const tbb::blocked_range<int>& r) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        alignas(64) RTCRayHit16 rh;
        alignas(64) int valid[16];
        for (int tile = r.begin(); tile != r.end(); ++tile) {
          size_t ray = s.tile_begin[size_t(tile)];
          for (size_t p = pb[size_t(tile)]; p < pb[size_t(tile) + 1]; ++p) {
            const int n = s.pk_n[p];
            for (int k = 0; k < 16; ++k) {
              const size_t j = ray + size_t(k < n ? k : 0);  // idle lanes: a copy of lane 0
              valid[k] = k < n ? -1 : 0;
              rh.ray.org_x[k] = s.org.x;
              rh.ray.org_y[k] = s.org.y;
              rh.ray.org_z[k] = s.org.z;
              rh.ray.dir_x[k] = s.dx[j];
              rh.ray.dir_y[k] = s.dy[j];
              rh.ray.dir_z[k] = s.dz[j];
              rh.ray.tnear[k] = 0.f;
              rh.ray.tfar[k] = std::numeric_limits<float>::infinity();
              rh.ray.time[k] = 0.f;
              rh.ray.mask[k] = ~0u;
              rh.ray.id[k] = unsigned(k);
              rh.ray.flags[k] = 0;
              rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
              rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
            }
            rtcIntersect16(valid, sc, &ctx, &rh);
            for (int k = 0; k < n; ++k) depth[s.pix[ray + size_t(k)]] = rh.ray.tfar[k];
            ray += size_t(n);
          }
        }
      },
      tbb::simple_partitioner());
  benchmark::DoNotOptimize(depth.data());
}

// Second baseline: single rays (rtcIntersect1) over the same rays and tiles.
void single_embree(RTCScene sc, const RaySet& s, std::vector<float>& depth) {
  tbb::parallel_for(
      tbb::blocked_range<int>(0, s.tx * s.ty, 1),
      [&](const tbb::blocked_range<int>& r) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        for (int tile = r.begin(); tile != r.end(); ++tile)
          for (size_t j = s.tile_begin[size_t(tile)]; j < s.tile_begin[size_t(tile) + 1]; ++j) {
            RTCRayHit rh;
            rh.ray.org_x = s.org.x;
            rh.ray.org_y = s.org.y;
            rh.ray.org_z = s.org.z;
            rh.ray.dir_x = s.dx[j];
            rh.ray.dir_y = s.dy[j];
            rh.ray.dir_z = s.dz[j];
            rh.ray.tnear = 0.f;
            rh.ray.tfar = std::numeric_limits<float>::infinity();
            rh.ray.time = 0.f;
            rh.ray.mask = ~0u;
            rh.ray.id = 0;
            rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(sc, &ctx, &rh);
            depth[s.pix[j]] = rh.ray.tfar;
          }
      },
      tbb::simple_partitioner());
  benchmark::DoNotOptimize(depth.data());
}

// Args: atrium complexity, threads (0 = all cores, timed by wall clock; 1 = one TBB thread,
// timed by thread CPU time).
void BM_PrimaryVsBare(benchmark::State& st) {
  Fixture& f = atrium(int(st.range(0)));
  const bool single = st.range(1) == 1;
  std::unique_ptr<tbb::global_control> gc;
  if (single)
    gc = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
  auto now = single ? thread_cpu_s : wall_s;
  GBuffer g;
  f.renderer->trace_gbuffer(f.cam, kShadingChannels, g);  // allocate outside the timing
  const int T = RenderSettings{}.tile;
  const RaySet rays_set = make_rays(f.cam, T);
  const std::vector<size_t> pb = packet_begin(rays_set);
  std::vector<float> depth(size_t(f.cam.width) * size_t(f.cam.height));
  RTCScene sc = RTCScene(f.renderer->embree_scene());
  double tg = 0, tp = 0, ts = 0;
  for (auto _ : st) {
    double t0 = now();
    f.renderer->trace_gbuffer(f.cam, kShadingChannels, g);
    double t1 = now();
    packet_embree(sc, rays_set, pb, depth);
    double t2 = now();
    single_embree(sc, rays_set, depth);
    tg += t1 - t0;
    tp += t2 - t1;
    ts += now() - t2;
  }
  const double rays = double(f.cam.width) * f.cam.height * double(st.iterations());
  st.counters["gbuf_Mrays_s"] = rays / tg * 1e-6;
  st.counters["packet_Mrays_s"] = rays / tp * 1e-6;
  st.counters["single_Mrays_s"] = rays / ts * 1e-6;
  st.counters["ratio_packet"] = tp / tg;
  st.counters["ratio_single"] = ts / tg;
  st.counters["triangles"] = double(f.scene.triangle_count());
}
BENCHMARK(BM_PrimaryVsBare)
    ->Args({3, 0})
    ->Args({6, 0})
    ->Args({3, 1})
    ->Args({6, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Where the G-buffer pass's time goes: trace_gbuffer at one thread with the shading channels
// added one at a time (arg 1: 0 depth, 1 +position, 2 +material, 3 +normal, 4 +albedo =
// kShadingChannels); counter ns_per_ray (thread CPU time). The differences between rows are the
// per-ray cost of each channel (its loads, arithmetic and stores); row 0 minus Embree's packet
// rate is ray generation, hit refinement and the packet loop.
void BM_GBufferChannels(benchmark::State& st) {
  Fixture& f = atrium(int(st.range(0)));
  const uint32_t sets[] = {kDepth, kDepth | kPosition, kDepth | kPosition | kMaterial,
                           kDepth | kPosition | kMaterial | kNormal, kShadingChannels};
  const uint32_t ch = sets[st.range(1)];
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
  GBuffer g;
  f.renderer->trace_gbuffer(f.cam, ch, g);  // allocate outside the timing
  double t = 0;
  for (auto _ : st) {
    const double t0 = thread_cpu_s();
    f.renderer->trace_gbuffer(f.cam, ch, g);
    t += thread_cpu_s() - t0;
  }
  const double rays = double(f.cam.width) * f.cam.height * double(st.iterations());
  st.counters["ns_per_ray"] = t / rays * 1e9;
}
BENCHMARK(BM_GBufferChannels)
    ->ArgsProduct({{3, 6}, {0, 1, 2, 3, 4}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Args as BM_PrimaryVsBare; counter frame_ms is the mean frame time (wall or thread CPU).
void BM_ReferenceFrame(benchmark::State& st) {
  Fixture& f = atrium(int(st.range(0)));
  const bool single = st.range(1) == 1;
  std::unique_ptr<tbb::global_control> gc;
  if (single)
    gc = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
  auto now = single ? thread_cpu_s : wall_s;
  GBuffer g;
  Image img;
  Counters c;
  f.renderer->trace_gbuffer(f.cam, kShadingChannels, g);
  double tf = 0, tgb = 0;
  for (auto _ : st) {
    double t0 = now();
    f.renderer->trace_gbuffer(f.cam, kShadingChannels, g, &c);
    double t1 = now();
    f.renderer->shade(g, f.cam.position, img, nullptr, &c);
    tf += now() - t0;
    tgb += t1 - t0;
    benchmark::DoNotOptimize(img.data.data());
  }
  st.counters["frame_ms"] = 1e3 * tf / double(st.iterations());
  st.counters["gbuffer_ms"] = 1e3 * tgb / double(st.iterations());
  st.counters["shadow_rays_per_px"] =
      c.get(Counter::shadow_rays) / (double(st.iterations()) * f.cam.width * f.cam.height);
  st.counters["triangles"] = double(f.scene.triangle_count());
}
BENCHMARK(BM_ReferenceFrame)
    ->Args({3, 0})
    ->Args({6, 0})
    ->Args({3, 1})
    ->Args({6, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The quickstart's reference setting: the atrium (complexity 1, indirect light, 16x16 RSMs) at
// render.scale 0.25 of the Vive Pro Eye (360x400), 16 spp.
Fixture& quickstart() {
  static std::unique_ptr<Fixture> f;
  if (!f) {
    f = std::make_unique<Fixture>();
    Params p(Json{{"type", "atrium"},
                  {"complexity", 1},
                  {"indirect", true},
                  {"vpl", Json{{"rsm_size", 16}}}});
    f->scene = make_scene(p, std::string(FOVSIM_SOURCE_DIR) + "/models");
    RenderSettings rs;
    rs.spp = kDefaultReferenceSpp;
    f->renderer = std::make_unique<Renderer>(f->scene, rs);
    f->display =
        Display::load("htc_vive_pro_eye", std::string(FOVSIM_SOURCE_DIR) + "/models").scaled(0.25);
    f->cam = Camera::from_pose(f->display, glm::dvec3(f->scene.default_eye),
                               glm::angleAxis(deg2rad(-8.0), glm::dvec3(0, 1, 0)));
  }
  return *f;
}

// Arg: threads (0 = all cores, wall clock; 1 = one TBB thread, thread CPU time).
void BM_ReferencePhase(benchmark::State& st) {
  Fixture* f = &quickstart();
  const bool single = st.range(0) == 1;
  std::unique_ptr<tbb::global_control> gc;
  if (single)
    gc = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
  auto now = single ? thread_cpu_s : wall_s;
  const Renderer& r = *f->renderer;
  GBuffer g;
  Image direct, ref;
  FrameVpls vpls;
  double t[5] = {0, 0, 0, 0, 0};
  for (auto _ : st) {
    Counters c;
    double t0 = now();
    r.trace_gbuffer(f->cam, kShadingChannels, g, &c);
    double t1 = now();
    r.shade(g, f->cam.position, direct, nullptr, &c);
    double t2 = now();
    r.render_reference(f->cam, g, ref, &c);
    double t3 = now();
    build_frame_vpls(r, vpls, &c);
    double t4 = now();
    add_indirect(g, vpls.all, vpls.shading, &r, nullptr, ref, &c);
    double t5 = now();
    t[0] += t1 - t0;
    t[1] += t2 - t1;
    t[2] += t3 - t2;
    t[3] += t4 - t3;
    t[4] += t5 - t4;
    benchmark::DoNotOptimize(ref.data.data());
  }
  const double k = 1e3 / double(st.iterations());
  st.counters["gbuffer_ms"] = k * t[0];
  st.counters["direct_ms"] = k * t[1];
  st.counters["supersample_ms"] = k * t[2];
  st.counters["vpls_ms"] = k * t[3];
  st.counters["indirect_ms"] = k * t[4];
  st.counters["frame_ms"] = k * (t[0] + t[1] + t[2] + t[3] + t[4]);
  st.counters["vpls"] = double(vpls.vpls.size());
}
BENCHMARK(BM_ReferencePhase)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

// The reference's sub-sample rays in its own packet order (render_reference: 16 consecutive
// pixels a packet, all strata of a packet before the next), as floats, for the bare baseline.
struct SampleRays {
  glm::vec3 org{0.f};
  std::vector<float> dx, dy, dz;  // packet after packet, 16 slots each (idle slots: lane 0)
  std::vector<uint8_t> n;         // active lanes of each packet
};

SampleRays make_sample_rays(const Camera& cam, int spp) {
  SampleRays s;
  s.org = glm::vec3(cam.position);
  const int sn = int(std::lround(std::sqrt(double(spp))));
  const glm::dmat3 R = glm::mat3_cast(cam.orientation);
  const size_t np = size_t(cam.width) * size_t(cam.height);
  for (size_t i0 = 0; i0 < np; i0 += 16) {
    const int m = int(std::min<size_t>(16, np - i0));
    for (int st = 0; st < spp; ++st) {
      for (int k = 0; k < 16; ++k) {
        const size_t i = i0 + size_t(k < m ? k : 0);
        const int x = int(i % size_t(cam.width)), y = int(i / size_t(cam.width));
        const glm::vec2 o = stratified_offset(x, y, st, sn);
        const glm::vec3 d(R * cam.dir_head(double(float(x) + o.x), double(float(y) + o.y)));
        s.dx.push_back(d.x);
        s.dy.push_back(d.y);
        s.dz.push_back(d.z);
      }
      s.n.push_back(uint8_t(m));
    }
  }
  return s;
}

// rtcIntersect16 over the prepared packets (coherent flag, as the renderer's static scenes).
void sample_packets_embree(RTCScene sc, const SampleRays& s, std::vector<float>& depth) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  for (size_t p = 0; p < s.n.size(); ++p) {
    const size_t j = p * 16;
    for (int k = 0; k < 16; ++k) {
      valid[k] = k < s.n[p] ? -1 : 0;
      rh.ray.org_x[k] = s.org.x;
      rh.ray.org_y[k] = s.org.y;
      rh.ray.org_z[k] = s.org.z;
      rh.ray.dir_x[k] = s.dx[j + size_t(k)];
      rh.ray.dir_y[k] = s.dy[j + size_t(k)];
      rh.ray.dir_z[k] = s.dz[j + size_t(k)];
      rh.ray.tnear[k] = 0.f;
      rh.ray.tfar[k] = std::numeric_limits<float>::infinity();
      rh.ray.time[k] = 0.f;
      rh.ray.mask[k] = ~0u;
      rh.ray.id[k] = unsigned(k);
      rh.ray.flags[k] = 0;
      rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, sc, &ctx, &rh);
    depth[p] = rh.ray.tfar[0];
  }
  benchmark::DoNotOptimize(depth.data());
}

// rtcOccluded16's valid mask (64-byte aligned, as Embree reads it).
struct alignas(64) Valid16 {
  int v[16];
};

// A filter-free copy of a static scene's triangles in world space (the renderer's static BVH
// quality), so rtcOccluded16 runs without the renderer's portable occlusion filter: Embree
// alone, for the bare shadow-ray baseline. scale: the renderer's scene scale (ray offsets).
struct BareScene {
  RTCDevice dev = nullptr;
  RTCScene sc = nullptr;
  float scale = 1.f;
  explicit BareScene(const Scene& s) {
    dev = rtcNewDevice(nullptr);
    sc = rtcNewScene(dev);
    rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_HIGH);
    glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-lo);
    for (const Object& o : s.objects) {
      const Mesh& m = s.meshes[size_t(o.mesh)];
      const glm::mat4 xf = o.dynamic() ? o.transform_at(0.0) : o.transform;
      RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
          g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.positions.size()));
      for (size_t i = 0; i < m.positions.size(); ++i) {
        const glm::vec3 w(xf * glm::vec4(m.positions[i], 1.f));
        v[3 * i] = w.x;
        v[3 * i + 1] = w.y;
        v[3 * i + 2] = w.z;
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
      }
      auto* ix = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
          g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), m.triangles.size()));
      std::memcpy(ix, m.triangles.data(), m.triangles.size() * 3 * sizeof(unsigned));
      rtcCommitGeometry(g);
      rtcAttachGeometry(sc, g);
      rtcReleaseGeometry(g);
    }
    rtcCommitScene(sc);
    const glm::vec3 e = glm::max(glm::abs(lo), glm::abs(hi));
    scale = std::max(1.f, std::max(e.x, std::max(e.y, e.z)));
  }
  ~BareScene() {
    rtcReleaseScene(sc);
    rtcReleaseDevice(dev);
  }
};

// The shadow rays of stratum `st` of the reference, as the renderer forms them (its packets of
// 16 consecutive pixels, one packet per light that some lane tests; lights at t = 0): origins
// offset along the normal, towards the light, to its distance), from a G-buffer of the
// stratum's sub-sample points. Appends the packets to `out`, `valid` alongside.
void stratum_shadow_packets(const Renderer& r, const Camera& cam, const BareScene& bs, int st,
                            std::vector<RTCRay16>& out, std::vector<Valid16>& valid) {
  const Scene& scene = r.scene();
  const int spp = r.settings().spp, sn = int(std::lround(std::sqrt(double(spp))));
  const size_t np = size_t(cam.width) * size_t(cam.height);
  std::vector<glm::vec2> pts(np);
  for (size_t i = 0; i < np; ++i) {
    const int x = int(i % size_t(cam.width)), y = int(i / size_t(cam.width));
    const glm::vec2 o = stratified_offset(x, y, st, sn);
    pts[i] = glm::vec2(float(x) + o.x, float(y) + o.y);
  }
  GBuffer g;
  r.trace_points(cam, pts, kShadingChannels, g, nullptr, 1.f / float(sn));
  const float eps = 2e-4f * bs.scale, slack = 1e-4f * bs.scale;
  for (size_t i0 = 0; i0 < np; i0 += 16) {
    for (const Light& l : scene.lights) {
      if (!(l.shadows && r.settings().shadows)) continue;
      const glm::vec3 ldir = glm::normalize(l.direction);
      const float ci = float(std::cos(deg2rad(std::min(l.spot_inner_deg, l.spot_outer_deg))));
      const float co = float(std::cos(deg2rad(l.spot_outer_deg)));
      alignas(64) RTCRay16 ray;
      Valid16 val{};
      int nv = 0;
      for (int k = 0; k < 16; ++k) {
        const size_t i = i0 + size_t(k);
        glm::vec3 O(0.f), L(0.f, 1.f, 0.f);
        float tfar = 0.f;
        bool on = i < np && g.hit(i);
        if (on) {
          const glm::vec3 P = g.position[i], N = g.normal[i];
          O = P + N * eps;
          if (l.type == Light::Type::Directional) {
            L = -ldir;
            tfar = std::numeric_limits<float>::infinity();
          } else {
            const glm::vec3 d = l.position - P;
            const float dist = glm::length(d);
            on = dist > 0.f;
            L = on ? d / dist : L;
            tfar = std::max(0.f, dist - 2.f * eps) + slack;
            if (on && l.type == Light::Type::Spot && ci > co)
              on = glm::dot(-L, ldir) > co;  // outside the outer cone: no light, no ray
          }
          on = on && glm::dot(N, L) > 0.f;
        }
        ray.org_x[k] = O.x;
        ray.org_y[k] = O.y;
        ray.org_z[k] = O.z;
        ray.dir_x[k] = L.x;
        ray.dir_y[k] = L.y;
        ray.dir_z[k] = L.z;
        ray.tnear[k] = 0.f;
        ray.tfar[k] = on ? tfar : std::numeric_limits<float>::infinity();
        ray.time[k] = 0.f;
        ray.mask[k] = ~0u;
        ray.id[k] = unsigned(k);
        ray.flags[k] = 0;
        val.v[k] = on ? -1 : 0;
        nv += on;
      }
      if (nv == 0) continue;
      out.push_back(ray);
      valid.push_back(val);
    }
  }
}

// The shared reference per sample against Embree's bare packet traversal of the same primary
// rays, one thread (thread CPU time), interleaved in every iteration: render_reference of the
// quickstart's frame (16 spp at 360x400: per sample a primary ray, its shadow rays, texture
// filtering and shading) and rtcIntersect16 over the same 16-spp sub-sample rays in the same
// packets (precomputed, writing one float per packet); then, stratum by stratum (the rays
// prepared outside the timing), rtcOccluded16 over the reference's shadow rays in its packets
// on a filter-free copy of the scene (BareScene). Counters: ref_ns_per_sample,
// packet_ns_per_ray, ratio_ref_packet = ref / packet (per sample over per primary ray),
// shadow_rays_per_sample, bare_shadow_ns_per_sample (the shadow packets' traversal per sample),
// bare_shadow_rays_per_sample (the rays the baseline formed: shadow_rays_per_sample's check),
// ratio_ref_bare = ref / (packet + bare shadow) (per sample over all its rays' bare traversal).
// Args: atrium complexity, spp. {1, 16} is the quickstart's frame (quickstart()); the others
// the same view and display scale with the atrium at that complexity and render.spp.
Fixture& reference_fixture(int complexity, int spp) {
  if (complexity == 1 && spp == kDefaultReferenceSpp) return quickstart();
  static std::map<std::pair<int, int>, std::unique_ptr<Fixture>> cache;
  auto& f = cache[{complexity, spp}];
  if (!f) {
    f = std::make_unique<Fixture>();
    Params p(Json{{"type", "atrium"},
                  {"complexity", complexity},
                  {"indirect", true},
                  {"vpl", Json{{"rsm_size", 16}}}});
    f->scene = make_scene(p, std::string(FOVSIM_SOURCE_DIR) + "/models");
    RenderSettings rs;
    rs.spp = spp;
    f->renderer = std::make_unique<Renderer>(f->scene, rs);
    f->display = quickstart().display;
    f->cam = quickstart().cam;
  }
  return *f;
}

void BM_ReferenceVsPacket(benchmark::State& st) {
  Fixture& f = reference_fixture(int(st.range(0)), int(st.range(1)));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
  const Renderer& r = *f.renderer;
  const int spp = r.settings().spp;
  GBuffer g;
  Image ref;
  r.trace_gbuffer(f.cam, kShadingChannels, g);
  const SampleRays rays = make_sample_rays(f.cam, spp);
  std::vector<float> depth(rays.n.size());
  RTCScene sc = RTCScene(r.embree_scene());
  const BareScene bare(f.scene);
  std::vector<RTCRay16> srays;
  std::vector<Valid16> svalid;
  double tr = 0, tp = 0, ts = 0, shadow = 0, bare_rays = 0;
  for (auto _ : st) {
    Counters c;
    const double t0 = thread_cpu_s();
    r.render_reference(f.cam, g, ref, &c);
    const double t1 = thread_cpu_s();
    sample_packets_embree(sc, rays, depth);
    tr += t1 - t0;
    tp += thread_cpu_s() - t1;
    shadow += c.get(Counter::shadow_rays);
    benchmark::DoNotOptimize(ref.data.data());
    for (int s = 0; s < spp; ++s) {
      srays.clear();
      svalid.clear();
      stratum_shadow_packets(r, f.cam, bare, s, srays, svalid);
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      const double t2 = thread_cpu_s();
      for (size_t p = 0; p < srays.size(); ++p)
        rtcOccluded16(svalid[p].v, bare.sc, &ctx, &srays[p]);
      ts += thread_cpu_s() - t2;
      for (const Valid16& v : svalid)
        for (int k = 0; k < 16; ++k) bare_rays += v.v[k] != 0;
      benchmark::DoNotOptimize(srays.data());
    }
  }
  const double samples =
      double(f.cam.width) * double(f.cam.height) * double(spp) * double(st.iterations());
  st.counters["ref_ns_per_sample"] = tr / samples * 1e9;
  st.counters["packet_ns_per_ray"] = tp / samples * 1e9;
  st.counters["ratio_ref_packet"] = tr / tp;
  st.counters["shadow_rays_per_sample"] = shadow / samples;
  st.counters["bare_shadow_ns_per_sample"] = ts / samples * 1e9;
  st.counters["bare_shadow_rays_per_sample"] = bare_rays / samples;
  st.counters["ratio_ref_bare"] = tr / (tp + ts);
  st.counters["triangles"] = double(f.scene.triangle_count());
}
BENCHMARK(BM_ReferenceVsPacket)
    ->Args({1, 16})
    ->Args({6, 16})
    ->Args({1, 4})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
