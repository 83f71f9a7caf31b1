// Temporal anti-aliasing post pass (taa.h): reprojection of the history through the G-buffer's
// screen motion, neighbourhood clamp, exponential blend (Karis 2014), Halton(2, 3) jitter.
#include "sim/foveation/taa.h"

#include <algorithm>
#include <cmath>

#include "sim/core/error.h"
#include "sim/core/scratch_pool.h"
#include "sim/foveation/mapping.h"  // parallel_rows
#include "sim/foveation/method.h"

namespace fovsim {

Json TaaSettings::keys() const {
  if (!enabled) return Json{{"taa", false}};
  return Json{
      {"taa", true}, {"taa_alpha", alpha}, {"taa_clamp", clamp == TaaClamp::Eta ? "eta" : "box3"}};
}

namespace {
// Radical inverse of i in base b (the Halton sequence's coordinate).
double radical_inverse(int i, int b) {
  double f = 1.0, r = 0.0;
  while (i > 0) {
    f /= b;
    r += f * (i % b);
    i /= b;
  }
  return r;
}
}  // namespace

// The working buffers of one apply(): the output being formed and the eta clamp's row min/max
// and half sizes, lent for the call (sim/core/scratch_pool.h): as many exist as passes ran at
// once, not one per method.
struct TaaScratch {
  Image out, rowmin, rowmax;
  std::vector<uint8_t> half;  // per pixel the clamp window's half size (eta / 2)
};

namespace {
ScratchPool<TaaScratch>& taa_scratch() {
  static ScratchPool<TaaScratch> pool;
  return pool;
}
}  // namespace

glm::dvec2 taa_jitter(const TaaSettings& s, int frame) {
  if (!s.enabled || !s.jitter) return {0.0, 0.0};
  const int i = ((frame % 16) + 16) % 16 + 1;  // points 1..16 (point 0 is the origin)
  return {radical_inverse(i, 2) - 0.5, radical_inverse(i, 3) - 0.5};
}

int taa_eta_half(double r_over_eL, double render_scale) {
  // Yang et al. 2021 eq. 15: eta = 3 + 2 floor((r / e^L - 0.10) / 0.05), at least 1 (the pixel
  // itself) and at most 39 (r <= e^L), in display pixels; applied at render.scale times that
  // size: the half width of the simulated window is round((eta s - 1) / 2), at least 0.
  const double q = std::min(std::max(r_over_eL, 0.0), 1.0);
  const double eta = std::clamp(3.0 + 2.0 * std::floor((q - 0.10) / 0.05 + 1e-9), 1.0, 39.0);
  return std::max(0, int(std::lround((eta * render_scale - 1.0) / 2.0)));
}

// The eta clamp's per-pixel half sizes (eq. 15) and the row min/max of the current image over
// each pixel's own row window (the first of the separable passes).
void TaaPass::prepare_eta(const FrameContext& ctx, const Image& img, TaaScratch& sc) {
  std::vector<uint8_t>& half_ = sc.half;
  Image &rowmin_ = sc.rowmin, &rowmax_ = sc.rowmax;
  const int W = img.width, H = img.height;
  half_.resize(size_t(W) * size_t(H));
  double eL = 0;  // the largest gaze-to-corner distance (simulated pixels)
  for (double cx : {0.0, double(W)})
    for (double cy : {0.0, double(H)})
      eL = std::max(eL, std::hypot(cx - ctx.gaze_px.x, cy - ctx.gaze_px.y));
  eL = std::max(eL, 1.0);
  parallel_rows(H, [&](int y) {
    for (int x = 0; x < W; ++x) {
      const double r = std::hypot(x + 0.5 - ctx.gaze_px.x, y + 0.5 - ctx.gaze_px.y);
      half_[size_t(y) * size_t(W) + size_t(x)] = uint8_t(taa_eta_half(r / eL, ctx.render_scale));
    }
  });
  // Separable min/max: each pixel's row window with its own half size, then the column
  // window with the target pixel's (exact where eta is constant over the window; eta changes
  // in steps of 0.05 e^L of radius, so the window differs from a square only on those rings).
  rowmin_.resize(W, H, 3);
  rowmax_.resize(W, H, 3);
  parallel_rows(H, [&](int y) {
    const float* row = img.row(y);
    float* mn = rowmin_.row(y);
    float* mx = rowmax_.row(y);
    for (int x = 0; x < W; ++x) {
      const int h = half_[size_t(y) * size_t(W) + size_t(x)];
      float lo[3] = {row[3 * x], row[3 * x + 1], row[3 * x + 2]};
      float hi[3] = {lo[0], lo[1], lo[2]};
      for (int k = std::max(0, x - h); k <= std::min(W - 1, x + h); ++k)
        for (int ch = 0; ch < 3; ++ch) {
          lo[ch] = std::min(lo[ch], row[3 * k + ch]);
          hi[ch] = std::max(hi[ch], row[3 * k + ch]);
        }
      for (int ch = 0; ch < 3; ++ch) {
        mn[3 * x + ch] = lo[ch];
        mx[3 * x + ch] = hi[ch];
      }
    }
  });
}

void TaaPass::apply(const TaaSettings& s, const FrameContext& ctx, Image& img, Counters& c) {
  const int W = img.width, H = img.height;
  if (!has_history_ || history_.width != W || history_.height != H || !ctx.prev_camera) {
    history_ = img;  // the first frame: nothing to blend (the output is the current image)
    has_history_ = true;
    c.set(Counter::taa_pixels, 0.0);
    return;
  }
  const GBuffer& g = *ctx.gbuffer;
  // The engine adds kMotion for a method with TAA (cell.cpp); a caller that renders frames
  // itself asks for it too (taa_channels).
  FOVSIM_CHECK(g.width == W && g.height == H && g.has(kMotion),
               "TAA needs the frame's G-buffer with screen motion at the image's size");
  const Camera& cam = *ctx.camera;
  const Camera& prev = *ctx.prev_camera;
  const float a = float(s.alpha);
  // The clamp window's half size per pixel: 1 (3x3, Karis 2014) or eq. 15's eta / 2.
  const bool eta = s.clamp == TaaClamp::Eta;
  const ScratchPool<TaaScratch>::Lease lease = taa_scratch().take();
  TaaScratch& sc = *lease;
  if (eta) prepare_eta(ctx, img, sc);
  const std::vector<uint8_t>& half_ = sc.half;
  const Image &rowmin_ = sc.rowmin, &rowmax_ = sc.rowmax;
  Image& next_ = sc.out;
  next_.resize(W, H, 3);
  std::vector<size_t> blended(size_t(H), 0);
  parallel_rows(H, [&](int y) {
    size_t n = 0;
    float* o = next_.row(y);
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * size_t(W) + size_t(x);
      const float* q = img.at(x, y);
      // Where the pixel was on the previous frame: its G-buffer motion on a hit; on a miss (sky,
      // at infinity) the same world direction through the previous camera.
      glm::dvec2 pp;
      bool ok = true;
      if (g.hit(i)) {
        pp = glm::dvec2(x + 0.5 - double(g.motion[i].x), y + 0.5 - double(g.motion[i].y));
      } else {
        ok = prev.project_head(prev.to_head_dir(cam.dir_world(x + 0.5, y + 0.5)), pp);
      }
      if (!ok || !std::isfinite(pp.x) || !std::isfinite(pp.y) || !prev.inside(pp)) {
        std::copy_n(q, 3, o + 3 * x);  // disoccluded from outside the screen: no history
        continue;
      }
      // Bilinear history fetch (pixel centres at i + 0.5, clamped at the borders).
      const double u = pp.x - 0.5, v = pp.y - 0.5;
      const int x0 = std::clamp(int(std::floor(u)), 0, W - 1);
      const int y0 = std::clamp(int(std::floor(v)), 0, H - 1);
      const int x1 = std::min(x0 + 1, W - 1), y1 = std::min(y0 + 1, H - 1);
      const float fx = float(std::clamp(u - std::floor(u), 0.0, 1.0));
      const float fy = float(std::clamp(v - std::floor(v), 0.0, 1.0));
      const float *h00 = history_.at(x0, y0), *h10 = history_.at(x1, y0),
                  *h01 = history_.at(x0, y1), *h11 = history_.at(x1, y1);
      float lo[3], hi[3];
      if (eta) {
        const int h = half_[i];
        for (int ch = 0; ch < 3; ++ch) {
          lo[ch] = rowmin_.at(x, y)[ch];
          hi[ch] = rowmax_.at(x, y)[ch];
        }
        for (int k = std::max(0, y - h); k <= std::min(H - 1, y + h); ++k)
          for (int ch = 0; ch < 3; ++ch) {
            lo[ch] = std::min(lo[ch], rowmin_.at(x, k)[ch]);
            hi[ch] = std::max(hi[ch], rowmax_.at(x, k)[ch]);
          }
      } else {
        for (int ch = 0; ch < 3; ++ch) lo[ch] = hi[ch] = q[ch];
        for (int ny = std::max(0, y - 1); ny <= std::min(H - 1, y + 1); ++ny)
          for (int nx = std::max(0, x - 1); nx <= std::min(W - 1, x + 1); ++nx) {
            const float* p = img.at(nx, ny);
            for (int ch = 0; ch < 3; ++ch) {
              lo[ch] = std::min(lo[ch], p[ch]);
              hi[ch] = std::max(hi[ch], p[ch]);
            }
          }
      }
      for (int ch = 0; ch < 3; ++ch) {
        const float hist = (1 - fy) * ((1 - fx) * h00[ch] + fx * h10[ch]) +
                           fy * ((1 - fx) * h01[ch] + fx * h11[ch]);
        o[3 * x + ch] = a * q[ch] + (1 - a) * std::clamp(hist, lo[ch], hi[ch]);
      }
      ++n;
    }
    blended[size_t(y)] = n;
  });
  size_t total = 0;
  for (size_t n : blended) total += n;
  std::swap(history_, next_);  // the output is the next frame's history (the pool keeps the old)
  std::copy(history_.data.begin(), history_.data.end(), img.data.begin());
  c.set(Counter::taa_pixels, double(total));
}

size_t TaaPass::bytes(int width, int height, const TaaSettings& s) {
  if (!s.enabled) return 0;
  const size_t px = size_t(std::max(width, 0)) * size_t(std::max(height, 0));
  return px * 3 * sizeof(float);  // the history
}

size_t TaaPass::scratch_bytes(int width, int height, const TaaSettings& s) {
  if (!s.enabled) return 0;
  const size_t px = size_t(std::max(width, 0)) * size_t(std::max(height, 0));
  size_t b = px * 3 * sizeof(float);                                   // the output being formed
  if (s.clamp == TaaClamp::Eta) b += 2 * px * 3 * sizeof(float) + px;  // row min/max, half sizes
  return b;
}

}  // namespace fovsim
