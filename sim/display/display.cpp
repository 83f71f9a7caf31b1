#include "sim/display/display.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "sim/core/error.h"
#include "sim/core/param_table.h"
#include "sim/display/display_keys.h"

namespace fovsim {

namespace {
// A flat screen given by its diagonal (inches or degrees) without fov_h_deg: the FOV follows
// from its size at the viewing distance instead of being read.
bool fov_from_diagonal(const Params& p) {
  auto positive = [&](const char* k) {
    const Json& j = p.json();
    return j.contains(k) && j.at(k).is_number() && j.at(k).get<double>() > 0;
  };
  return (positive("diagonal_inches") || positive("fov_diagonal_deg")) && !p.has("fov_h_deg");
}
}  // namespace

const ParamTable<Display>& display_table() {
  using D = Display;
  auto read_fov = [](const Params& p) { return !fov_from_diagonal(p); };
  static const auto t =
      ParamTable<D>()
          .text("name", "custom", {}, &D::name)
          .doc("", "display name (results, manifest)")
          .integer("width", 0, Range::closed(1, 16384), &D::width)
          .required()
          .doc("", "pixels per eye, horizontal")
          .integer("height", 0, Range::closed(1, 16384), &D::height)
          .required()
          .doc("", "pixels per eye, vertical")
          .number("refresh_hz", 90.0, Range::above(0, 1000), &D::refresh_hz)
          .doc("", "refresh rate; the trace is resampled to it")
          .integer("eyes", 1, Range::closed(1, 2), &D::eyes)
          .doc("", "eyes rendered per frame (the cost model charges each)")
          .text("source", "", {}, &D::source)
          .doc("", "where the numbers come from")
          // Photometry and physical geometry (FovVideoVDP's display model).
          .number("peak_luminance", 100.0, Range::above(0, 1e5), &D::peak_luminance)
          .doc("Mantiuk et al. 2021", "peak (white) luminance, cd/m^2")
          .number("black_luminance", 0.0, Range::closed(0, 1e4), &D::black_luminance)
          .shown("0", "[0, peak_luminance)")
          .doc("Mantiuk et al. 2021", "black level, cd/m^2; 0 = `peak_luminance / contrast`")
          .number("contrast", 500.0, Range::above(1, 1e9), &D::contrast)
          .doc("Mantiuk et al. 2021", "panel contrast, used when `black_luminance` is 0")
          .number("ambient_lux", 0.0, Range::closed(0, 1e6), &D::ambient_lux)
          .doc("Mantiuk et al. 2021",
               "ambient illuminance; adds `ambient_lux/pi reflectivity` to the black level")
          .number("reflectivity", 0.005, Range::closed(0, 1), &D::reflectivity)
          .doc("Mantiuk et al. 2021", "panel reflectivity")
          .number("viewing_distance_m", 0.0, Range::closed(0, 100), &D::viewing_distance_m)
          .doc("Mantiuk et al. 2021",
               "viewing distance; 0 = unknown (FovVideoVDP assumes 3 m, "
               "the virtual screen of a headset)")
          .number("diagonal_inches", 0.0, Range::closed(0, 1000), &D::diagonal_inches)
          .doc("", "physical diagonal of a flat screen (0 = absent)")
          .number("fov_diagonal_deg", 0.0, Range::closed(0, 179), &D::fov_diagonal_deg)
          .doc("", "diagonal FOV (0 = absent); not with `diagonal_inches`")
          .number("fov_h_deg", 0, Range::above(0, 179), &D::fov_h_deg)
          .required()
          .read_if(read_fov)
          .shown("required", "(0, 179]")
          .doc("",
               "horizontal FOV (symmetric); derived from the diagonal when that is given "
               "instead")
          .number("fov_v_deg", 0, Range::above(0, 179), &D::fov_v_deg)
          .required()
          .read_if(read_fov)
          .shown("required", "(0, 179]")
          .doc("", "vertical FOV (symmetric); derived with `fov_h_deg`")
          .validate([](const D& d, Params& p) {
            if (d.black_luminance >= d.peak_luminance)
              throw Error(
                  p.where("black_luminance"),
                  "must be below peak_luminance (" + std::to_string(d.peak_luminance) + " cd/m2)");
            if (d.diagonal_inches > 0 && d.fov_diagonal_deg > 0)
              throw Error(p.where("diagonal_inches"),
                          "give diagonal_inches or fov_diagonal_deg, not both");
          });
  return t;
}

Display Display::from_params(Params& p) {
  Display d;
  display_table().read_into(p, d);
  if (fov_from_diagonal(p)) {
    // A flat screen: FOV from its physical size at the viewing distance (3 m when unknown).
    const double dist = d.viewing_distance_m > 0 ? d.viewing_distance_m : 3.0;
    const double a = double(d.width) / double(d.height);
    double h_m;
    if (d.diagonal_inches > 0) {
      const double D = d.diagonal_inches * 0.0254;
      h_m = std::sqrt(D * D / (1 + a * a));
    } else {
      const double px = std::sqrt(double(d.width) * d.width + double(d.height) * d.height) /
                        (2.0 * std::tan(deg2rad(d.fov_diagonal_deg) / 2.0));
      h_m = d.height * dist / px;
    }
    d.fov_h_deg = rad2deg(2.0 * std::atan(a * h_m / (2.0 * dist)));
    d.fov_v_deg = rad2deg(2.0 * std::atan(h_m / (2.0 * dist)));
  }
  p.ignore("comment");
  return d;
}

Display Display::load(const std::string& name_or_path, const std::string& models_dir) {
  std::string path = name_or_path;
  if (path.find('/') == std::string::npos && path.find(".json") == std::string::npos)
    path = models_dir + "/displays/" + name_or_path + ".json";
  if (!std::filesystem::exists(path)) {
    std::vector<std::string> names;
    std::error_code ec;
    for (auto& e : std::filesystem::directory_iterator(models_dir + "/displays", ec))
      if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    std::string list;
    for (auto& n : names) list += (list.empty() ? "" : ", ") + n;
    std::string hint = closest_name(name_or_path, names);
    throw Error(path, "display model not found" +
                          (hint.empty() ? std::string() : " (did you mean \"" + hint + "\"?)") +
                          "; displays in " + models_dir + "/displays: " +
                          (list.empty() ? "none" : list) + " (or give a path to a display JSON)");
  }
  Params p = Params::from_file(path);
  Display d = from_params(p);
  p.finish();
  return d;
}

Display Display::from_config(Params& root, const std::string& models_dir) {
  if (root.has("display") && root.json()["display"].is_object()) {
    Params dp = root.child("display");
    return from_params(dp);
  }
  return load(root.string("display", kDefaultDisplay), models_dir);
}

Json Display::to_json() const {
  return Json{{"name", name},
              {"width", width},
              {"height", height},
              {"fov_h_deg", fov_h_deg},
              {"fov_v_deg", fov_v_deg},
              {"refresh_hz", refresh_hz},
              {"eyes", eyes},
              {"source", source},
              {"peak_luminance", peak_luminance},
              {"black_luminance", black_luminance},
              {"contrast", contrast},
              {"ambient_lux", ambient_lux},
              {"reflectivity", reflectivity},
              {"viewing_distance_m", viewing_distance_m},
              {"diagonal_inches", diagonal_inches},
              {"fov_diagonal_deg", fov_diagonal_deg}};
}

Display Display::scaled(double s) const {
  Display d = *this;
  d.width = std::max(1, int(std::lround(width * s)));
  d.height = std::max(1, int(std::lround(height * s)));
  return d;
}

double Display::ppd_center() const {
  Camera c = Camera::from_pose(*this, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  return c.ppd_at(width * 0.5, height * 0.5);
}

Camera Camera::from_pose(const Display& d, const glm::dvec3& pos, const glm::dquat& rot) {
  Camera c;
  c.width = d.width;
  c.height = d.height;
  c.tan_half_h = d.tan_half_h();
  c.tan_half_v = d.tan_half_v();
  c.position = pos;
  c.orientation = glm::normalize(rot);
  return c;
}

glm::dvec3 Camera::dir_head(double px, double py) const {
  double x = (2.0 * px / width - 1.0) * tan_half_h;
  double y = (1.0 - 2.0 * py / height) * tan_half_v;
  return glm::normalize(glm::dvec3(x, y, -1.0));
}

bool Camera::project_head(const glm::dvec3& dir, glm::dvec2& px) const {
  if (!(dir.z < 0.0)) return false;
  double x = dir.x / -dir.z, y = dir.y / -dir.z;
  px.x = (x / tan_half_h + 1.0) * 0.5 * width;
  px.y = (1.0 - y / tan_half_v) * 0.5 * height;
  return true;
}

bool Camera::project_world(const glm::dvec3& p, glm::dvec2& px, double* depth) const {
  glm::dvec3 h = glm::conjugate(orientation) * (p - position);
  if (depth) *depth = -h.z;
  return project_head(h, px);
}

double Camera::ppd_at(double px, double py) const {
  // Central difference of the angle over one pixel, horizontally and vertically; report
  // the mean of the two (the local sampling rate in pixels per degree).
  const double h = 0.5;
  double ax = rad2deg(angle_between(dir_head(px - h, py), dir_head(px + h, py)));
  double ay = rad2deg(angle_between(dir_head(px, py - h), dir_head(px, py + h)));
  return 0.5 * (1.0 / ax + 1.0 / ay);
}

void eccentricity_map(const Camera& cam, const glm::dvec3& gaze_dir_head, std::vector<float>& e) {
  e.resize(size_t(cam.width) * size_t(cam.height));
  glm::dvec3 g = glm::normalize(gaze_dir_head);
  tbb::parallel_for(0, cam.height, [&](int y) {
    for (int x = 0; x < cam.width; ++x)
      e[size_t(y) * size_t(cam.width) + size_t(x)] =
          float(cam.eccentricity_deg(x + 0.5, y + 0.5, g));
  });
}

std::vector<float> eccentricity_map(const Camera& cam, const glm::dvec3& gaze_dir_head) {
  std::vector<float> e;
  eccentricity_map(cam, gaze_dir_head, e);
  return e;
}

glm::dvec3 gaze_dir_from_screen(const Display& d, double u, double v) {
  double x = (2.0 * u - 1.0) * d.tan_half_h();
  double y = (1.0 - 2.0 * v) * d.tan_half_v();
  return glm::normalize(glm::dvec3(x, y, -1.0));
}

bool gaze_screen_from_dir(const Display& d, const glm::dvec3& dir, double& u, double& v) {
  if (!(dir.z < 0.0)) return false;
  double x = dir.x / -dir.z, y = dir.y / -dir.z;
  u = (x / d.tan_half_h() + 1.0) * 0.5;
  v = (1.0 - y / d.tan_half_v()) * 0.5;
  return true;
}

}  // namespace fovsim
