// A GPU profile: per-pass linear coefficients (ms per counter unit) and fixed overheads,
// with the calibration residuals they were fitted with. See models/gpus/README.md.
#pragma once
#include <map>
#include <string>

#include "sim/core/params.h"

namespace fovsim {

struct GpuProfile {
  std::string name;
  Json data;  // the profile document (coefficients per pass, residuals, source)
  static GpuProfile load(const std::string& name_or_path, const std::string& models_dir);
};

}  // namespace fovsim
