#include "sim/experiment/code_paths.h"

#include "sim/foveation/simd_kernels.h"
#include "sim/render/embree_device.h"

namespace fovsim {

Json code_paths_info() {
  Json simd = Json::array();
  for (SimdPath p : simd_paths_available()) simd.push_back(simd_path_name(p));
  return Json{{"embree_isas", embree_supported_isas()},
              {"embree_isa", embree_active_isa()},
              {"simd_paths", simd},
              {"simd_path", simd_path_name(simd_path())}};
}

}  // namespace fovsim
