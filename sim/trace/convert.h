// Coordinate conventions for importing recordings (traces/README.md "Column maps").
// fovsim: right-handed, +Y up, head looks down -Z, +X right (sim/core/math.h).
#pragma once
#include <string>

#include "sim/core/math.h"
#include "sim/core/params.h"

namespace fovsim {

// Maps source coordinates to fovsim: v_fovsim = M * v_source, with M a signed permutation
// (a reflection when the source is left-handed). Rotations map as R_f = M R_s M^T.
struct AxisMap {
  glm::dmat3 M{1.0};
  glm::dvec3 vec(const glm::dvec3& v) const { return M * v; }
  glm::dquat rot(const glm::dmat3& R_source) const;  // world-from-head in fovsim
};

// "fovsim" / "opengl" (identity), "unity" (left-handed, +Y up, +Z forward: z flips),
// "unreal" (left-handed, +Z up, +X forward, +Y right), or an object {"x": "+x", "y": "+y",
// "z": "-z"} naming the signed source axis of each fovsim axis.
AxisMap axis_map_from(const Json& j, const std::string& where);

// Rotation matrix from Euler angles (radians) about the source X, Y, Z axes. `order` lists
// the axes in the order the rotations act on a vector in the fixed frame (extrinsic), e.g.
// Unity's Quaternion.Euler is "ZXY" extrinsic: R = Ry * Rx * Rz. `intrinsic` reads the
// order as rotations about the moving axes (R = R_a1 * R_a2 * R_a3). Matrices are the
// usual right-hand-rule ones; for a left-handed source the axis map does the rest.
glm::dmat3 euler_matrix(const glm::dvec3& xyz_rad, const std::string& order, bool intrinsic);

// Unity transform.eulerAngles (degrees) -> fovsim world-from-head quaternion.
glm::dquat unity_euler_to_fovsim(double x_deg, double y_deg, double z_deg);

}  // namespace fovsim
