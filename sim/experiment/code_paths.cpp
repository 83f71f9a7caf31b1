#include "sim/experiment/code_paths.h"

#include "sim/core/powf_lanes.h"
#include "sim/foveation/simd_kernels.h"
#include "sim/render/embree_device.h"
#include "sim/render/gbuffer_lanes.h"
#include "sim/render/tonemap.h"
#include "sim/scene/texture_packet.h"

namespace fovsim {

Json code_paths_info() {
  Json simd = Json::array();
  for (SimdPath p : simd_paths_available()) simd.push_back(simd_path_name(p));
  return Json{{"embree_isas", embree_supported_isas()},
              {"embree_isa", embree_active_isa()},
              {"simd_paths", simd},
              {"simd_path", simd_path_name(simd_path())},
              // Lanes per instruction of the kernels that pick their width at run time (floats
              // for the G-buffer and the tone map, doubles for the powers and box filters).
              {"lane_widths",
               {{"gbuffer", gbuffer_lane_width()},
                {"tonemap", tonemap_lane_width()},
                {"powf", powf_lane_width()},
                {"texture_box_filter", texture_lane_width()}}}};
}

}  // namespace fovsim
