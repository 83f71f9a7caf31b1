// Run configs (docs/architecture.md "Inputs: displays, traces, scenes, configs"): JSON with
// optional inheritance ("base": "other.json", merged recursively; arrays replace) and command-line
// overrides key.path=value. A relative path in a config (trace.file, trace.map, scene.path, a
// "base" itself) is relative to the folder of the file that wrote it, through any depth of "base";
// errors about an inherited value name the file it came from ("inherited from base.json").
#pragma once
#include <string>
#include <vector>

#include "sim/core/params.h"

namespace fovsim {

struct LoadedConfig {
  Json doc;              // merged document (base files applied, overrides applied)
  std::string file;      // path of the config given by the user
  std::string base_dir;  // directory of that file (for relative paths)
  // (JSON path, override text) of each command-line override, for Params::set_origins.
  std::vector<std::pair<std::string, std::string>> overridden;
  // (JSON path, base file) of every value written by a base file, for Params::set_inherited.
  std::vector<std::pair<std::string, std::string>> inherited;
};

// Longest "base" chain accepted (files, the config itself included). Configs inherit one or
// two levels; the chain is followed in a loop, so the limit is about mistakes, not the stack.
constexpr int kMaxBaseDepth = 256;

// Loads CONFIG, applies "base" chains (cycle-checked) and then `overrides` in order.
LoadedConfig load_config(const std::string& path, const std::vector<std::string>& overrides = {});

// Directory holding models/ (displays, gpus, calibration, scenes): $FOVSIM_MODELS, else
// ./models if present, else the source tree's models/ recorded at build time.
std::string default_models_dir();

// Resolves `p` against `base_dir` unless it is absolute.
std::string resolve_path(const std::string& base_dir, const std::string& p);

}  // namespace fovsim
