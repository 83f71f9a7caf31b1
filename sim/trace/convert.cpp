#include "sim/trace/convert.h"

#include "sim/core/error.h"

namespace fovsim {

glm::dquat AxisMap::rot(const glm::dmat3& R) const {
  glm::dmat3 Rf = M * R * glm::transpose(M);
  return glm::normalize(glm::quat_cast(Rf));
}

static glm::dvec3 signed_axis(const Json& v, const std::string& where) {
  std::string s = v.is_string() ? v.get<std::string>() : "";
  if (s.size() == 1) s = "+" + s;
  if (s.size() == 2 && (s[0] == '+' || s[0] == '-') &&
      (s[1] == 'x' || s[1] == 'y' || s[1] == 'z')) {
    glm::dvec3 a(0.0);
    a[s[1] - 'x'] = s[0] == '-' ? -1.0 : 1.0;
    return a;
  }
  throw Error(where,
              "expected a signed source axis such as \"+x\" or \"-z\", got " + describe_json(v));
}

AxisMap axis_map_from(const Json& j, const std::string& where) {
  AxisMap a;
  if (j.is_string()) {
    std::string n = j.get<std::string>();
    if (n == "fovsim" || n == "opengl") return a;
    if (n == "unity") {
      a.M = glm::dmat3(1, 0, 0, 0, 1, 0, 0, 0, -1);
      return a;
    }
    if (n == "unreal") {
      // fovsim x (right) = UE +Y, fovsim y (up) = UE +Z, fovsim z (back) = UE -X.
      glm::dmat3 M(0.0);
      M[1][0] = 1;   // column 1 (source y) -> row 0 (fovsim x)
      M[2][1] = 1;   // source z -> fovsim y
      M[0][2] = -1;  // source x -> -fovsim z
      a.M = M;
      return a;
    }
    throw Error(where, "unknown coordinate convention \"" + n +
                           "\" (allowed: fovsim, opengl, unity, unreal, or an "
                           "object {\"x\": \"+x\", \"y\": \"+y\", \"z\": \"-z\"})");
  }
  if (!j.is_object())
    throw Error(where, "expected a convention name or an axis object, got " + describe_json(j));
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "x" && it.key() != "y" && it.key() != "z")
      throw Error(where + "." + it.key(), "unknown key (expected x, y, z)");
  glm::dmat3 M(0.0);
  for (int r = 0; r < 3; ++r) {
    std::string k(1, char('x' + r));
    if (!j.contains(k))
      throw Error(where + "." + k, "missing: which signed source axis is fovsim " + k + "?");
    glm::dvec3 s = signed_axis(j[k], where + "." + k);
    for (int c = 0; c < 3; ++c) M[c][r] = s[c];  // row r of M = source axis
  }
  double det = glm::determinant(M);
  if (std::fabs(std::fabs(det) - 1.0) > 1e-9) throw Error(where, "the three axes must be distinct");
  a.M = M;
  return a;
}

static glm::dmat3 axis_rot(char axis, double a) {
  double c = std::cos(a), s = std::sin(a);
  // glm matrices are column-major: m[col][row].
  switch (axis) {
    case 'X':
      return glm::dmat3(1, 0, 0, 0, c, s, 0, -s, c);
    case 'Y':
      return glm::dmat3(c, 0, -s, 0, 1, 0, s, 0, c);
    default:
      return glm::dmat3(c, s, 0, -s, c, 0, 0, 0, 1);
  }
}

glm::dmat3 euler_matrix(const glm::dvec3& xyz, const std::string& order, bool intrinsic) {
  glm::dmat3 R(1.0);
  for (char ax : order) {
    double a = ax == 'X' ? xyz.x : ax == 'Y' ? xyz.y : xyz.z;
    // Extrinsic: each later rotation pre-multiplies; intrinsic: post-multiplies.
    R = intrinsic ? R * axis_rot(ax, a) : axis_rot(ax, a) * R;
  }
  return R;
}

glm::dquat unity_euler_to_fovsim(double x_deg, double y_deg, double z_deg) {
  AxisMap u = axis_map_from(Json("unity"), "unity");
  return u.rot(euler_matrix({deg2rad(x_deg), deg2rad(y_deg), deg2rad(z_deg)}, "ZXY", false));
}

}  // namespace fovsim
