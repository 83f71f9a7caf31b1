// VPLs from RSMs and single-bounce diffuse VPL shading (Yang et al. 2021 §3 S-2, S-7). See vpl.h.
#include "sim/render/vpl.h"

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "sim/render/renderer.h"

namespace fovsim {

void vpls_from_rsm(const RSM& rsm, std::vector<VPL>& out) {
  for (size_t i = 0; i < rsm.texels(); ++i) {
    if (!rsm.hit(i)) continue;
    const glm::vec3& f = rsm.flux[i];
    if (!(f.x > 0.f || f.y > 0.f || f.z > 0.f)) continue;
    VPL v;
    v.position = rsm.position[i];
    v.normal = rsm.normal[i];
    v.flux = f;
    v.light = rsm.light;
    v.texel = int(i);
    out.push_back(v);
  }
}

void VplSoA::clear() {
  for (auto* a : {&px, &py, &pz, &nx, &ny, &nz, &fr, &fg, &fb}) a->clear();
}

void VplSoA::push(const VPL& v, float weight) {
  const float s = weight * float(1.0 / kPi);  // vpl.h: Phi cos cos / (pi d^2)
  px.push_back(v.position.x);
  py.push_back(v.position.y);
  pz.push_back(v.position.z);
  nx.push_back(v.normal.x);
  ny.push_back(v.normal.y);
  nz.push_back(v.normal.z);
  fr.push_back(v.flux.x * s);
  fg.push_back(v.flux.y * s);
  fb.push_back(v.flux.z * s);
}

VplSoA make_soa(const std::vector<VPL>& vpls, const std::vector<uint32_t>& idx,
                const std::vector<float>& weight) {
  VplSoA s;
  for (size_t k = 0; k < idx.size(); ++k) s.push(vpls[idx[k]], weight.empty() ? 1.f : weight[k]);
  return s;
}

VplSoA make_soa(const std::vector<VPL>& vpls) {
  VplSoA s;
  for (const VPL& v : vpls) s.push(v, 1.f);
  return s;
}

glm::vec3 shade_vpls_point(const VplSoA& v, const glm::vec3& p, const glm::vec3& n,
                           const glm::vec3& a, const VplShading& s, const Renderer* r, float scale,
                           uint64_t* rays) {
  const size_t m = v.size();
  if (m == 0) return glm::vec3(0.f);
  const float dmin2 = s.min_dist * s.min_dist;
  float ar = 0.f, ag = 0.f, ab = 0.f;
  const float* px = v.px.data();
  const float* py = v.py.data();
  const float* pz = v.pz.data();
  const float* nx = v.nx.data();
  const float* ny = v.ny.data();
  const float* nz = v.nz.data();
  const float* fr = v.fr.data();
  const float* fg = v.fg.data();
  const float* fb = v.fb.data();
  if (!s.visibility || !r) {
    // cos_v cos_x = (n_v . d)(-n_x . d) / |d|^2: no square root, and 8 independent partial
    // sums (fixed order, so deterministic) let the compiler vectorise without -ffast-math.
    constexpr size_t kL = 8;
    float sr[kL] = {}, sg[kL] = {}, sb[kL] = {};
    size_t k = 0;
    for (; k + kL <= m; k += kL) {
      for (size_t j = 0; j < kL; ++j) {
        const size_t q = k + j;
        const float dx = p.x - px[q], dy = p.y - py[q], dz = p.z - pz[q];
        const float d2 = dx * dx + dy * dy + dz * dz;
        const float a = std::max(0.f, nx[q] * dx + ny[q] * dy + nz[q] * dz);
        const float b = std::max(0.f, -(n.x * dx + n.y * dy + n.z * dz));
        const float g = a * b / (std::max(d2, 1e-20f) * std::max(d2, dmin2));
        sr[j] += fr[q] * g;
        sg[j] += fg[q] * g;
        sb[j] += fb[q] * g;
      }
    }
    for (; k < m; ++k) {
      const float dx = p.x - px[k], dy = p.y - py[k], dz = p.z - pz[k];
      const float d2 = dx * dx + dy * dy + dz * dz;
      const float a = std::max(0.f, nx[k] * dx + ny[k] * dy + nz[k] * dz);
      const float b = std::max(0.f, -(n.x * dx + n.y * dy + n.z * dz));
      const float g = a * b / (std::max(d2, 1e-20f) * std::max(d2, dmin2));
      ar += fr[k] * g;
      ag += fg[k] * g;
      ab += fb[k] * g;
    }
    for (size_t j = 0; j < kL; ++j) {
      ar += sr[j];
      ag += sg[j];
      ab += sb[j];
    }
  } else {
    uint64_t nr = 0;
    const glm::vec3 pe = p + n * s.ray_offset;
    for (size_t k = 0; k < m; ++k) {
      const float dx = p.x - px[k], dy = p.y - py[k], dz = p.z - pz[k];
      const float d2 = dx * dx + dy * dy + dz * dz;
      const float inv = 1.f / std::sqrt(std::max(d2, 1e-20f));
      const float cv = (nx[k] * dx + ny[k] * dy + nz[k] * dz) * inv;
      const float cx = -(n.x * dx + n.y * dy + n.z * dz) * inv;
      if (cv <= 0.f || cx <= 0.f) continue;  // no contribution: no ray needed
      ++nr;
      const glm::vec3 ve(px[k] + nx[k] * s.ray_offset, py[k] + ny[k] * s.ray_offset,
                         pz[k] + nz[k] * s.ray_offset);
      if (r->occluded(ve, pe)) continue;
      const float g = cv * cx / std::max(d2, dmin2);
      ar += fr[k] * g;
      ag += fg[k] * g;
      ab += fb[k] * g;
    }
    if (rays) *rays += nr;
  }
  return a * glm::vec3(ar, ag, ab) * scale;
}

void shade_indirect(const GBuffer& g, const VplSoA& v, const VplShading& s, Image& out,
                    const Renderer* r, const uint8_t* mask, Counters* c) {
  if (out.width != g.width || out.height != g.height || out.channels != 3)
    out.resize(g.width, g.height, 3);
  std::atomic<uint64_t> shaded{0}, rays{0};
  const int tile = std::max(1, s.tile);
  tbb::parallel_for(tbb::blocked_range2d<int>(0, g.height, tile, 0, g.width, tile),
                    [&](const tbb::blocked_range2d<int>& b) {
                      uint64_t ns = 0, nr = 0;
                      for (int y = b.rows().begin(); y < b.rows().end(); ++y)
                        for (int x = b.cols().begin(); x < b.cols().end(); ++x) {
                          const size_t i = size_t(y) * size_t(g.width) + size_t(x);
                          float* o = out.at(x, y);
                          if (!g.hit(i) || (mask && !mask[i])) {
                            o[0] = o[1] = o[2] = 0.f;
                            continue;
                          }
                          ++ns;
                          glm::vec3 L = shade_vpls_point(v, g.position[i], g.normal[i], g.albedo[i],
                                                         s, r, 1.f, &nr);
                          o[0] = L.x;
                          o[1] = L.y;
                          o[2] = L.z;
                        }
                      shaded += ns;
                      rays += nr;
                    });
  if (c) {
    c->add(Counter::shaded_samples, double(shaded.load()));
    c->add(Counter::shaded_sample_vpls, double(shaded.load()) * double(v.size()));
    if (s.visibility) c->add(Counter::vpl_shadow_rays, double(rays.load()));
  }
}

}  // namespace fovsim
