// TWFR push-pull hole filling (Franke et al. 2021 §5.1) and contrast confidence (§5.2).
#include "sim/foveation/twfr_pushpull.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>

#include "sim/core/math.h"
#include "sim/render/tonemap.h"

namespace fovsim {
namespace twfr {

float display_luminance(const float* rgb, float exposure) {
  // The renderer's display encoding (ACES filmic, Narkowicz 2015, then sRGB; tonemap.h).
  return display_encode<ToneCurve::Aces>(luma(rgb[0], rgb[1], rgb[2]) * exposure);
}

namespace {

// One push-pull "pull" step: texel (x, y) of level k+1 from its up-to-4 children at level k.
// Children with negative alpha are invalid. Returns the texel's validity.
template <class GetChild>
inline void reduce_texel(int x, int y, int cw, int ch, GetChild child, float* out_rgb, float& out_a,
                         float& out_lum, float exposure) {
  float sum[3] = {0, 0, 0};
  int cnt = 0;
  float lmin = 1e30f, lmax = -1e30f;
  for (int dy = 0; dy < 2; ++dy) {
    int cy = 2 * y + dy;
    if (cy >= ch) break;
    for (int dx = 0; dx < 2; ++dx) {
      int cx = 2 * x + dx;
      if (cx >= cw) break;
      const float* c;
      float lum;
      if (!child(cx, cy, c, lum)) continue;
      sum[0] += c[0];
      sum[1] += c[1];
      sum[2] += c[2];
      lmin = std::min(lmin, lum);
      lmax = std::max(lmax, lum);
      ++cnt;
    }
  }
  if (cnt == 0) {
    out_rgb[0] = out_rgb[1] = out_rgb[2] = 0.f;
    out_a = -1.f;
    out_lum = 0.f;
    return;
  }
  float inv = 1.f / float(cnt);
  out_rgb[0] = sum[0] * inv;
  out_rgb[1] = sum[1] * inv;
  out_rgb[2] = sum[2] * inv;
  out_a = 1.f - 0.5f * (lmax - lmin);  // §5.2 contrast confidence of this interpolation step
  out_lum = display_luminance(out_rgb, exposure);
}

// Pull (§5.1): the pyramid of valid pixels down to 1x1. Level k has ceil(W / 2^k) x
// ceil(H / 2^k) texels. Returns the number of levels.
int pull(const Image& color, const std::vector<uint8_t>& valid, float exposure, PushPull& pp) {
  const int W = color.width, H = color.height;
  int nl = 1;
  for (int w = W, h = H; w > 1 || h > 1; w = (w + 1) / 2, h = (h + 1) / 2) ++nl;
  nl = std::min(nl, 254);
  pp.levels.resize(size_t(nl));
  for (int k = 1; k < nl; ++k) {
    PushPullLevel& L = pp.levels[size_t(k)];
    const int cw = k == 1 ? W : pp.levels[size_t(k - 1)].width;
    const int ch = k == 1 ? H : pp.levels[size_t(k - 1)].height;
    L.width = (cw + 1) / 2;
    L.height = (ch + 1) / 2;
    L.rgb.resize(size_t(L.width) * size_t(L.height) * 3);
    L.alpha.resize(size_t(L.width) * size_t(L.height));
    L.lum.resize(L.alpha.size());
    const PushPullLevel* P = k == 1 ? nullptr : &pp.levels[size_t(k - 1)];
    const std::vector<float>* plum = k == 1 ? &pp.lum0 : &P->lum;
    tbb::parallel_for(0, L.height, [&](int y) {
      for (int x = 0; x < L.width; ++x) {
        size_t o = size_t(y) * size_t(L.width) + size_t(x);
        auto child = [&](int cx, int cy, const float*& c, float& l) {
          size_t ci = size_t(cy) * size_t(cw) + size_t(cx);
          if (P) {
            if (P->alpha[ci] < 0.f) return false;
            c = &P->rgb[ci * 3];
          } else {
            if (!valid[ci]) return false;
            c = &color.data[ci * 3];
          }
          l = (*plum)[ci];
          return true;
        };
        reduce_texel(x, y, cw, ch, child, &L.rgb[o * 3], L.alpha[o], L.lum[o], exposure);
      }
    });
  }
  return nl;
}

// Push (§5.1) of one hole (x, y): the finest level m whose covering texel is valid, the hole's
// colour `dst` interpolated bilinearly over the valid texels of that level (normalised weights)
// and its contrast confidence `cc`. Returns m, or nl when no level covers it.
inline int push_hole(const PushPull& pp, int nl, int x, int y, float* dst, float& cc) {
  int m = 1;
  for (; m < nl; ++m) {
    const PushPullLevel& L = pp.levels[size_t(m)];
    if (L.alpha[size_t(y >> m) * size_t(L.width) + size_t(x >> m)] >= 0.f) break;
  }
  if (m >= nl) return nl;
  const PushPullLevel& L = pp.levels[size_t(m)];
  const float s = 1.f / float(1 << m);
  const float u = (float(x) + 0.5f) * s - 0.5f, v = (float(y) + 0.5f) * s - 0.5f;
  const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
  const float fx = u - float(x0), fy = v - float(y0);
  float rgb[3] = {0, 0, 0}, al = 0.f, wsum = 0.f;
  for (int dy = 0; dy < 2; ++dy) {
    int ty = y0 + dy;
    if (ty < 0 || ty >= L.height) continue;
    float wy = dy ? fy : 1.f - fy;
    for (int dx = 0; dx < 2; ++dx) {
      int tx = x0 + dx;
      if (tx < 0 || tx >= L.width) continue;
      size_t ti = size_t(ty) * size_t(L.width) + size_t(tx);
      if (L.alpha[ti] < 0.f) continue;
      float w = wy * (dx ? fx : 1.f - fx);
      rgb[0] += w * L.rgb[ti * 3];
      rgb[1] += w * L.rgb[ti * 3 + 1];
      rgb[2] += w * L.rgb[ti * 3 + 2];
      al += w * L.alpha[ti];
      wsum += w;
    }
  }
  // wsum > 0: the covering texel is among the four and has weight > 1/4.
  float inv = 1.f / wsum;
  dst[0] = rgb[0] * inv;
  dst[1] = rgb[1] * inv;
  dst[2] = rgb[2] * inv;
  cc = clamp01(al * inv);
  return m;
}

}  // namespace

PushPullStats push_pull_fill(Image& color, const std::vector<uint8_t>& valid, const uint8_t* skip,
                             float exposure, std::vector<uint8_t>& level_out,
                             std::vector<float>& cc_out, PushPull& pp) {
  const int W = color.width, H = color.height;
  const size_t n = size_t(W) * size_t(H);
  level_out.resize(n);
  cc_out.resize(n);
  pp.lum0.resize(n);
  tbb::parallel_for(0, H, [&](int y) {
    for (int x = 0; x < W; ++x) {
      size_t i = size_t(y) * size_t(W) + size_t(x);
      pp.lum0[i] = valid[i] ? display_luminance(color.at(x, y), exposure) : 0.f;
    }
  });

  const int nl = pull(color, valid, exposure, pp);

  // Push: each hole takes the finest level m whose covering texel is valid (§5.1: mip level per
  // hole), interpolated bilinearly over the valid texels of that level (push_hole).
  struct Acc {
    std::vector<size_t> per_level;
    size_t uncovered = 0;
  };
  Acc init;
  init.per_level.assign(size_t(nl), 0);
  Acc acc = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, H), init,
      [&](const tbb::blocked_range<int>& rows, Acc a) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
          for (int x = 0; x < W; ++x) {
            size_t i = size_t(y) * size_t(W) + size_t(x);
            if (valid[i]) {
              level_out[i] = 0;
              cc_out[i] = 1.f;
              continue;
            }
            float* dst = color.at(x, y);
            if (skip && skip[i]) {
              level_out[i] = kUncovered;
              cc_out[i] = 0.f;
              continue;
            }
            float cc = 0.f;
            const int m = push_hole(pp, nl, x, y, dst, cc);
            if (m >= nl) {
              level_out[i] = kUncovered;
              cc_out[i] = 0.f;
              dst[0] = dst[1] = dst[2] = 0.f;
              ++a.uncovered;
              continue;
            }
            level_out[i] = uint8_t(m);
            cc_out[i] = cc;
            ++a.per_level[size_t(m)];
          }
        }
        return a;
      },
      [](Acc a, const Acc& b) {
        for (size_t k = 0; k < a.per_level.size(); ++k) a.per_level[k] += b.per_level[k];
        a.uncovered += b.uncovered;
        return a;
      });

  PushPullStats st;
  st.holes_per_level = acc.per_level;
  for (size_t k = 1; k < st.holes_per_level.size(); ++k) st.holes += st.holes_per_level[k];
  st.uncovered = acc.uncovered;
  return st;
}

}  // namespace twfr
}  // namespace fovsim
