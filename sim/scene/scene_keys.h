// The run config's `scene` block as declared tables (sim/core/param_table.h): the keys every
// scene type has, `scene.vpl`, and one table per type (atrium, patterns, cornell, file). Each
// table drives the parsing of its keys in builtin.cpp / import.cpp (located errors, defaults,
// ranges) and its section of configs/README.md.
#pragma once
#include <string>
#include <vector>

#include "sim/core/param_table.h"

namespace fovsim {

// Keys of every scene type.
struct SceneKeys {
  std::string type;
  double max_triangles = 2e7;
};
const ParamTable<SceneKeys>& scene_table();

// `scene.vpl` (scenes with indirect light).
struct VplKeys {
  int rsm_size = 64;
  double min_dist = 0.01;
  bool shadow_rays = false;
  double max_vpls = 262144;
};
const ParamTable<VplKeys>& vpl_table();

struct AtriumKeys {
  int complexity = 3;
  bool dynamic = false, moving_light = false, indirect = false, sun = true;
  double sun_elevation_deg = 62, sun_azimuth_deg = 35, sun_intensity = 2.2;
  double lamp_intensity = 6, spot_intensity = 40;
  double anim_duration = 60, anim_period = 8, texture_scale = 1;
};
const ParamTable<AtriumKeys>& atrium_table();

struct PatternsKeys {
  double angle = 0;
  std::string pattern = "stripes";
  double frequency = 40, distance = 1, size = 0, contrast = 1;
};
const ParamTable<PatternsKeys>& patterns_table();

struct CornellKeys {
  double light_intensity = 1.6;
  std::string light = "point";
  double cell = 0.25;
  bool textured = false;
};
const ParamTable<CornellKeys>& cornell_table();

struct FileSceneKeys {
  std::string path;
  double scale = 1;
  std::vector<double> translate{0, 0, 0}, rotate_deg{0, 0, 0}, default_eye;
  bool default_lights = true;
  double exposure = 1;
  std::string on_missing_texture = "fail";
  double max_texture_pixels = 67108864;
};
const ParamTable<FileSceneKeys>& file_scene_table();

}  // namespace fovsim
