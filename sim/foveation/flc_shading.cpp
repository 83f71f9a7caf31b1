// FLC shading passes (Yang et al. 2021 §6). See flc_shading.h.
#include "sim/foveation/flc_shading.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "sim/core/math.h"
#include "sim/foveation/lighting.h"

namespace fovsim {

namespace {
// One thread's (or a whole pass's) shading work: samples shaded, sample x VPL pairs, shadow
// rays, as the counters report them.
struct ShadeTally {
  uint64_t shaded = 0, pairs = 0, rays = 0;
};
struct ShadeTotals {
  std::atomic<uint64_t> shaded{0}, pairs{0}, rays{0};
  void add(const ShadeTally& t) {
    shaded += t.shaded;
    pairs += t.pairs;
    rays += t.rays;
  }
};
// G-buffer sample i shaded by the VPLs of `grp` into o (RGB), counted in t.
inline void shade_sample(const GBuffer& g, size_t i, const VplSoA& grp, const VplShading& s,
                         const Renderer* r, float* o, ShadeTally& t) {
  const glm::vec3 L = shade_vpls(grp, g.position[i], g.normal[i], g.albedo[i], s, r, 1.f, &t.rays);
  ++t.shaded;
  t.pairs += grp.size();
  o[0] = L.x;
  o[1] = L.y;
  o[2] = L.z;
}
}  // namespace

std::vector<VplSoA> flc_interleave_groups(const std::vector<VPL>& vpls,
                                          const std::vector<uint32_t>& idx,
                                          const std::vector<float>& weight, int n) {
  n = std::max(1, n);
  const size_t G = size_t(n) * size_t(n);
  std::vector<VplSoA> groups(G);
  for (size_t k = 0; k < idx.size(); ++k)
    groups[k % G].push(vpls[idx[k]], (weight.empty() ? 1.f : weight[k]) * float(G));
  return groups;
}

void flc_gauss3(Image& img, const std::vector<uint8_t>& valid, bool wrap_y, Image* scratch) {
  const int W = img.width, H = img.height, C = img.channels;
  if (W == 0 || H == 0) return;
  Image local;
  Image& src = scratch ? *scratch : local;  // the filter needs the unfiltered neighbours
  if (src.width != W || src.height != H || src.channels != C) src.resize(W, H, C);
  std::copy(img.data.begin(), img.data.end(), src.data.begin());
  static const float k1[3] = {1.f, 2.f, 1.f};
  tbb::parallel_for(0, H, [&](int y) {
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * size_t(W) + size_t(x);
      if (!valid[i]) continue;
      float acc[4] = {0, 0, 0, 0};
      float wsum = 0.f;
      for (int dy = -1; dy <= 1; ++dy) {
        int yy = y + dy;
        if (wrap_y)
          yy = (yy + H) % H;
        else if (yy < 0 || yy >= H)
          continue;
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx;
          if (xx < 0 || xx >= W) continue;
          const size_t j = size_t(yy) * size_t(W) + size_t(xx);
          if (!valid[j]) continue;
          const float w = k1[dx + 1] * k1[dy + 1];
          const float* p = src.at(xx, yy);
          for (int ch = 0; ch < C && ch < 4; ++ch) acc[ch] += w * p[ch];
          wsum += w;
        }
      }
      float* o = img.at(x, y);
      for (int ch = 0; ch < C && ch < 4; ++ch) o[ch] = acc[ch] / wsum;  // wsum >= 4 (centre)
    }
  });
}

void flc_shade_cartesian(const GBuffer& g, const std::vector<VplSoA>& groups, int n,
                         const VplShading& s, const Renderer* r, Image& out, Counters* c,
                         FlcShadeScratch* scratch) {
  n = std::max(1, n);
  if (out.width != g.width || out.height != g.height || out.channels != 3)
    out.resize(g.width, g.height, 3);
  ShadeTotals tot;
  tbb::parallel_for(tbb::blocked_range<int>(0, g.height, 4), [&](const tbb::blocked_range<int>& b) {
    ShadeTally t;
    for (int y = b.begin(); y < b.end(); ++y)
      for (int x = 0; x < g.width; ++x) {
        const size_t i = size_t(y) * size_t(g.width) + size_t(x);
        float* o = out.at(x, y);
        if (!g.hit(i)) {
          o[0] = o[1] = o[2] = 0.f;
          continue;
        }
        shade_sample(g, i, groups[size_t(x % n) + size_t(n) * size_t(y % n)], s, r, o, t);
      }
    tot.add(t);
  });
  if (n > 1) {
    std::vector<uint8_t> local;
    std::vector<uint8_t>& valid = scratch ? scratch->valid : local;
    valid.resize(g.size());
    for (size_t i = 0; i < g.size(); ++i) valid[i] = g.hit(i) ? 1 : 0;
    flc_gauss3(out, valid, false, scratch ? &scratch->filter_src : nullptr);
  }
  if (c) {
    c->add(Counter::shaded_samples, double(tot.shaded.load()));
    c->add(Counter::shaded_sample_vpls, double(tot.pairs.load()));
    if (s.visibility) c->add(Counter::vpl_shadow_rays, double(tot.rays.load()));
  }
}

void flc_shade_logpolar(const GBuffer& g, const glm::dvec2& gaze_px, double sigma,
                        const std::vector<VplSoA>& groups, int n, const VplShading& s,
                        const Renderer* r, Image& out, Counters* c, Image* lp_debug,
                        FlcShadeScratch* scratch) {
  n = std::max(1, n);
  sigma = std::max(1.0, sigma);
  const int W = g.width, H = g.height;
  if (out.width != W || out.height != H || out.channels != 3) out.resize(W, H, 3);
  const int w = std::max(1, int(std::ceil(W / sigma))), h = std::max(1, int(std::ceil(H / sigma)));
  // L = log of the largest distance from the gaze to a screen corner (KFR eq. 2.12 role).
  double maxd = 0.0;
  for (int k = 0; k < 4; ++k) {
    const double cx = (k & 1) ? W : 0, cy = (k & 2) ? H : 0;
    maxd = std::max(maxd, std::hypot(cx - gaze_px.x, cy - gaze_px.y));
  }
  const double L = std::log(std::max(maxd, 2.0));
  const double two_pi = 2.0 * kPi;
  Image lp_local;
  std::vector<uint8_t> valid_local;
  Image& lp = scratch ? scratch->lp : lp_local;
  std::vector<uint8_t>& valid = scratch ? scratch->lp_valid : valid_local;
  if (lp.width != w || lp.height != h || lp.channels != 3) lp.resize(w, h, 3);
  valid.assign(size_t(w) * size_t(h), 0);  // every texel's o[] is written below
  ShadeTotals tot;
  // Backward transform: each LP texel fetches the G-buffer sample it maps to, then is shaded.
  tbb::parallel_for(0, h, [&](int v) {
    ShadeTally t;
    for (int u = 0; u < w; ++u) {
      const double rho = std::exp((u + 0.5) / w * L);
      const double th = (v + 0.5) / h * two_pi;
      const double x = gaze_px.x + rho * std::cos(th), y = gaze_px.y + rho * std::sin(th);
      float* o = lp.at(u, v);
      o[0] = o[1] = o[2] = 0.f;
      if (!(x >= 0 && y >= 0 && x < W && y < H)) continue;
      const size_t i = size_t(int(y)) * size_t(W) + size_t(int(x));
      if (!g.hit(i)) continue;
      valid[size_t(v) * size_t(w) + size_t(u)] = 1;
      shade_sample(g, i, groups[size_t(u % n) + size_t(n) * size_t(v % n)], s, r, o, t);
    }
    tot.add(t);
  });
  if (n > 1) flc_gauss3(lp, valid, true, scratch ? &scratch->filter_src : nullptr);
  // Full VPL set for the rare pixels with no valid LP neighbour (weights / n^2 undo the groups).
  const float inv_g = 1.f / float(n * n);
  std::atomic<uint64_t> fallback{0};
  tbb::parallel_for(0, H, [&](int y) {
    uint64_t nf = 0;
    ShadeTally t;
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * size_t(W) + size_t(x);
      float* o = out.at(x, y);
      o[0] = o[1] = o[2] = 0.f;
      if (!g.hit(i)) continue;
      const double dx = x + 0.5 - gaze_px.x, dy = y + 0.5 - gaze_px.y;
      const double rho = std::max(1.0, std::hypot(dx, dy));
      double th = std::atan2(dy, dx);
      if (th < 0) th += two_pi;
      const double uf = std::log(rho) / L * w - 0.5, vf = th / two_pi * h - 0.5;
      const int u0 = int(std::floor(uf)), v0 = int(std::floor(vf));
      const double fu = uf - u0, fv = vf - v0;
      double acc[3] = {0, 0, 0}, ws = 0;
      for (int k = 0; k < 4; ++k) {
        int uu = u0 + (k & 1), vv = v0 + ((k >> 1) & 1);
        const double wk = ((k & 1) ? fu : 1 - fu) * ((k & 2) ? fv : 1 - fv);
        uu = std::clamp(uu, 0, w - 1);
        vv = ((vv % h) + h) % h;
        if (!valid[size_t(vv) * size_t(w) + size_t(uu)] || wk <= 0) continue;
        const float* p = lp.at(uu, vv);
        for (int ch = 0; ch < 3; ++ch) acc[ch] += wk * p[ch];
        ws += wk;
      }
      if (ws > 1e-9) {
        for (int ch = 0; ch < 3; ++ch) o[ch] = float(acc[ch] / ws);
        continue;
      }
      glm::vec3 Lo(0.f);
      for (const VplSoA& grp : groups) {
        Lo += shade_vpls(grp, g.position[i], g.normal[i], g.albedo[i], s, r, inv_g, &t.rays);
        t.pairs += grp.size();
      }
      ++nf;
      o[0] = Lo.x;
      o[1] = Lo.y;
      o[2] = Lo.z;
    }
    fallback += nf;
    tot.add(t);
  });
  if (c) {
    c->add(Counter::shaded_samples, double(tot.shaded.load() + fallback.load()));
    c->add(Counter::shaded_sample_vpls, double(tot.pairs.load()));
    c->add(Counter::lp_texels, double(size_t(w) * size_t(h)));
    c->add(Counter::lp_fallback_samples, double(fallback.load()));
    if (s.visibility) c->add(Counter::vpl_shadow_rays, double(tot.rays.load()));
  }
  if (lp_debug) *lp_debug = lp;  // a copy: lp may be the reused scratch
}

}  // namespace fovsim
