// FLC contribution estimation and stochastic culling (Yang et al. 2021 §5, eqs. 10-14).
#include "sim/foveation/flc_contribution.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>

#include "sim/core/rng.h"
#include "sim/render/renderer.h"

namespace fovsim {

namespace {

inline float hash_unit(uint64_t key) {
  return float(splitmix64(key) >> 40) * (1.0f / 16777216.0f);
}

void basis(const glm::vec3& n, glm::vec3& t1, glm::vec3& t2) {
  float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  t1 = glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  t2 = glm::vec3(b, sign + n.y * n.y * a, -n.y);
}

}  // namespace

double blso_g(double dh, double xi, double k) {
  // eq. 12
  if (dh <= -xi) return 1.0;  // in front of the lit surface: free space
  if (dh < xi) return 0.0;    // on a surface: occluder
  return 1.0 - std::exp(-k * std::sqrt(dh));
}

double blso_T(const RSM& rsm, const glm::vec3& o, const glm::vec3& dir, float max_dist,
              const BlsoParams& p, float scene_scale, uint64_t key) {
  const int n = std::max(1, p.samples);
  const float tmin = float(2.0 * p.xi) * scene_scale;
  const float tmax = std::min(float(p.radius) * scene_scale, max_dist);
  if (!(tmax > tmin)) return 1.0;  // no local space between the end points
  glm::vec3 t1, t2;
  basis(dir, t1, t2);
  const float cos_c = float(std::cos(deg2rad(p.cone_deg)));
  const float inv_scale = 1.f / std::max(scene_scale, 1e-20f);
  double acc = 0.0;
  for (int i = 0; i < n; ++i) {
    const uint64_t ki = key * 0x9e3779b97f4a7c15ull + uint64_t(i) * 3u;
    // Uniform direction in the cone around d, uniform distance in [tmin, tmax].
    const float u1 = hash_unit(ki), u2 = hash_unit(ki + 1), u3 = hash_unit(ki + 2);
    const float ct = 1.f - u1 * (1.f - cos_c);
    const float st = std::sqrt(std::max(0.f, 1.f - ct * ct));
    const float ph = float(2.0 * kPi) * u2;
    const glm::vec3 w = dir * ct + t1 * (st * std::cos(ph)) + t2 * (st * std::sin(ph));
    const glm::vec3 s = o + w * (tmin + u3 * (tmax - tmin));
    glm::vec2 tex;
    float ds;
    double g = 1.0;  // outside the map: nothing known about occluders
    if (rsm.project(s, tex, ds)) {
      const float dm = rsm.depth_at(tex);
      if (dm < 3.0e38f) g = blso_g(double(ds - dm) * inv_scale, p.xi, p.k);
    }
    acc += g;
  }
  return acc / double(n);  // eq. 13
}

std::vector<double> flc_contributions(const std::vector<VPL>& vpls, const std::vector<RSM>& rsms,
                                      const std::vector<FlcShadingPoint>& pts,
                                      const ContributionSettings& s, const Renderer* r,
                                      Counters* c) {
  std::vector<double> C(vpls.size(), 0.0);
  std::vector<int> rsm_of_light;
  for (size_t k = 0; k < rsms.size(); ++k) {
    if (rsms[k].light < 0) continue;
    if (size_t(rsms[k].light) >= rsm_of_light.size())
      rsm_of_light.resize(size_t(rsms[k].light) + 1, -1);
    rsm_of_light[size_t(rsms[k].light)] = int(k);
  }
  const size_t ns = pts.size();
  std::atomic<uint64_t> lookups{0}, rays{0};
  const FlcVisibility vis =
      (s.visibility == FlcVisibility::Exact && !r) ? FlcVisibility::None : s.visibility;
  const float lam = float(s.blso.lambda);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, vpls.size(), 16), [&](const tbb::blocked_range<size_t>& b) {
        uint64_t nl = 0, nr = 0;
        for (size_t v = b.begin(); v < b.end(); ++v) {
          const VPL& l = vpls[v];
          const float Iv = luma(l.flux.x, l.flux.y, l.flux.z);
          const RSM* rsm = (l.light >= 0 && size_t(l.light) < rsm_of_light.size() &&
                            rsm_of_light[size_t(l.light)] >= 0)
                               ? &rsms[size_t(rsm_of_light[size_t(l.light)])]
                               : nullptr;
          double acc = 0.0;
          for (size_t i = 0; i < ns; ++i) {
            const FlcShadingPoint& sp = pts[i];
            if (!(sp.weight > 0.f)) continue;
            glm::vec3 d = sp.p - l.position;
            const float d2 = glm::dot(d, d);
            const float dl = std::sqrt(d2);
            if (!(dl > 0.f)) continue;
            d /= dl;
            const float cl = glm::dot(l.normal, d), cp = -glm::dot(sp.n, d);
            if (cl <= 0.f || cp <= 0.f) continue;
            float V = 1.f;
            if (vis == FlcVisibility::Blso && rsm) {
              // eq. 11: V = mix(T_lv(d), T_p(-d), lambda)
              const uint64_t key =
                  s.seed ^ (uint64_t(v) * 0x100000001b3ull + uint64_t(i) * 0x9e3779b97f4a7c15ull);
              const double Tl = blso_T(*rsm, l.position, d, dl, s.blso, s.scene_scale, key);
              const double Tp = blso_T(*rsm, sp.p, -d, dl, s.blso, s.scene_scale, ~key);
              V = float(Tl) * (1.f - lam) + float(Tp) * lam;
              nl += 2u * uint64_t(std::max(1, s.blso.samples));
            } else if (vis == FlcVisibility::Exact) {
              ++nr;
              V = r->occluded(l.position + l.normal * s.ray_offset, sp.p + sp.n * s.ray_offset)
                      ? 0.f
                      : 1.f;
            }
            acc += double(Iv * V * cp * cl * sp.weight / (d2 + s.eps2));  // eq. 14 summand
          }
          C[v] = ns ? acc / double(ns) : 0.0;
        }
        lookups += nl;
        rays += nr;
      });
  if (c) {
    c->add(Counter::contribution_evals, double(vpls.size()) * double(ns));
    c->add(Counter::blso_lookups, double(lookups.load()));
    c->add(Counter::visibility_rays, double(rays.load()));
  }
  return C;
}

CullResult flc_cull(const std::vector<double>& C, int budget, double floor_mix, uint64_t seed) {
  CullResult res;
  const size_t n = C.size();
  if (budget <= 0 || n == 0) return res;
  if (size_t(budget) >= n) {
    res.kept.resize(n);
    std::iota(res.kept.begin(), res.kept.end(), 0u);
    res.weight.assign(n, 1.f);
    return res;
  }
  double sum = 0.0;
  for (double v : C) sum += (std::isfinite(v) && v > 0.0) ? v : 0.0;
  const double mix = sum > 0.0 ? std::clamp(floor_mix, 0.0, 1.0) : 1.0;
  std::vector<double> x(n);
  for (size_t i = 0; i < n; ++i) {
    const double v = (std::isfinite(C[i]) && C[i] > 0.0) ? C[i] : 0.0;
    x[i] = (1.0 - mix) * (sum > 0.0 ? v / sum : 0.0) + mix / double(n);
  }
  // Water filling: the largest items saturate at q = 1, the rest share the remaining budget.
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(),
            [&](uint32_t a, uint32_t b) { return x[a] > x[b] || (x[a] == x[b] && a < b); });
  std::vector<double> tail(n + 1, 0.0);
  for (size_t k = n; k-- > 0;) tail[k] = tail[k + 1] + x[order[k]];
  const double B = double(budget);
  double cscale = 0.0;
  size_t sat = 0;
  for (; sat < n; ++sat) {
    if (!(tail[sat] > 0.0)) break;
    cscale = (B - double(sat)) / tail[sat];
    if (x[order[sat]] * cscale <= 1.0) break;
  }
  std::vector<double> q(n, 0.0);
  for (size_t k = 0; k < n; ++k) q[order[k]] = k < sat ? 1.0 : std::min(1.0, x[order[k]] * cscale);
  // Systematic sampling: points u + j, j = 0..B-1, over the cumulative sum of q.
  Rng rng(seed, 0x63756c6cull);  // "cull"
  const double u = rng.uniform();
  double S = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double lo = S;
    S += q[i];
    if (std::floor(S - u) > std::floor(lo - u) && q[i] > 0.0) {
      res.kept.push_back(uint32_t(i));
      res.weight.push_back(float(1.0 / q[i]));
    }
  }
  return res;
}

}  // namespace fovsim
