// The converged shared reference (DESIGN §4, render.spp): stratified supersampling with a box
// reconstruction filter. Each sub-sample is an independent primary ray + shading, so the
// result is the same at any thread count and on any ISA path as the 1-spp image is.
#include <tbb/parallel_for.h>

#include <cmath>

#include "sim/render/render_internal.h"

namespace fovsim {

namespace {

// Fixed jitter in [0, 1) per pixel and stratum (no frame dependence: a static view keeps its
// reference).
inline uint32_t mix32(uint32_t h) {
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}
inline float jitter(uint32_t x, uint32_t y, uint32_t s, uint32_t axis) {
  const uint32_t h = mix32(x * 0x9e3779b1u ^ mix32(y * 0x85ebca77u ^ mix32(s * 2u + axis)));
  return float(h >> 8) * (1.f / 16777216.f);
}

}  // namespace

glm::vec2 stratified_offset(int x, int y, int s, int n) {
  const int sx = s % n, sy = s / n;
  return {(float(sx) + jitter(uint32_t(x), uint32_t(y), uint32_t(s), 0u)) / float(n),
          (float(sy) + jitter(uint32_t(x), uint32_t(y), uint32_t(s), 1u)) / float(n)};
}

void Renderer::render_reference(const Camera& cam, const GBuffer& g1, Image& out,
                                Counters* c) const {
  const int spp = std::max(1, settings_.spp);
  if (spp == 1) {
    shade(g1, cam.position, out, nullptr, c);
    return;
  }
  const int n = int(std::lround(std::sqrt(double(spp))));
  const int W = cam.width, H = cam.height;
  const size_t np = size_t(W) * size_t(H);
  out.resize(W, H, 3);
  std::vector<double> acc(np * 3, 0.0);
  std::vector<glm::vec2> pts(np);
  GBuffer g;
  Image col;
  for (int s = 0; s < spp; ++s) {
    tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& r) {
      for (int y = r.begin(); y != r.end(); ++y)
        for (int x = 0; x < W; ++x) {
          const glm::vec2 o = stratified_offset(x, y, s, n);
          pts[size_t(y) * size_t(W) + size_t(x)] = glm::vec2(float(x) + o.x, float(y) + o.y);
        }
    });
    trace_points(cam, pts, kShadingChannels, g, c, 1.f / float(n));
    shade(g, cam.position, col, nullptr, c);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, np * 3, 1 << 14),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i != r.end(); ++i) acc[i] += col.data[i];
                      });
  }
  const double inv = 1.0 / double(spp);
  for (size_t i = 0; i < np * 3; ++i) out.data[i] = float(acc[i] * inv);
}

}  // namespace fovsim
