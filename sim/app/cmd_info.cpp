// `fovsim info`: version, commit and the CPU code paths (Embree ISA, SIMD kernels) this
// machine offers and would use; `--json` for scripts (tests/isa/run_isa_tests.sh).
#include <cstdio>

#include "sim/app/commands.h"
#include "sim/core/counter_list.h"
#include "sim/core/version.h"
#include "sim/cost/gpu_profile.h"
#include "sim/experiment/code_paths.h"
#include "sim/experiment/info.h"
#include "sim/experiment/run_config.h"
#include "sim/foveation/factory.h"
#include "sim/metrics/registry.h"

namespace fovsim::app {

void register_info(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "info", "Version and the CPU code paths (Embree ISA, SIMD kernels) available here");
  auto json = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json, "Print one JSON object instead of text");
  cmd->footer(
      "Results do not depend on the code path. Force one with the environment variables\n"
      "FOVSIM_EMBREE_ISA=sse2|sse4.2|avx|avx2|avx512|native and FOVSIM_SIMD=generic|avx2|native.");
  cmd->callback([&action, json]() {
    action = [json]() {
      const Json j = info_json();  // sim/experiment/info.h
      if (*json) {
        std::printf("%s\n", j.dump().c_str());
        return 0;
      }
      auto list = [](const Json& a) {
        std::string s;
        for (const auto& x : a) s += (s.empty() ? "" : " ") + x.get<std::string>();
        return s;
      };
      std::printf("fovsim %s (%s)\n", version_string().c_str(), git_commit().c_str());
      std::printf("embree ISA paths: %s (active: %s)\n", list(j["embree_isas"]).c_str(),
                  j["embree_isa"].get<std::string>().c_str());
      std::printf("SIMD kernel paths: %s (active: %s)\n", list(j["simd_paths"]).c_str(),
                  j["simd_path"].get<std::string>().c_str());
      std::printf("lanes per instruction:");
      for (const auto& [k, v] : j["lane_widths"].items())
        std::printf(" %s %d", k.c_str(), v.get<int>());
      std::printf("\n");
      std::printf("metrics:");
      for (const auto& m : j["metrics"])
        std::printf(" %s%s", m["name"].get<std::string>().c_str(), m["family"] ? "*" : "");
      std::printf("\n");
      return 0;
    };
  });
}

void register_methods(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "methods", "List the foveation methods and their parameters (from their declarations)");
  auto md = std::make_shared<bool>(false), keys = std::make_shared<bool>(false),
       counters = std::make_shared<bool>(false), profile_keys = std::make_shared<bool>(false);
  cmd->add_flag("--markdown", *md,
                "Print the parameter tables as Markdown (embedded in docs/methods.md)");
  cmd->add_flag("--config-keys", *keys,
                "With --markdown: print the run config's other key tables instead (top level, "
                "render, frames, outputs, metrics, latency, GPU spec; embedded in "
                "configs/README.md)");
  cmd->add_flag("--counters", *counters,
                "With --markdown: print the counter table instead (sim/core/counter_list.h; "
                "embedded in docs/cost_model.md)");
  cmd->add_flag("--gpu-profile-keys", *profile_keys,
                "With --markdown: print the GPU profile file's key table instead "
                "(sim/cost/gpu_profile.cpp; embedded in docs/cost_model.md)");
  cmd->callback([&action, md, keys, counters, profile_keys]() {
    action = [md, keys, counters, profile_keys]() {
      if (*md && *profile_keys) {
        std::printf("%s", gpu_profile_keys_markdown().c_str());
        return 0;
      }
      if (*md && *counters) {
        std::printf("%s", counters_markdown().c_str());
        return 0;
      }
      if (*md && *keys) {
        std::printf("%s", config_keys_markdown().c_str());
        return 0;
      }
      if (*md) {
        std::printf("%s", methods_markdown().c_str());
        return 0;
      }
      for (const auto& e : method_table()) {
        std::printf("%-11s %s\n", e.name, e.summary);
        for (const ParamInfo& p : e.params())
          std::printf("    %-24s %-7s default %-8s %s\n", p.name, p.type, p.def, p.range);
      }
      std::printf("\nlighting strategies (a method's \"lighting\": {\"method\": ...} block):\n");
      for (const auto& e : lighting_table()) {
        std::printf("%-11s %s\n", e.name, e.summary);
        for (const ParamInfo& p : e.params())
          std::printf("    %-24s %-7s default %-8s %s\n", p.name, p.type, p.def, p.range);
      }
      return 0;
    };
  });
}

}  // namespace fovsim::app
