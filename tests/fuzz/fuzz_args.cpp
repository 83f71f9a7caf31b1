// libFuzzer target: the argument layer the Python API goes through (python/bindings.cpp) --
// the library's check_number/check_integer, check_cost_args (the what-if overrides of
// fovsim.estimate/budget with the CLI flags' ranges), parse_method_arg and the analytic
// estimate it feeds. Input: 8 doubles as raw bytes (any bit pattern: NaN, inf, subnormals),
// then text lines: a `where` string, a method argument ("kfr:sigma=1.8"), a resource name,
// and the rest a workload or GPU profile JSON.
// Every failure must be a fovsim::Error; anything else is a bug. Build: `make fuzz`.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>

#include "sim/core/error.h"
#include "sim/core/params.h"
#include "sim/cost/analytic.h"
#include "sim/cost/budget.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/workload.h"
#include "sim/display/display.h"
#include "sim/foveation/factory.h"

using namespace fovsim;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  double v[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  const size_t nb = std::min(size, sizeof v);
  std::memcpy(v, data, nb);
  std::string rest(reinterpret_cast<const char*>(data) + nb, size - nb);
  std::string lines[3];
  for (int i = 0; i < 3; ++i) {
    const size_t nl = rest.find('\n');
    lines[i] = rest.substr(0, nl);
    rest = nl == std::string::npos ? "" : rest.substr(nl + 1);
  }
  // The generic checks with arbitrary bounds (lo > hi, NaN bounds, open and closed).
  try {
    (void)check_number(lines[0], v[0], Range::closed(v[1], v[2]));
  } catch (const Error&) {
  }
  try {
    (void)check_number(lines[0], v[0], Range::above(v[1], v[2]));
  } catch (const Error&) {
  }
  try {
    (void)check_integer(lines[0], v[0], Range::closed(v[1], v[2]));
  } catch (const Error&) {
  }
  // fovsim.estimate(width, height, eyes, budget_ms, scale={resource: factor}).
  try {
    check_cost_args(v[3], v[4], v[5], v[6], {{lines[2], v[7]}});
  } catch (const Error&) {
  }
  // The method argument, then the analytic estimate the bindings compute from it.
  try {
    const MethodArg m = parse_method_arg(lines[1], "method");
    if (!is_cost_method(m.name)) return 0;
    static const GpuProfile gpu = GpuProfile::load("gtx1080", "models");
    static const Workload w = Workload::load("kfr_bistro", "models");
    static const Display d = Display::load("htc_vive_pro_eye", "models");
    (void)analytic_frame(gpu, m.name, m.params, w, d, "method " + m.text);
  } catch (const Error&) {
  }
  // The rest of the input: a workload or a GPU profile document (one with "spec" is a
  // profile), read and costed for a method of every cost family: the ranges of its numbers,
  // the missing-pass and non-finite checks of the cost evaluation.
  if (rest.empty()) return 0;
  try {
    static const GpuProfile gtx = GpuProfile::load("gtx1080", "models");
    static const Workload bistro = Workload::load("kfr_bistro", "models");
    static const Display d = Display::load("htc_vive_pro_eye", "models");
    const Json j = parse_json_text(rest, "fuzz.json");
    GpuProfile g = gtx;
    Workload w = bistro;
    if (j.is_object() && j.contains("spec")) {
      g = GpuProfile::from_json(j, "fuzz.json");
    } else {
      Params p(j, "fuzz.json");
      w = Workload::from_params(p);
      p.finish();
    }
    for (const std::string& m : method_names())
      (void)analytic_frame(g, m, Json::object(), w, d, m, true);
  } catch (const Error&) {
  }
  return 0;
}
