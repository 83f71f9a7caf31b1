// Tone mapping + sRGB encoding of one frame (ToneMap::apply, sim/render/tonemap.cpp) at one
// thread, against two lines measured in the same run:
//   BM_ToneMap/apply/<W>:      ToneMap::apply (the curve 4 lanes at a time, ACES + sRGB);
//   BM_ToneMap/scalar/<W>:     the same curve per value (display_encode in a plain loop: what
//                              apply compiled to before it was written with vector types);
//   BM_ToneMap/copy/<W>:       std::copy of the same buffer (the memory-bandwidth floor).
// <W> is the image width: 360 (the quickstart's 360 x 400, render scale 0.25) or 1440 (HTC
// Vive Pro Eye per eye, 1440 x 1600). Counters: ns_per_value (per float of the RGB image).
// Time: the calling thread's CPU time (tbb limited to one thread). Results: bench/README.md.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <ctime>

#include "sim/render/tonemap.h"

using namespace fovsim;

namespace {

double thread_cpu_s() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

enum Kind { kApply, kScalar, kCopy };

template <Kind K>
void BM_ToneMap(benchmark::State& st) {
  const int w = int(st.range(0)), h = w == 360 ? 400 : 1600;
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
  Image lin(w, h, 3), out(w, h, 3);
  // Linear HDR values over the range a frame has (0 .. 4, a few negatives and zeros).
  for (size_t i = 0; i < lin.data.size(); ++i)
    lin.data[i] = float((i * 2654435761u) % 100003u) * (4.f / 100003.f) - 0.05f;
  ToneMap tm;
  tm.exposure = 1.2;
  double t = 0;
  for (auto _ : st) {
    const double t0 = thread_cpu_s();
    if constexpr (K == kApply) {
      tm.apply(lin, out);
    } else if constexpr (K == kScalar) {
      const float ex = float(tm.exposure);
      for (size_t i = 0; i < lin.data.size(); ++i)
        out.data[i] = display_encode<ToneCurve::Aces>(lin.data[i] * ex);
    } else {
      std::copy(lin.data.begin(), lin.data.end(), out.data.begin());
    }
    benchmark::DoNotOptimize(out.data.data());
    benchmark::ClobberMemory();
    t += thread_cpu_s() - t0;
    st.SetIterationTime(thread_cpu_s() - t0);
  }
  st.counters["ns_per_value"] = t / double(st.iterations()) / double(lin.data.size()) * 1e9;
}

}  // namespace

BENCHMARK(BM_ToneMap<kApply>)
    ->Name("BM_ToneMap/apply")
    ->Arg(360)
    ->Arg(1440)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ToneMap<kScalar>)
    ->Name("BM_ToneMap/scalar")
    ->Arg(360)
    ->Arg(1440)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ToneMap<kCopy>)
    ->Name("BM_ToneMap/copy")
    ->Arg(360)
    ->Arg(1440)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
