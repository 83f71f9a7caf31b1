// Per-frame CPU time of the image-mapping methods and of KFR's mapping passes.
//
// 1. method/<name>/tbb:<n>: one FoveationMethod::render() of kfr, rmfr, hyperbolic, linear,
//    fvrs and twfr (default parameters) at the HTC Vive Pro Eye resolution (1440x1600,
//    models/displays/htc_vive_pro_eye.json) on the atrium (complexity 3), with n TBB threads
//    (tbb::global_control). The shared per-frame inputs (G-buffer, reference, eccentricity) are
//    built once with prepare_frame and are not timed. "full" is the full-resolution shading of
//    the same G-buffer (Renderer::shade): the `full` method itself only flags the shared
//    reference and costs nothing. twfr times a reprojected frame after an untimed full-redraw
//    frame (reset each iteration, as bench_twfr). items/s = frames/s; the time column is ms
//    per frame. One thread: CPU time of the calling thread (the work runs on it); two
//    threads: wall-clock time, and the CPU column is the process CPU time (all threads).
// 2. map/<pass>/tbb:<n>: KFR's forward map as rendered (LP-buffer gather, lp_gather: the
//    nearest G-buffer sample of each LP slot as a 32-bit index plus the used mask; the shader
//    reads the G-buffer channels through the index, so that cost is in method/kfr, not here)
//    and inverse map (bilinear reconstruction of the full image,
//    lp_reconstruct) against OpenCV's cv::warpPolar (INTER_LINEAR | WARP_POLAR_LOG, forward and
//    with WARP_INVERSE_MAP) on a CV_32FC3 image, same sizes: full 1440x1600 <-> LP-buffer
//    (W/sigma) x (H/sigma), sigma = 1.8, centre at the gaze, maxRadius = e^L (the farthest
//    screen corner). map/fovsim_forward_rgb is the like-for-like variant of the forward map
//    (bilinear RGB gather of the reference through LogPolarMap::inverse, as warpPolar does).
//    cv::setNumThreads(n) matches the TBB limit. Ratio fovsim/OpenCV = time of map/fovsim_*
//    over map/opencv_* at the same tbb:n. The OpenCV cases are compiled only with
//    FOVSIM_HAVE_OPENCV (CMakeLists.txt finds OpenCV optionally; `make bench` installs it).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "sim/foveation/factory.h"
#include "sim/foveation/frame.h"
#include "sim/foveation/mapping.h"
#include "sim/scene/scene.h"

#ifdef FOVSIM_HAVE_OPENCV
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#endif

using namespace fovsim;

namespace {

// Every registered method but the reference itself (sim/foveation/method_list.h).
const std::vector<std::string> kMethods = [] {
  std::vector<std::string> m;
  for (const std::string& n : method_names())
    if (n != "full") m.push_back(n);
  return m;
}();
constexpr double kSigma = 1.8;  // KFR default (Meng 2018 §2.1)

struct Setup {
  Scene scene;
  Display display;
  std::unique_ptr<Renderer> renderer;
  FrameData a, b;   // b is the timed frame; a is the previous frame (twfr's full redraw)
  LogPolarMap map;  // KFR's map for frame b at sigma = 1.8, default kernel (power, alpha 4)
  Image lp_rgb;     // RGB LP-buffer (bilinear gather of b.reference), input of the inverse pass

  Setup() {
    const std::string models = std::string(FOVSIM_SOURCE_DIR) + "/models";
    Params sp(Json{{"type", "atrium"}, {"complexity", 3}}, "bench");
    scene = make_scene(sp, models);
    display = Display::load("htc_vive_pro_eye", models);
    renderer = std::make_unique<Renderer>(scene, RenderSettings{});
    uint32_t ch = kShadingChannels;
    for (const std::string& m : kMethods) {
      Params p(Json::object(), "bench");
      ch |= make_method(m, p)->required_channels();
    }
    TraceSample s0, s1;
    s0.head_pos = glm::dvec3(scene.default_eye);
    s1 = s0;
    s1.t = 1.0 / display.refresh_hz;
    s1.head_pos += glm::dvec3(0.004, 0, -0.014);                           // ~1 m/s walk
    s1.head_rot = glm::angleAxis(glm::radians(0.6), glm::dvec3(0, 1, 0));  // ~50 deg/s turn
    renderer->set_time(s0.t);
    prepare_frame(*renderer, display, s0, 0, ch, nullptr, a);  // gaze straight ahead (centre)
    renderer->set_time(s1.t);
    prepare_frame(*renderer, display, s1, 1, ch, &a.camera, b);
    const int W = b.gbuffer.width, H = b.gbuffer.height;
    map = LogPolarMap::make(W, H, reduced_size(W, kSigma), reduced_size(H, kSigma), b.gaze_px,
                            KernelFn{});
    forward_rgb(lp_rgb);
  }

  // Bilinear RGB forward map of the reference (what cv::warpPolar's forward mode computes).
  void forward_rgb(Image& lp) const {
    const int w = int(map.w), h = int(map.h);
    lp.resize(w, h, 3);
    parallel_rows(h, [&](int v) {
      for (int u = 0; u < w; ++u) {
        const glm::dvec2 p = map.inverse(u + 0.5, v + 0.5);
        const glm::vec3 c = bilinear(b.reference, p.x, p.y, false);
        float* o = lp.at(u, v);
        o[0] = c.x;
        o[1] = c.y;
        o[2] = c.z;
      }
    });
  }
};

Setup& setup() {
  static Setup s;
  return s;
}

void frames_done(benchmark::State& state, double shaded, double pixels) {
  state.SetItemsProcessed(state.iterations());
  if (pixels > 0) state.counters["shaded_frac"] = shaded / pixels;
}

void BM_Method(benchmark::State& state, std::string name) {
  Setup& S = setup();
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
  const FrameContext ca = S.a.context(S.scene, *S.renderer, S.display, false);
  const FrameContext cb = S.b.context(S.scene, *S.renderer, S.display, false);
  Params p(Json::object(), "bench");
  std::unique_ptr<FoveationMethod> m = make_method(name, p);
  FrameOutput out, prev;
  auto frame = [&] {
    out.counters.clear();
    out.flags.clear();
    m->render(cb, out);
  };
  if (m->temporal()) {
    for (auto _ : state) {
      state.PauseTiming();
      m->reset();
      prev.counters.clear();
      m->render(ca, prev);
      state.ResumeTiming();
      frame();
    }
  } else {
    frame();  // warm-up: buffers allocated, iso-budget (if any) resolved
    for (auto _ : state) frame();
  }
  frames_done(state, out.counters.get(Counter::shaded_samples), double(S.b.gbuffer.size()));
}

void BM_FullShade(benchmark::State& state) {
  Setup& S = setup();
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
  Image img;
  for (auto _ : state) S.renderer->shade(S.b.gbuffer, S.b.camera.position, img);
  frames_done(state, double(S.b.gbuffer.size()), double(S.b.gbuffer.size()));
}

// ---- KFR's mapping passes ----------------------------------------------------------------

void BM_FovsimForward(benchmark::State& state) {  // KFR pass 1 as rendered (lp_gather)
  Setup& S = setup();
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
  std::vector<uint32_t> lp;  // the LP-buffer: G-buffer sample index per slot (GBufferRef)
  std::vector<uint8_t> used;
  size_t n = 0;
  for (auto _ : state) n = lp_gather(S.b.gbuffer, S.map, lp, used);
  state.SetItemsProcessed(state.iterations());
  state.counters["used_frac"] = double(n) / (S.map.w * S.map.h);
}

// Direct shading of KFR's LP-buffer (Renderer::shade, used slots): through the index view
// (as rendered) or from a copy of the five shading channels (the LP G-buffer pass 1 used to
// build). The difference is the cost of the scattered G-buffer reads that moved from the
// forward map into shading; same output bits.
void BM_KfrShadeLp(benchmark::State& state, bool copy) {
  Setup& S = setup();
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
  const int w = int(S.map.w), h = int(S.map.h);
  std::vector<uint32_t> index;
  std::vector<uint8_t> used;
  lp_gather(S.b.gbuffer, S.map, index, used);
  GBuffer lp;
  lp.resize(w, h, kShadingChannels);
  for (size_t i = 0; i < lp.size(); ++i) {
    if (index[i] == GBufferRef::kNone)
      lp.clear_sample(i);
    else
      lp.copy_sample(S.b.gbuffer, index[i], i);
  }
  const GBufferRef view = copy ? GBufferRef(lp) : GBufferRef(S.b.gbuffer, index.data(), w, h);
  Image col;
  for (auto _ : state) S.renderer->shade(view, S.b.camera.position, col, used.data());
  state.SetItemsProcessed(state.iterations());
}

void BM_FovsimForwardRgb(benchmark::State& state) {  // like-for-like with warpPolar forward
  Setup& S = setup();
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
  Image lp;
  for (auto _ : state) S.forward_rgb(lp);
  state.SetItemsProcessed(state.iterations());
}

void BM_FovsimInverse(benchmark::State& state) {  // KFR pass 2 (lp_reconstruct)
  Setup& S = setup();
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
  Image img;
  for (auto _ : state) lp_reconstruct(S.lp_rgb, S.map, S.b.gbuffer.width, S.b.gbuffer.height, img);
  state.SetItemsProcessed(state.iterations());
}

#ifdef FOVSIM_HAVE_OPENCV
cv::Mat to_mat(const Image& img) {
  return cv::Mat(img.height, img.width, CV_32FC3, const_cast<float*>(img.data.data())).clone();
}

// cv::warpPolar, log-polar, bilinear; `inverse` adds WARP_INVERSE_MAP (LP-buffer -> screen).
void BM_OpenCv(benchmark::State& state, bool inverse) {
  Setup& S = setup();
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
  const int prev_threads = cv::getNumThreads();
  cv::setNumThreads(int(state.range(0)));
  const cv::Mat src = to_mat(inverse ? S.lp_rgb : S.b.reference);
  const cv::Size dsize = inverse ? cv::Size(S.b.gbuffer.width, S.b.gbuffer.height)
                                 : cv::Size(int(S.map.w), int(S.map.h));
  const cv::Point2f centre(float(S.map.gx), float(S.map.gy));
  const double max_radius = std::exp(S.map.L);
  const int flags = cv::INTER_LINEAR | cv::WARP_POLAR_LOG | (inverse ? cv::WARP_INVERSE_MAP : 0);
  cv::Mat dst;
  for (auto _ : state) cv::warpPolar(src, dst, dsize, centre, max_radius, flags);
  state.SetItemsProcessed(state.iterations());
  state.counters["cv_threads"] = cv::getNumThreads();
  // "Parallel framework: <name>" line of OpenCV's build information.
  const std::string info = cv::getBuildInformation();
  const size_t at = info.find("Parallel framework:");
  if (at != std::string::npos) {
    std::string fw = info.substr(at + 19, info.find('\n', at) - at - 19);
    fw.erase(0, fw.find_first_not_of(' '));
    state.SetLabel("cv parallel: " + fw);
  }
  cv::setNumThreads(prev_threads);
}
#endif

template <class Fn, class... Args>
void add(const std::string& name, Fn fn, Args... args) {
  for (int t : {1, 2}) {
    auto* b = benchmark::RegisterBenchmark(name.c_str(), fn, args...);
    b->Arg(t)->ArgName("tbb")->Unit(benchmark::kMillisecond);
    if (t > 1) b->UseRealTime()->MeasureProcessCPUTime();  // CPU column: all threads' work
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  add("method/full", BM_FullShade);
  for (const std::string& m : kMethods) add("method/" + m, BM_Method, m);
  add("map/fovsim_forward", BM_FovsimForward);
  add("map/fovsim_forward_rgb", BM_FovsimForwardRgb);
  add("shade/kfr_lp_index", BM_KfrShadeLp, false);
  add("shade/kfr_lp_copy", BM_KfrShadeLp, true);
  add("map/fovsim_inverse", BM_FovsimInverse);
#ifdef FOVSIM_HAVE_OPENCV
  add("map/opencv_forward", BM_OpenCv, false);
  add("map/opencv_inverse", BM_OpenCv, true);
#endif
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
