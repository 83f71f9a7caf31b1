// Headset/display model (docs/architecture.md "Inputs: displays, traces, scenes, configs"): per-eye
// resolution, symmetric FOV, refresh rate, eyes. fovsim simulates one eye's view; the cost model
// charges per-eye work `eyes` times.
#pragma once
#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/core/params.h"

namespace fovsim {

// The display every command and config uses when none is named (the one place it is written;
// Python reads it from the module as fovsim.DEFAULT_DISPLAY).
inline constexpr const char* kDefaultDisplay = "htc_vive_pro_eye";

struct Display {
  std::string name = "custom";
  int width = 1440, height = 1600;  // per eye, pixels
  double fov_h_deg = 98.0, fov_v_deg = 107.0;
  double refresh_hz = 90.0;
  int eyes = 2;
  std::string source;  // where the numbers come from
  // Photometry (FovVideoVDP's display model, Mantiuk et al. 2021; defaults of its reference
  // display database): peak luminance cd/m², black level cd/m² (0 = from the contrast),
  // contrast (used when black_luminance is 0), ambient illuminance lux, panel reflectivity.
  double peak_luminance = 100.0, black_luminance = 0.0, contrast = 500.0;
  double ambient_lux = 0.0, reflectivity = 0.005;
  // Optional physical geometry: viewing distance (0 = unknown, 3 m assumed by FovVideoVDP) and
  // either a diagonal size or a diagonal FOV (0 = absent; the FOVs above then give the size).
  double viewing_distance_m = 0.0, diagonal_inches = 0.0, fov_diagonal_deg = 0.0;

  // Reads models/displays/NAME.json or a path; keys: name, width, height, fov_h_deg,
  // fov_v_deg, refresh_hz, eyes, source, peak_luminance, black_luminance, contrast, ambient_lux,
  // reflectivity, viewing_distance_m, diagonal_inches, fov_diagonal_deg (configs/README.md).
  // fov_h_deg/fov_v_deg may be omitted when viewing_distance_m and diagonal_inches or
  // fov_diagonal_deg are given (a flat screen: derived from its size). Unknown keys are errors.
  static Display from_params(Params& p);
  static Display load(const std::string& name_or_path, const std::string& models_dir);
  // The config key `display` of `root`: an inline object (from_params), a name or path (load),
  // or kDefaultDisplay when absent; anything else is an error at that key.
  static Display from_config(Params& root, const std::string& models_dir);
  Json to_json() const;

  // Same FOV at a scaled pixel count (render.scale < 1 makes a cheaper simulation).
  Display scaled(double s) const;
  double tan_half_h() const { return std::tan(deg2rad(fov_h_deg) * 0.5); }
  double tan_half_v() const { return std::tan(deg2rad(fov_v_deg) * 0.5); }
  // Pixels per degree along the horizontal axis at the view centre (exact, from the projection).
  double ppd_center() const;
  double frame_budget_ms() const { return 1000.0 / refresh_hz; }
};

// Pinhole camera for one eye: pose (world-from-head) + the display's projection.
struct Camera {
  int width = 0, height = 0;
  double tan_half_h = 1, tan_half_v = 1;
  glm::dvec3 position{0.0};
  glm::dquat orientation{1, 0, 0, 0};  // world-from-head

  static Camera from_pose(const Display& d, const glm::dvec3& pos, const glm::dquat& rot);

  // Head-space direction (unit) through screen point (px, py) in pixels (centre of pixel i is
  // i+0.5).
  glm::dvec3 dir_head(double px, double py) const;
  glm::dvec3 dir_world(double px, double py) const { return orientation * dir_head(px, py); }
  glm::dvec3 to_world_dir(const glm::dvec3& head_dir) const { return orientation * head_dir; }
  glm::dvec3 to_head_dir(const glm::dvec3& world_dir) const {
    return glm::conjugate(orientation) * world_dir;
  }
  // Projects a head-space direction to pixels. Returns false (and leaves px) if the direction
  // points behind the eye (z >= 0). The point may land outside [0,W)x[0,H).
  bool project_head(const glm::dvec3& dir, glm::dvec2& px) const;
  // Projects a world point; `depth` is the distance along the view axis (-z in head space).
  bool project_world(const glm::dvec3& p, glm::dvec2& px, double* depth = nullptr) const;
  bool inside(const glm::dvec2& px) const {
    return px.x >= 0 && px.y >= 0 && px.x < width && px.y < height;
  }

  // Exact eccentricity (degrees) of pixel point (px,py): angle between the gaze ray and the
  // pixel's ray through the real projection (docs/architecture.md "Inputs: displays, traces,
  // scenes, configs"; not a pixel-distance proxy).
  double eccentricity_deg(double px, double py, const glm::dvec3& gaze_dir_head) const {
    return rad2deg(angle_between(dir_head(px, py), gaze_dir_head));
  }
  // Local pixels per degree at (px, py) along the direction towards `toward_px` (radial),
  // from the projection's Jacobian: 1 / (d angle / d pixel).
  double ppd_at(double px, double py) const;
};

// Per-pixel eccentricity in degrees (row-major, W*H), computed in parallel.
std::vector<float> eccentricity_map(const Camera& cam, const glm::dvec3& gaze_dir_head);
// The same into `out` (resized to W*H; keeps its storage when the size is unchanged, so the
// per-frame map of a run allocates once).
void eccentricity_map(const Camera& cam, const glm::dvec3& gaze_dir_head, std::vector<float>& out);

// Converts between a gaze direction in head space and a normalized screen point
// ((0,0) top-left, (1,1) bottom-right). The screen point may be outside [0,1].
glm::dvec3 gaze_dir_from_screen(const Display& d, double u, double v);
bool gaze_screen_from_dir(const Display& d, const glm::dvec3& dir, double& u, double& v);

}  // namespace fovsim
