// Shared helpers for the metrics tests: deterministic synthetic images and cameras.
#pragma once
#include <cmath>

#include "sim/core/image.h"
#include "sim/core/rng.h"
#include "sim/display/display.h"

namespace fovsim {
namespace testutil {

// Smooth pattern + seeded noise, values in [0,1].
inline Image pattern(int w, int h, int c, uint64_t seed, double noise = 0.1) {
  Image im(w, h, c);
  Rng rng(seed);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < c; ++k) {
        double v = 0.5 + 0.3 * std::sin(x / (3.0 + k) + y / 5.0) * std::cos(y / 7.0) +
                   noise * (rng.uniform() - 0.5);
        im.at(x, y)[k] = float(v < 0 ? 0 : (v > 1 ? 1 : v));
      }
  return im;
}

// Camera with a given size and horizontal/vertical FOV, looking down -Z.
inline Camera camera(int w, int h, double fov_h, double fov_v) {
  Display d;
  d.width = w;
  d.height = h;
  d.fov_h_deg = fov_h;
  d.fov_v_deg = fov_v;
  return Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
}

}  // namespace testutil
}  // namespace fovsim
