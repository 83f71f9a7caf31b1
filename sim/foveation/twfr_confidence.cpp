// TWFR confidence function, redraw map and OR-mipmap (Franke et al. 2021 §5.2, §6.1, §7).
#include "sim/foveation/twfr_confidence.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>

namespace fovsim {
namespace twfr {

ConfidenceStats compute_redraw_map(const ConfidenceInputs& in, const ConfidenceParams& p, int W,
                                   int H, std::vector<float>& confidence,
                                   std::vector<uint8_t>& redraw) {
  const size_t n = size_t(W) * size_t(H);
  confidence.resize(n);
  redraw.resize(n);
  // A^m and D^t tables: no pow per pixel.
  float a_pow[256];
  a_pow[0] = 1.f;
  for (int m = 1; m < 256; ++m) a_pow[m] = a_pow[m - 1] * p.A;
  if (p.level_offset != 0.f)  // display levels: A^max(0, m + offset) (ConfidenceParams)
    for (int m = 1; m < 256; ++m)
      a_pow[m] = std::pow(p.A, std::max(0.f, float(m) + p.level_offset));
  const float logD = p.D > 0.f ? std::log(p.D) : -1e30f;
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, H), ConfidenceStats{},
      [&](const tbb::blocked_range<int>& rows, ConfidenceStats s) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
          for (size_t i = size_t(y) * size_t(W), e = i + size_t(W); i < e; ++i) {
            uint8_t reason = 0;
            float c = 0.f;
            const uint8_t m = in.hole_level[i];
            if (in.fovea && in.fovea[i]) {
              reason |= kRedrawFovea;
              ++s.fovea;
            } else if (m == kUncovered) {
              reason |= kRedrawUncovered;
              ++s.uncovered;
            } else {
              c = eccentricity_confidence(in.eccentricity[i], p.phi_f, p.phi_0);  // c_e
              if (m > 0) {
                c *= in.contrast[i] * a_pow[m];  // c_c * c_s(m) (hole-filled, §5.2)
              } else if (in.dynamic && in.dynamic[i]) {
                // c_d(t) = D^t, t = frames since last redraw (§7).
                float t = in.age ? float(in.age[i]) : 0.f;
                c *= p.D >= 1.f ? 1.f : std::exp(logD * t);
                ++s.dynamic;
              }
              if (c <= p.epsilon) {
                reason |= kRedrawConfidence;
                ++s.by_confidence;
              }
            }
            if (in.forced && in.forced[i]) {
              if (!reason) ++s.forced;
              reason |= kRedrawForced;
            }
            confidence[i] = c;
            redraw[i] = reason;
            if (reason) ++s.redrawn;
          }
        }
        return s;
      },
      [](ConfidenceStats a, const ConfidenceStats& b) {
        a.redrawn += b.redrawn;
        a.by_confidence += b.by_confidence;
        a.uncovered += b.uncovered;
        a.fovea += b.fovea;
        a.forced += b.forced;
        a.dynamic += b.dynamic;
        return a;
      });
}

void OrMip::build(const std::vector<uint8_t>& map, int W, int H) {
  int nl = 1;
  for (int w = W, h = H; w > 1 || h > 1; w = (w + 1) / 2, h = (h + 1) / 2) ++nl;
  w.resize(size_t(nl));
  h.resize(size_t(nl));
  level.resize(size_t(nl));
  w[0] = W;
  h[0] = H;
  level[0].resize(size_t(W) * size_t(H));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, level[0].size(), 1 << 14),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i) level[0][i] = map[i] != 0;
                    });
  for (int k = 1; k < nl; ++k) {
    const int cw = w[size_t(k - 1)], ch = h[size_t(k - 1)];
    w[size_t(k)] = (cw + 1) / 2;
    h[size_t(k)] = (ch + 1) / 2;
    level[size_t(k)].resize(size_t(w[size_t(k)]) * size_t(h[size_t(k)]));
    const std::vector<uint8_t>& c = level[size_t(k - 1)];
    std::vector<uint8_t>& o = level[size_t(k)];
    const int ow = w[size_t(k)];
    tbb::parallel_for(0, h[size_t(k)], [&](int y) {
      for (int x = 0; x < ow; ++x) {
        uint8_t v = 0;
        for (int dy = 0; dy < 2 && 2 * y + dy < ch; ++dy)
          for (int dx = 0; dx < 2 && 2 * x + dx < cw; ++dx)
            v |= c[size_t(2 * y + dy) * size_t(cw) + size_t(2 * x + dx)];
        o[size_t(y) * size_t(ow) + size_t(x)] = v;
      }
    });
  }
}

bool OrMip::any(int x0, int y0, int x1, int y1) const {
  if (level.empty()) return false;
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, w[0] - 1);
  y1 = std::min(y1, h[0] - 1);
  if (x0 > x1 || y0 > y1) return false;
  size_t k = 0;
  while (k + 1 < level.size() && (((x1 >> k) - (x0 >> k)) > 1 || ((y1 >> k) - (y0 >> k)) > 1)) ++k;
  const int tx0 = x0 >> k, tx1 = x1 >> k, ty0 = y0 >> k, ty1 = y1 >> k;
  const std::vector<uint8_t>& L = level[k];
  const size_t lw = size_t(w[k]);
  return L[size_t(ty0) * lw + size_t(tx0)] | L[size_t(ty0) * lw + size_t(tx1)] |
         L[size_t(ty1) * lw + size_t(tx0)] | L[size_t(ty1) * lw + size_t(tx1)];
}

}  // namespace twfr
}  // namespace fovsim
