// TWFR forward reprojection (Franke et al. 2021 §4, §7). See twfr_reproject.h.
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

// The new view's projection with the rotation as a matrix (no quaternion or call per pixel).
// Same formulas as Camera::project_world / project_head (display.cpp).
struct Projector {
  glm::dmat3 head_from_world;
  glm::dvec3 pos;
  double sx, sy;  // 0.5 W / tan_half_h, 0.5 H / tan_half_v
  int W, H;
  explicit Projector(const Camera& c)
      : head_from_world(glm::mat3_cast(glm::conjugate(c.orientation))),
        pos(c.position),
        sx(0.5 * c.width / c.tan_half_h),
        sy(0.5 * c.height / c.tan_half_v),
        W(c.width),
        H(c.height) {}
};

// Target pixel and depth key of a sample in the new view; false if it misses the view.
inline bool splat_target(const Projector& pr, const Sample& s, const glm::vec3& p, int& tx, int& ty,
                         uint32_t& depth_bits) {
  glm::dvec3 h;
  if (s.kind == kSky) {
    h = pr.head_from_world * glm::dvec3(p);
    depth_bits = kSkyDepthBits;
    if (!(h.z < 0.0)) return false;
  } else {
    h = pr.head_from_world * (glm::dvec3(p) - pr.pos);
    const double depth = -h.z;
    if (!(depth > 0.0) || !std::isfinite(depth)) return false;
    depth_bits = float_bits(float(depth));
    if (depth_bits >= kSkyDepthBits) depth_bits = kSkyDepthBits - 1;
  }
  const double inv = 1.0 / -h.z;
  const double px = (h.x * inv) * pr.sx + 0.5 * pr.W, py = 0.5 * pr.H - (h.y * inv) * pr.sy;
  // NaN fails these comparisons too.
  if (!(px >= 0.0 && py >= 0.0 && px < double(pr.W) && py < double(pr.H))) return false;
  // A pixel-sized point sprite covers the pixel containing its projected point (§4).
  tx = std::min(int(px), pr.W - 1);
  ty = std::min(int(py), pr.H - 1);
  return true;
}

}  // namespace

void SplatBuffer::resize(size_t n) {
  if (n != size) {
    key.reset(new std::atomic<uint64_t>[n]);
    size = n;
  }
}

ReprojectStats forward_reproject(const ReprojectInput& in, Image& color,
                                 std::vector<Sample>& samples, std::vector<uint8_t>& covered,
                                 SplatBuffer& scratch) {
  const Camera& cam = *in.camera;
  const int W = cam.width, H = cam.height;
  const size_t n = size_t(W) * size_t(H);
  const Image& src_color = *in.color;
  const std::vector<Sample>& src = *in.samples;
  const std::vector<float>& ecc = *in.eccentricity;
  const Projector proj(cam);
  scratch.resize(n);
  if (color.width != W || color.height != H || color.channels != 3) color.resize(W, H, 3);
  samples.resize(n);
  covered.resize(n);

  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 14),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i)
                        scratch.key[i].store(kEmpty, std::memory_order_relaxed);
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
            if (!splat_target(proj, s, moved_position(in, s), tx, ty, db)) {
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
