// Scene model (docs/architecture.md "Inputs: displays, traces, scenes, configs"): meshes, materials
// with procedural textures, objects (static or keyframed), lights, sub-models for culling, and the
// features that decide which passes exist.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/core/params.h"

namespace fovsim {

// Procedural textures: detail at several orientations and frequencies, where foveation error lives.
enum class TexKind : uint8_t {
  Constant,  // base_color
  Checker,   // two colours, `scale` cells per uv unit, rotated by `angle`
  Stripes,   // square-wave stripes, frequency `scale`, orientation `angle`
  Grating,   // sum of sinusoids at 3 octaves from `scale`, 4 orientations starting at `angle`
  Bricks,    // brick pattern with mortar lines
  Noise,     // value-noise fBm (deterministic hash)
  Radial,    // RMFR rotating-patterns (Ye et al. 2022 §6.1): spokes + rings, rotated by `angle`
  Image      // texture loaded from a file (assimp import), `image` index into Scene::images
};

struct Material {
  std::string name;
  glm::vec3 base_color{0.7f};
  glm::vec3 color2{0.1f};
  TexKind tex = TexKind::Constant;
  float scale = 8.f;       // texture frequency (cycles per uv unit)
  float angle = 0.f;       // radians
  float specular = 0.04f;  // Blinn-Phong ks
  float shininess = 32.f;  // Blinn-Phong exponent
  glm::vec3 emission{0.f};
  bool transparent = false;  // alpha-blended (flagged: methods' limits, docs/architecture.md
                             // "Methods and lighting strategies")
  int image = -1;
  // Imported materials (sim/scene/import.cpp): cut-out (glTF alphaMode MASK): a surface point
  // whose alpha = `alpha` x texture alpha is below alpha_cutoff is not there (rays pass it);
  // alpha_cutoff < 0 = opaque. Normal map (tangent space, linear texels, glTF convention).
  float alpha = 1.f;
  float alpha_cutoff = -1.f;
  int normal_image = -1;
  float normal_scale = 1.f;
  bool cutout() const { return alpha_cutoff >= 0.f; }
};

struct MipLevel {
  int width = 0, height = 0;
  std::vector<glm::vec3> texels;
};

struct TextureImage {  // linear RGB float, for imported textures
  int width = 0, height = 0;
  std::vector<glm::vec3> texels;
  std::vector<float> alpha;    // per texel, empty when opaque (alpha-masked materials)
  std::vector<MipLevel> mips;  // levels 1.. (2x2 box), from build_mips() at load
  void build_mips();
};

struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;  // object space
  std::vector<glm::vec3> normals;    // per vertex, may be empty (then faceted)
  std::vector<glm::vec2> uvs;        // per vertex, may be empty
  std::vector<glm::uvec3> triangles;
  std::vector<int> tri_material;  // per triangle material index (empty -> `material`)
  int material = 0;
};

struct Keyframe {
  double t = 0;
  glm::vec3 translation{0.f};
  glm::quat rotation{1, 0, 0, 0};
  glm::vec3 scale{1.f};
};

struct Object {  // an instance of a mesh
  std::string name;
  int mesh = 0;
  glm::mat4 transform{1.f};    // static transform (world-from-object)
  std::vector<Keyframe> keys;  // non-empty -> dynamic; interpolated (lerp/slerp), clamped at ends
  bool dynamic() const { return !keys.empty(); }
  glm::mat4 transform_at(double t) const;
};

struct SubModel {  // <= ~500 faces of one object, for culling (Franke et al. 2021 §6.1)
  int object = 0;
  uint32_t first_tri = 0, tri_count = 0;  // range in the mesh's triangle list (after reordering)
  AABB bounds;                            // object space
};

struct Light {
  enum class Type : uint8_t { Directional, Point, Spot } type = Type::Point;
  glm::vec3 position{0.f};
  glm::vec3 direction{0, -1, 0};  // for directional and spot: direction light travels
  glm::vec3 color{1.f};
  float intensity = 1.f;  // W/sr-like scale (point/spot), irradiance (directional)
  float spot_inner_deg = 20.f, spot_outer_deg = 30.f;
  bool shadows = true;
  std::vector<Keyframe> keys;  // non-empty -> moving light
  bool moving() const { return !keys.empty(); }
};

struct SceneFeatures {  // decides which passes exist (docs/architecture.md "Cost model": model only
                        // what a scene requires)
  bool shadows = false, dynamic_objects = false, moving_lights = false, transparency = false,
       indirect = false, textures = false;
  size_t triangles = 0, submodels = 0;
  int lights = 0, shadowed_lights = 0;
  // As recorded in manifest.json (scene.features); from_json reads what to_json writes
  // (missing keys keep their defaults).
  Json to_json() const;
  static SceneFeatures from_json(const Json& j);
};

// Scene-level settings of the one-bounce indirect light (VPLs from reflective shadow maps,
// instant radiosity as in Yang et al., "Foveated light culling", §3). One VPL set per frame,
// shared by the reference and every method (models/scenes/README.md, key `vpl`).
struct VplSettings {
  int rsm_size = 64;         // RSM texels per edge per light (FLC paper §7: 64x64)
  double min_dist = 0.01;    // distance clamp against the 1/d^2 singularity, / scene diagonal
  bool shadow_rays = false;  // exact VPL -> receiver visibility in shading (beyond the paper)
};

struct Scene {
  std::string name;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<TextureImage> images;
  std::vector<Object> objects;
  std::vector<Light> lights;
  std::vector<SubModel> submodels;
  glm::vec3 ambient{0.03f};
  glm::vec3 background{0.02f, 0.02f, 0.03f};
  bool wants_indirect = false;
  VplSettings vpl;        // used when wants_indirect
  double exposure = 1.0;  // suggested tone-mapping exposure
  // Suggested default viewpoint for traces without head positions (e.g. synthetic fixate).
  glm::vec3 default_eye{0, 1.6f, 0};

  SceneFeatures features() const;
  size_t triangle_count() const;
  // Builds `submodels` by splitting each object's triangles spatially into chunks of at most
  // `max_faces` (reorders mesh triangles so each chunk is contiguous).
  void build_submodels(uint32_t max_faces = 500);
};

// Texture evaluation without virtual calls (a switch per sample), point-sampled.
glm::vec3 eval_albedo(const Scene& scene, const Material& m, glm::vec2 uv);
// The same with cos/sin of m.angle precomputed (the renderer's per-sample path), averaged over
// an isotropic box footprint of width `fw` uv units (0 = point sample). sim/scene/texture.cpp
// documents each texture's filter.
glm::vec3 eval_albedo(const Scene& scene, const Material& m, glm::vec2 uv, float cos_a, float sin_a,
                      float fw = 0.f);
// Image lookup: bilinear at mip level mip_level(img, fw), trilinear between levels.
glm::vec3 sample_image(const TextureImage& img, glm::vec2 uv, float fw = 0.f);
// log2 of the footprint in texels, clamped to [0, mips.size()] (0 without mips).
float mip_level(const TextureImage& img, float fw);
// The square wave s(x) (+1 on [0, 1), -1 on [1, 2), period 2) box-filtered over
// [x - w/2, x + w/2] (exact; w ~ 0 -> point value); and a pulse train (1 on [k, k + a))
// likewise. Building blocks of the filtered procedural textures (tested on their own).
float box_square(float x, float w);
// Alpha of a cut-out material at uv (alpha x the base-colour texture's alpha, bilinear at
// level 0: the cut-out edge is decided per ray, not filtered).
float material_alpha(const Scene& scene, const Material& m, glm::vec2 uv);
float box_pulse(float x, float w, float a);

// The explicit scene factory: "type" is one of atrium, patterns, cornell, file.
// See models/scenes/README.md for every key. Throws fovsim::Error with the JSON path.
Scene make_scene(Params& p, const std::string& models_dir);

}  // namespace fovsim
