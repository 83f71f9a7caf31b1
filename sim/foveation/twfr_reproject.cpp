// TWFR forward reprojection (seed 002 §4, §7). See twfr_reproject.h.
#include "sim/foveation/twfr_reproject.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <cmath>
#include <cstring>

namespace fovsim {
namespace twfr {

namespace {

constexpr uint64_t kEmpty = ~uint64_t(0);
constexpr uint32_t kSkyDepthBits = 0x7f800000u;  // +inf: any surface wins over the sky

inline uint32_t float_bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

inline void atomic_min(std::atomic<uint64_t>& a, uint64_t v) {
  uint64_t cur = a.load(std::memory_order_relaxed);
  while (v < cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

// Position of a source sample in the new frame (world point, or world direction for the sky).
inline glm::vec3 moved_position(const ReprojectInput& in, const Sample& s) {
  if (s.kind == kSurface && s.object >= 0 && in.object_dynamic &&
      size_t(s.object) < in.object_dynamic->size() && (*in.object_dynamic)[size_t(s.object)])
    return glm::vec3((*in.object_motion)[size_t(s.object)] * glm::vec4(s.pos, 1.f));
  return s.pos;
}

// Target pixel and depth key of a sample in the new view; false if it misses the view.
inline bool splat_target(const Camera& cam, const Sample& s, const glm::vec3& p, int& tx, int& ty,
                         uint32_t& depth_bits) {
  glm::dvec2 px;
  if (s.kind == kSky) {
    if (!cam.project_head(cam.to_head_dir(glm::dvec3(p)), px)) return false;
    depth_bits = kSkyDepthBits;
  } else {
    double depth = 0;
    if (!cam.project_world(glm::dvec3(p), px, &depth)) return false;
    if (!(depth > 0.0) || !std::isfinite(depth)) return false;
    depth_bits = float_bits(float(depth));
    if (depth_bits >= kSkyDepthBits) depth_bits = kSkyDepthBits - 1;
  }
  if (!(std::isfinite(px.x) && std::isfinite(px.y)) || !cam.inside(px)) return false;
  // A pixel-sized point sprite covers the pixel containing its projected point (§4).
  tx = int(std::floor(px.x));
  ty = int(std::floor(px.y));
  if (tx >= cam.width) tx = cam.width - 1;
  if (ty >= cam.height) ty = cam.height - 1;
  return true;
}

}  // namespace

void SplatBuffer::resize(size_t n) {
  if (n != size) {
    key.reset(new std::atomic<uint64_t>[n]);
    size = n;
  }
}

ReprojectStats forward_reproject(const ReprojectInput& in, Image& color, std::vector<Sample>& samples,
                                 std::vector<uint8_t>& covered, SplatBuffer& scratch) {
  const Camera& cam = *in.camera;
  const int W = cam.width, H = cam.height;
  const size_t n = size_t(W) * size_t(H);
  const Image& src_color = *in.color;
  const std::vector<Sample>& src = *in.samples;
  const std::vector<float>& ecc = *in.eccentricity;
  scratch.resize(n);
  if (color.width != W || color.height != H || color.channels != 3) color.resize(W, H, 3);
  samples.resize(n);
  covered.resize(n);

  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 14), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) scratch.key[i].store(kEmpty, std::memory_order_relaxed);
  });

  struct Counts {
    size_t splats = 0, offscreen = 0, fovea = 0;
  };
  // Pass 1: scatter with depth test (hardware depth test in the seed).
  Counts c = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, H), Counts{},
      [&](const tbb::blocked_range<int>& rows, Counts acc) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
          for (int x = 0; x < W; ++x) {
            const size_t si = size_t(y) * size_t(W) + size_t(x);
            const Sample& s = src[si];
            if (s.kind == kNoSample) continue;
            ++acc.splats;
            int tx, ty;
            uint32_t db;
            if (!splat_target(cam, s, moved_position(in, s), tx, ty, db)) {
              ++acc.offscreen;
              continue;
            }
            const size_t ti = size_t(ty) * size_t(W) + size_t(tx);
            if (ecc[ti] < in.fovea_deg) {  // §4: foveal splats are discarded, the fovea is redrawn
              ++acc.fovea;
              continue;
            }
            atomic_min(scratch.key[ti], (uint64_t(db) << 32) | uint64_t(si));
          }
        }
        return acc;
      },
      [](Counts a, const Counts& b) {
        a.splats += b.splats;
        a.offscreen += b.offscreen;
        a.fovea += b.fovea;
        return a;
      });

  // Pass 2: gather the winners (colour + moved sample, age + 1).
  size_t landed = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, H), size_t(0),
      [&](const tbb::blocked_range<int>& rows, size_t acc) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
          for (int x = 0; x < W; ++x) {
            const size_t ti = size_t(y) * size_t(W) + size_t(x);
            const uint64_t k = scratch.key[ti].load(std::memory_order_relaxed);
            float* dst = color.at(x, y);
            if (k == kEmpty) {
              dst[0] = dst[1] = dst[2] = 0.f;
              samples[ti] = Sample{};
              covered[ti] = 0;
              continue;
            }
            const size_t si = size_t(k & 0xffffffffu);
            const Sample& s = src[si];
            const float* sc = &src_color.data[si * 3];
            dst[0] = sc[0];
            dst[1] = sc[1];
            dst[2] = sc[2];
            Sample o = s;
            o.pos = moved_position(in, s);
            o.age = s.age == 0xffff ? s.age : uint16_t(s.age + 1);
            samples[ti] = o;
            covered[ti] = 1;
            ++acc;
          }
        }
        return acc;
      },
      [](size_t a, size_t b) { return a + b; });

  ReprojectStats st;
  st.splats = c.splats;
  st.offscreen = c.offscreen;
  st.fovea_discarded = c.fovea;
  st.landed = landed;
  return st;
}

}  // namespace twfr
}  // namespace fovsim
