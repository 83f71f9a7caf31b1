// Run configs (DESIGN §3): JSON with optional inheritance ("base": "other.json", merged
// recursively; arrays replace) and command-line overrides key.path=value. Paths inside a
// config are relative to the config file's directory.
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
};

// Loads CONFIG, applies "base" chains (cycle-checked) and then `overrides` in order.
LoadedConfig load_config(const std::string& path, const std::vector<std::string>& overrides = {});

// Directory holding models/ (displays, gpus, calibration, scenes): $FOVSIM_MODELS, else
// ./models if present, else the source tree's models/ recorded at build time.
std::string default_models_dir();

// Resolves `p` against `base_dir` unless it is absolute.
std::string resolve_path(const std::string& base_dir, const std::string& p);

}  // namespace fovsim
