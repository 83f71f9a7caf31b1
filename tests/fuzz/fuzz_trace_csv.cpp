// libFuzzer target: canonical trace CSV -> read_trace_csv (every bad-sample
// policy) -> resample over a bounded range. Every failure must be a fovsim::Error.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/trace/trace.h"

using namespace fovsim;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/fovsim_fuzz_trace_" + std::to_string(::getpid()) + ".csv";
  static Display display = [] {
    Params p(Json{{"width", 64},
                  {"height", 72},
                  {"fov_h_deg", 100},
                  {"fov_v_deg", 110},
                  {"refresh_hz", 90}},
             "display");
    return Display::from_params(p);
  }();
  write_file_atomic(path, std::string(reinterpret_cast<const char*>(data), size));
  for (auto pol : {BadSamplePolicy::Fail, BadSamplePolicy::Skip, BadSamplePolicy::Hold}) {
    try {
      TraceReadOptions opt;
      opt.on_bad = pol;
      Trace tr = read_trace_csv(path, display, opt);
      if (!tr.samples.empty() && resampled_count(tr, 90.0, tr.samples.front().t + 2.0) < 1e6)
        (void)resample(tr, 90.0, tr.samples.front().t + 2.0);
    } catch (const Error&) {
    }
  }
  return 0;
}
