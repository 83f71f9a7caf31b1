// Internal: the built-in scene generators behind make_scene (keys: models/scenes/README.md).
#pragma once
#include <string>

#include "sim/scene/scene.h"

namespace fovsim {

Scene make_atrium(Params& p);
Scene make_patterns(Params& p);
Scene make_cornell(Params& p, double max_triangles);
Scene load_file_scene(Params& p, const std::string& models_dir);

// Atrium tessellation for a complexity level (exposed for tests/benchmarks).
struct AtriumTess {
  int column_facets, column_segs, arch_segs, arch_rsegs, arch_dsegs, baluster_facets;
  float grid_cell;  // metres per floor/wall cell
};
AtriumTess atrium_tess(int complexity);
constexpr int kAtriumMaxComplexity = 6;

// Appends a keyframed rotation about +y (period seconds) over [0, duration] to keys.
void add_spin_keys(std::vector<Keyframe>& keys, double duration, double period,
                   const glm::vec3& translation, double bob_amplitude = 0.0);

}  // namespace fovsim
