#include "sim/render/embree_device.h"

#include <algorithm>
#include <cstdlib>

#include "sim/core/error.h"

namespace fovsim {

const std::vector<std::string>& embree_isa_names() {
  static const std::vector<std::string> n = {"sse2", "sse4.2", "avx", "avx2", "avx512"};
  return n;
}

std::vector<std::string> embree_supported_isas() {
  // The same feature sets Embree 3 requires for each of its ISA levels (common/sys/sysinfo.h:
  // SSE42 = SSE4.1+SSE4.2, AVX2 = AVX + AVX2 + FMA + BMI1/2 + LZCNT, AVX512 = SKX's F+CD+DQ+BW+VL).
  std::vector<std::string> s = {"sse2"};
  __builtin_cpu_init();
  if (!(__builtin_cpu_supports("sse4.1") && __builtin_cpu_supports("sse4.2"))) return s;
  s.push_back("sse4.2");
  if (!__builtin_cpu_supports("avx")) return s;
  s.push_back("avx");
  if (!(__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
        __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2")))
    return s;
  s.push_back("avx2");
  if (!(__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512vl")))
    return s;
  s.push_back("avx512");
  return s;
}

std::string embree_forced_isa() {
  const char* v = std::getenv("FOVSIM_EMBREE_ISA");
  if (!v || !*v || std::string(v) == "native") return "";
  const std::string isa(v);
  const auto& names = embree_isa_names();
  auto join = [](const std::vector<std::string>& l) {
    std::string r;
    for (const auto& x : l) r += (r.empty() ? "" : ", ") + x;
    return r;
  };
  if (std::find(names.begin(), names.end(), isa) == names.end())
    throw Error("FOVSIM_EMBREE_ISA",
                "unknown Embree ISA \"" + isa + "\" (allowed: native, " + join(names) + ")");
  const auto sup = embree_supported_isas();
  if (std::find(sup.begin(), sup.end(), isa) == sup.end())
    throw Error("FOVSIM_EMBREE_ISA",
                "this CPU cannot run Embree's " + isa + " path (it supports: " + join(sup) + ")");
  return isa;
}

std::string embree_active_isa() {
  std::string f = embree_forced_isa();
  return f.empty() ? embree_supported_isas().back() : f;
}

std::string embree_device_config() {
  std::string f = embree_forced_isa();
  return f.empty() ? std::string() : "isa=" + f;
}

}  // namespace fovsim
