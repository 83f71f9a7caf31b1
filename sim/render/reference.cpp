// The converged shared reference (docs/architecture.md "Rendering and the shared reference",
// render.spp): stratified supersampling with a box reconstruction filter. Each sub-sample is an
// independent primary ray + shading, so the result is the same at any thread count and on any ISA
// path as the 1-spp image is.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "sim/render/render_internal.h"
#include "sim/render/vec4.h"

namespace fovsim {

namespace {

// Fixed jitter in [0, 1) per pixel and stratum (no frame dependence: a static view keeps its
// reference). The hash nests stratum, row and column, so its inner parts are computed once per
// stratum (stratum_hash) and once per stratum and row (row_hash).
inline uint32_t mix32(uint32_t h) {
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}
inline uint32_t stratum_hash(uint32_t s, uint32_t axis) {
  return mix32(s * 2u + axis);
}
inline uint32_t row_hash(uint32_t y, uint32_t hs) {
  return mix32(y * 0x85ebca77u ^ hs);
}
inline float jitter_at(uint32_t x, uint32_t hr) {
  const uint32_t h = mix32(x * 0x9e3779b1u ^ hr);
  return float(h >> 8) * (1.f / 16777216.f);
}
inline float jitter(uint32_t x, uint32_t y, uint32_t s, uint32_t axis) {
  return jitter_at(x, row_hash(y, stratum_hash(s, axis)));
}

// Per-thread scratch of the reference pass: one primary-ray packet and the shading buffers.
struct RefScratch {
  PointPacketTracer tracer;
  ShadeScratch shade;
};

constexpr size_t kLane[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};

// mix32 and jitter_at on 4 lanes (SSE2 integer vectors: the products are the same 32-bit
// wrap-around multiplications; h >> 8 < 2^24 converts to float exactly either way).
typedef uint32_t vu __attribute__((vector_size(16)));
inline vu mix32v(vu h) {
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}
inline vf jitter_at4(vu x, vu hr) {
  const vu h = mix32v(x * 0x9e3779b1u ^ hr);
  return __builtin_convertvector((vi)(h >> 8), vf) * (1.f / 16777216.f);
}

}  // namespace

glm::vec2 stratified_offset(int x, int y, int s, int n) {
  const int sx = s % n, sy = s / n;
  return {(float(sx) + jitter(uint32_t(x), uint32_t(y), uint32_t(s), 0u)) / float(n),
          (float(sy) + jitter(uint32_t(x), uint32_t(y), uint32_t(s), 1u)) / float(n)};
}

// Pixels go in packets of 16 consecutive pixels in scanline order (pixel indices 16p .. 16p+15,
// rows wrap inside a packet), all spp strata of a packet before the next: trace a stratum's 16
// rays (one rtcIntersect16), shade them from the packet's own staging buffer (one
// rtcOccluded16 per light), add them to the packet's sums. The packets, their lanes and every
// sample's operations are those of the former pass (per stratum: a frame of points through
// trace_points, whose packets are the same 16 consecutive indices, shade(), whose blocks are
// too, and a frame-sized double sum), and each pixel's sum still adds strata 0, 1, ..., spp-1 in
// order, so the image is bit-identical; it no longer streams 16 times through frame-sized
// G-buffers and colour buffers (tests/render/reference_test.cpp keeps the former pass and
// compares; bench/README.md has the times).
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
  const RenderState& I = *impl_;
  const glm::vec3 eye(cam.position);
  const float fn = float(n);
  // Per stratum: its cell (sx, sy) and the stratum part of both axes' jitter hashes.
  struct Stratum {
    float sx, sy;
    uint32_t hx, hy;
  };
  std::vector<Stratum> strata(static_cast<size_t>(spp));
  for (int s = 0; s < spp; ++s)
    strata[size_t(s)] = {float(s % n), float(s / n), stratum_hash(uint32_t(s), 0u),
                         stratum_hash(uint32_t(s), 1u)};
  const size_t npk = (np + 15) / 16;
  const size_t G = 16;  // packets per task: 256 pixels x spp samples
  const size_t nt = (npk + G - 1) / G;
  std::vector<uint64_t> shadow(nt, 0);
  tbb::enumerable_thread_specific<RefScratch> tls([&] {
    return RefScratch{PointPacketTracer(scene_, I, cam, kShadingChannels, 1.f / fn), {}};
  });
  const double inv = 1.0 / double(spp);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, nt, 1),
      [&](const tbb::blocked_range<size_t>& r) {
        RefScratch& sc = tls.local();
        for (size_t t = r.begin(); t != r.end(); ++t) {
          uint64_t sr = 0;
          for (size_t p = t * G, pe = std::min(npk, p + G); p < pe; ++p) {
            const size_t i0 = p * 16;
            const int m = int(std::min<size_t>(16, np - i0));
            alignas(16) uint32_t xs[16], ys[16];
            for (int k = 0; k < 16; ++k) {  // lanes past m: copies of lane 0, never read
              const size_t i = i0 + size_t(k < m ? k : 0);
              xs[k] = uint32_t(i % size_t(W));
              ys[k] = uint32_t(i / size_t(W));
            }
            double acc[48] = {};
            for (int s = 0; s < spp; ++s) {
              const Stratum& S = strata[size_t(s)];
              glm::vec2 pts[16];
              alignas(16) uint32_t hrx[16], hry[16];
              uint32_t y = ~0u, hx = 0, hy = 0;
              for (int k = 0; k < 16; ++k) {  // the row part of the hashes (a packet has 1-2 rows)
                if (ys[k] != y) {
                  y = ys[k];
                  hx = row_hash(y, S.hx);
                  hy = row_hash(y, S.hy);
                }
                hrx[k] = hx;
                hry[k] = hy;
              }
              // == stratified_offset(x, y, s, n), added to the pixel's corner, 4 lanes at a time.
              const vf vsx = splat(S.sx), vsy = splat(S.sy), vfn = splat(fn);
              for (int k = 0; k < 16; k += 4) {
                vu x, y4, rx, ry;
                __builtin_memcpy(&x, xs + k, sizeof x);
                __builtin_memcpy(&y4, ys + k, sizeof y4);
                __builtin_memcpy(&rx, hrx + k, sizeof rx);
                __builtin_memcpy(&ry, hry + k, sizeof ry);
                const vf ox = (vsx + jitter_at4(x, rx)) / vfn;
                const vf oy = (vsy + jitter_at4(x, ry)) / vfn;
                const vf px = __builtin_convertvector((vi)x, vf) + ox;
                const vf py = __builtin_convertvector((vi)y4, vf) + oy;
                for (int j = 0; j < 4; ++j) {
                  pts[k + j].x = px[j];
                  pts[k + j].y = py[j];
                }
              }
              const GBuffer& g = sc.tracer.trace(pts, m);
              float col[48];
              shade_packet(scene_, I, settings_.shadows, g, kLane, m, eye, col, sr, sc.shade);
              for (int j = 0; j < 3 * m; ++j) acc[j] += double(col[j]);
            }
            float* o = &out.data[i0 * 3];
            for (int j = 0; j < 3 * m; ++j) o[j] = float(acc[j] * inv);
          }
          shadow[t] = sr;
        }
      },
      tbb::simple_partitioner());
  uint64_t sr = 0;
  for (uint64_t v : shadow) sr += v;
  const uint64_t samples = uint64_t(np) * uint64_t(spp);
  rays_ += samples + sr;
  if (c) {
    // The former pass added these once per stratum, in this order (integers: the same sums).
    c->add(Counter::primary_rays, double(samples));
    c->add(Counter::shaded_samples, double(samples));
    c->add(Counter::shadow_rays, double(sr));
  }
}

}  // namespace fovsim
