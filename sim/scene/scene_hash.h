// A content hash of a built scene: everything the renderer reads (geometry, materials,
// textures, objects and their keyframes, lights, sub-models, scene-level settings). Two scenes
// with the same hash render the same images with the same code; used in the key of the
// reference cache (sim/experiment/reference_cache.h), so an imported scene whose files change
// gets new entries whatever its path.
#pragma once
#include <cstdint>

#include "sim/scene/scene.h"

namespace fovsim {

uint64_t scene_content_hash(const Scene& s);

}  // namespace fovsim
