// Common math: GLM types and a few helpers. Conventions used everywhere in fovsim:
// - world and head space are right-handed, +Y up; the head looks down -Z, +X is right;
// - pixel (i, j) has its centre at (i + 0.5, j + 0.5); x grows right, y grows DOWN, row 0 on top;
// - quaternions are world-from-head, stored (w, x, y, z) in files.
#pragma once
#define GLM_ENABLE_EXPERIMENTAL
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtx/quaternion.hpp>
#include <limits>

namespace fovsim {

constexpr double kPi = 3.14159265358979323846;
inline double deg2rad(double d) {
  return d * kPi / 180.0;
}
inline double rad2deg(double r) {
  return r * 180.0 / kPi;
}
template <class T>
inline T clamp01(T v) {
  return v < T(0) ? T(0) : (v > T(1) ? T(1) : v);
}
// Angle between two (not necessarily unit) vectors; atan2 form is accurate near 0 and pi.
inline double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}
inline float luma(float r, float g, float b) {
  return 0.2126f * r + 0.7152f * g + 0.0722f * b;
}

struct AABB {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};
  void extend(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool empty() const { return lo.x > hi.x; }
};

}  // namespace fovsim
