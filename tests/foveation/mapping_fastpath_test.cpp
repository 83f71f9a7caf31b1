// The optimised KFR passes (lp_gather tables, lp_reconstruct with hoisted terms and ipow,
// run-wise variable_gaussian) against straightforward per-pixel references built from
// LogPolarMap::inverse/forward and the plain filter loop. The filter must match bit for bit;
// the maps to a few ulp (sqrt for hypot, x^4 by squaring); lp_reconstruct bit for bit against
// its loop before the log/bilinear split.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "sim/foveation/mapping.h"
#include "sim/foveation/simd_kernels.h"

using namespace fovsim;

namespace {

// Per-pixel reference of variable_gaussian (the loop it replaced).
double variable_gaussian_ref(Image& img, const std::vector<uint8_t>& eta, int max_eta) {
  const int w = img.width, h = img.height;
  max_eta = std::max(1, max_eta | 1);
  std::vector<std::vector<float>> k(size_t(max_eta) + 1);
  for (int n = 3; n <= max_eta; n += 2) {
    const double sg = 0.3 * ((n - 1) * 0.5 - 1.0) + 0.8;
    std::vector<float> v(static_cast<size_t>(n));
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      double d = i - (n - 1) * 0.5;
      v[size_t(i)] = float(std::exp(-d * d / (2 * sg * sg)));
      sum += v[size_t(i)];
    }
    for (auto& e : v) e = float(e / sum);
    k[size_t(n)] = std::move(v);
  }
  Image tmp(w, h, 3);
  double taps = 0;
  auto size_at = [&](int x, int y) {
    int n = std::min<int>(eta[size_t(y) * size_t(w) + size_t(x)], max_eta);
    return (n >= 3) ? (n | 1) : 1;
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int n = size_at(x, y);
      float* o = tmp.at(x, y);
      if (n < 3) {
        std::memcpy(o, img.at(x, y), 3 * sizeof(float));
        continue;
      }
      float acc[3] = {0, 0, 0};
      for (int i = 0; i < n; ++i) {
        const float* s = img.at(std::clamp(x + i - n / 2, 0, w - 1), y);
        for (int c = 0; c < 3; ++c) acc[c] += k[size_t(n)][size_t(i)] * s[c];
      }
      std::memcpy(o, acc, sizeof acc);
      taps += n;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int n = size_at(x, y);
      if (n < 3) continue;
      float acc[3] = {0, 0, 0};
      for (int i = 0; i < n; ++i) {
        const float* s = tmp.at(x, std::clamp(y + i - n / 2, 0, h - 1));
        for (int c = 0; c < 3; ++c) acc[c] += k[size_t(n)][size_t(i)] * s[c];
      }
      std::memcpy(img.at(x, y), acc, sizeof acc);
      taps += n;
    }
  return taps;
}

Image noise_image(int w, int h, uint32_t seed) {
  Image img(w, h, 3);
  uint32_t s = seed;
  for (float& v : img.data) {
    s = s * 1664525u + 1013904223u;
    v = float(s >> 8) / float(1u << 24);
  }
  return img;
}

}  // namespace

TEST(MappingFastPath, VariableGaussianBitIdenticalToPerPixelLoop) {
  // Every SIMD path this CPU has (simd_kernels.h) must give the same bits.
  for (SimdPath path : simd_paths_available()) {
    set_simd_path(path);
    SCOPED_TRACE(simd_path_name(path));
    // Sizes smaller and larger than the kernels, eta in runs (incl. untouched 1 and even values)
    // and scattered single pixels; a reused scratch of the wrong size must be reshaped.
    Image scratch(3, 3, 3);
    for (auto wh : {std::pair<int, int>{97, 61}, {5, 40}, {40, 3}, {1, 1}}) {
      const int w = wh.first, h = wh.second;
      Image a = noise_image(w, h, 7u + uint32_t(w)), b = a;
      std::vector<uint8_t> eta(a.pixels());
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const int r = int(std::hypot(x - w * 0.3, y - h * 0.6));
          int e = std::min(1 + 2 * (r / 3), 41);
          if ((x * 7 + y * 13) % 29 == 0) e = (x + y) % 40;  // isolated odd/even sizes
          eta[size_t(y) * size_t(w) + size_t(x)] = uint8_t(e);
        }
      const double ta = variable_gaussian(a, eta, 39, &scratch);
      const double tb = variable_gaussian_ref(b, eta, 39);
      EXPECT_EQ(ta, tb) << w << "x" << h;
      ASSERT_EQ(a.data.size(), b.data.size());
      size_t diff = 0;
      for (size_t i = 0; i < a.data.size(); ++i) diff += (a.data[i] != b.data[i]);
      EXPECT_EQ(diff, 0u) << w << "x" << h;
    }
  }
  set_simd_path(simd_paths_available().back());
}

TEST(MappingFastPath, IpowMatchesPow) {
  for (int n = 1; n <= 16; ++n)
    for (double x : {0.0, 1e-3, 0.1, 0.37, 0.5, 0.999, 1.0})
      EXPECT_NEAR(ipow(x, n), std::pow(x, double(n)), 4e-16 * std::max(1.0, std::pow(x, double(n))))
          << n;
}

TEST(MappingFastPath, LpGatherAndReconstructMatchTheMaps) {
  // Every SIMD path this CPU has (simd_kernels.h) must give the same bits.
  for (SimdPath path : simd_paths_available()) {
    set_simd_path(path);
    SCOPED_TRACE(simd_path_name(path));
    const int W = 83, H = 67;
    for (double alpha : {4.0, 2.5, 1.0}) {
      for (glm::dvec2 g : {glm::dvec2(41.5, 33.5), glm::dvec2(10.2, 60.7), glm::dvec2(-20, 90)}) {
        KernelFn k;
        k.alpha = alpha;
        const int w = reduced_size(W, 1.8), h = reduced_size(H, 1.8);
        const LogPolarMap m = LogPolarMap::make(W, H, w, h, g, k);
        // Gather: the LP-buffer is the source index of each slot.
        GBuffer src;
        src.resize(W, H, kDepth);
        std::vector<uint32_t> lp;
        std::vector<uint8_t> used;
        const size_t n = lp_gather(src, m, lp, used);
        ASSERT_EQ(lp.size(), size_t(w) * size_t(h));
        size_t n_ref = 0;
        for (int iv = 0; iv < h; ++iv)
          for (int iu = 0; iu < w; ++iu) {
            const size_t i = size_t(iv) * size_t(w) + size_t(iu);
            const glm::dvec2 p = m.inverse(iu + 0.5, iv + 0.5);
            const bool in = p.x >= 0 && p.y >= 0 && p.x < W && p.y < H;
            ASSERT_EQ(used[i], in ? 1 : 0);
            n_ref += in;
            EXPECT_EQ(lp[i],
                      in ? uint32_t(size_t(p.y) * size_t(W) + size_t(p.x)) : GBufferRef::kNone);
          }
        EXPECT_EQ(n, n_ref);
        // Reconstruct: against forward() + bilinear() per pixel.
        const Image lpimg = noise_image(w, h, 3u);
        Image out(1, 1, 3);
        lp_reconstruct_exact(lpimg, m, W, H, out);
        ASSERT_EQ(out.width, W);
        ASSERT_EQ(out.height, H);
        double worst = 0;
        for (int y = 0; y < H; ++y)
          for (int x = 0; x < W; ++x) {
            const glm::dvec2 uv = m.forward(x + 0.5, y + 0.5);
            const glm::vec3 c = bilinear(lpimg, uv.x, uv.y, true);
            for (int ch = 0; ch < 3; ++ch)
              worst = std::max(worst, double(std::abs(out.at(x, y)[ch] - c[ch])));
          }
        EXPECT_LT(worst, 2e-6) << "alpha " << alpha;
      }
    }
  }
  set_simd_path(simd_paths_available().back());
}

// lp_reconstruct_exact's loop before its split (log inside the bilinear loop, std::floor),
// kept as the bit-exact reference of the split loop with the truncation floor.
void lp_reconstruct_ref(const Image& lp, const LogPolarMap& map, int W, int H, Image& out) {
  out = Image(W, H, 3);
  const double inv_L = 1.0 / map.L, w = map.w, h = map.h, gx = map.gx, gy = map.gy;
  const double v_per_rad = h / (2.0 * kPi), half_inv_L = 0.5 * inv_L;
  const int lw1 = lp.width - 1, lh = lp.height;
  std::vector<double> vrow(static_cast<size_t>(W));
  for (int y = 0; y < H; ++y) {
    const double dy = (y + 0.5) - gy, dy2 = dy * dy;
    polar_angle_row(vrow.data(), W, gx, dy, v_per_rad);
    for (int x = 0; x < W; ++x) {
      const double dx = (x + 0.5) - gx, r2 = dx * dx + dy2;
      const double t = r2 > 1.0 ? std::min(std::log(r2) * half_inv_L, 1.0) : 0.0;
      const double u = (map.k.alpha == 4.0 ? (t * t) * (t * t) : map.k.K(t)) * w;
      double v = vrow[size_t(x)];
      if (!(v < h)) v = 0;
      const double fx = u - 0.5, fy = v - 0.5;
      const double x0f = std::floor(fx), y0f = std::floor(fy);
      const float tx = float(fx - x0f), ty = float(fy - y0f);
      const int xi = int(x0f), yi = int(y0f);
      const int x0 = xi < 0 ? 0 : xi, x1 = xi + 1 > lw1 ? lw1 : xi + 1;
      const int y0 = yi < 0 ? lh - 1 : yi, y1 = yi + 1 >= lh ? yi + 1 - lh : yi + 1;
      const float sx = 1 - tx, sy = 1 - ty;
      for (int ch = 0; ch < 3; ++ch) {
        const float top = lp.at(x0, y0)[ch] * sx + lp.at(x1, y0)[ch] * tx;
        const float bot = lp.at(x0, y1)[ch] * sx + lp.at(x1, y1)[ch] * tx;
        out.at(x, y)[ch] = top * sy + bot * ty;
      }
    }
  }
}

TEST(MappingFastPath, LpReconstructBitIdenticalToUnsplitLoop) {
  const int W = 97, H = 71;
  for (double alpha : {4.0, 2.5})
    for (glm::dvec2 g : {glm::dvec2(48.5, 35.5), glm::dvec2(3.2, 69.9), glm::dvec2(-15, 20)}) {
      KernelFn k;
      k.alpha = alpha;
      const LogPolarMap m =
          LogPolarMap::make(W, H, reduced_size(W, 1.8), reduced_size(H, 1.8), g, k);
      const Image lp = noise_image(int(m.w), int(m.h), 11u);
      Image got, want;
      lp_reconstruct_exact(lp, m, W, H, got);
      lp_reconstruct_ref(lp, m, W, H, want);
      ASSERT_EQ(got.data.size(), want.data.size());
      EXPECT_EQ(std::memcmp(got.data.data(), want.data.data(), got.data.size() * sizeof(float)), 0)
          << "alpha " << alpha << " gaze " << g.x << "," << g.y;
    }
}

TEST(MappingFastPath, AngleMatchesAtan2) {
  double worst = 0;
  uint32_t s = 12345u;
  auto rnd = [&] {
    s = s * 1664525u + 1013904223u;
    return double(s >> 8) / double(1u << 24) * 2.0 - 1.0;
  };
  std::vector<std::pair<double, double>> pts = {{0, 1},     {0, -1},  {1, 0},       {-1, 0},
                                                {1, 1},     {-1, -1}, {1e-300, -1}, {-1e-300, -1},
                                                {3, 1e-17}, {0, 0}};
  for (int i = 0; i < 200000; ++i) {
    const double sc = std::pow(10.0, 4 * rnd());
    pts.push_back({rnd() * sc, rnd()});
  }
  for (auto [dy, dx] : pts) {
    double ref = std::atan2(dy, dx);
    if (ref < 0) ref += 2.0 * kPi;
    const double a = angle_0_2pi(dy, dx);
    EXPECT_GE(a, 0.0);
    EXPECT_LT(a, 2.0 * kPi);
    worst = std::max(worst, std::abs(a - ref));
  }
  EXPECT_LT(worst, 3e-15);  // a few ulp of 2 pi
  EXPECT_EQ(angle_0_2pi(0.0, 0.0), 0.0);
}

TEST(MappingFastPath, AngleRowBitIdenticalToScalar) {
  // Every SIMD path this CPU has (simd_kernels.h) must give the same bits.
  for (SimdPath path : simd_paths_available()) {
    set_simd_path(path);
    SCOPED_TRACE(simd_path_name(path));
    const double vpr = 889.0 / (2.0 * kPi);
    for (double gx : {0.0, 17.5, 40.3, -3.0, 1e6})
      for (double dy : {0.0, 1e-12, -0.5, 3.25, -1000.0}) {
        std::vector<double> v(97);
        polar_angle_row(v.data(), int(v.size()), gx, dy, vpr);
        for (size_t i = 0; i < v.size(); ++i) {
          const double ref = angle_0_2pi(dy, (double(i) + 0.5) - gx) * vpr;
          EXPECT_EQ(v[i], ref) << "gx " << gx << " dy " << dy << " i " << i;
        }
      }
  }
  set_simd_path(simd_paths_available().back());
}

// The float inverse map (lp_reconstruct: simd_lp_uv_row + simd_bilinear_wrap_row) gives the
// same bits on every SIMD path, its LP coordinates stay within 2e-3 LP pixels of the double
// map (LogPolarMap::forward), and its pixels within the bound stated in mapping.h of
// lp_reconstruct_exact: (|du| + |dv|) x the largest neighbour difference (<= 1 for this noise)
// + 1e-6.
TEST(MappingFastPath, LpReconstructFloatWithinBound) {
  struct Case {
    int W, H;
    double alpha;
    glm::dvec2 g;
  };
  const std::vector<Case> cases = {{1440, 1600, 4.0, {700.3, 812.9}},  // HTC Vive Pro Eye size
                                   {97, 71, 4.0, {48.5, 35.5}},
                                   {97, 71, 2.0, {3.2, 69.9}},
                                   {97, 71, 2.5, {-15, 20}},
                                   {64, 48, 4.0, {32.0, 24.0}}};  // gaze on a pixel corner
  std::vector<Image> first;
  for (SimdPath path : simd_paths_available()) {
    set_simd_path(path);
    SCOPED_TRACE(simd_path_name(path));
    for (size_t ci = 0; ci < cases.size(); ++ci) {
      const Case& c = cases[ci];
      KernelFn k;
      k.alpha = c.alpha;
      const LogPolarMap m =
          LogPolarMap::make(c.W, c.H, reduced_size(c.W, 1.8), reduced_size(c.H, 1.8), c.g, k);
      // LP coordinates against the double map.
      std::vector<float> dxs(static_cast<size_t>(c.W)), u(dxs.size()), v(dxs.size());
      for (int x = 0; x < c.W; ++x) dxs[size_t(x)] = float((x + 0.5) - m.gx);
      double du = 0, dv = 0;
      for (int y = 0; y < c.H; y += (c.H > 200 ? 7 : 1)) {
        simd_lp_uv_row(u.data(), v.data(), dxs.data(), c.W, float((y + 0.5) - m.gy),
                       float(0.5 / m.L), float(m.w), float(m.h / (2.0 * kPi)), float(m.h),
                       c.alpha == 4.0);
        for (int x = 0; x < c.W; ++x) {
          const glm::dvec2 e = m.forward(x + 0.5, y + 0.5);
          ASSERT_GE(v[size_t(x)], 0.f);
          ASSERT_LT(v[size_t(x)], float(m.h));
          if (c.alpha == 4.0) du = std::max(du, std::abs(double(u[size_t(x)]) - e.x));
          const double d = std::abs(double(v[size_t(x)]) - e.y);
          dv = std::max(dv, std::min(d, m.h - d));  // the angle axis wraps
        }
      }
      EXPECT_LT(du, 2e-3) << ci;
      EXPECT_LT(dv, 2e-3) << ci;
      const Image lp = noise_image(int(m.w), int(m.h), 5u + uint32_t(ci));
      Image got(1, 1, 3), want;
      lp_reconstruct(lp, m, c.W, c.H, got);
      lp_reconstruct_exact(lp, m, c.W, c.H, want);
      ASSERT_EQ(got.data.size(), want.data.size());
      double worst = 0;
      for (size_t i = 0; i < got.data.size(); ++i)
        worst = std::max(worst, double(std::abs(got.data[i] - want.data[i])));
      EXPECT_LT(worst, 4e-3 + 1e-6) << ci;  // (2e-3 + 2e-3) x neighbour difference <= 1
      std::printf("[ %s ] %dx%d alpha %g: max |du| %.2e, |dv| %.2e LP px; max |pixel diff| %.2e\n",
                  simd_path_name(path), c.W, c.H, c.alpha, du, dv, worst);
      if (path == simd_paths_available().front()) {
        first.push_back(got);
      } else {
        EXPECT_EQ(
            std::memcmp(got.data.data(), first[ci].data.data(), got.data.size() * sizeof(float)), 0)
            << "case " << ci << " differs between SIMD paths";
      }
    }
  }
  set_simd_path(simd_paths_available().back());
}

// push_pull_fill (the linear baseline's hole fill) before it ran rows in parallel with a
// per-thread pyramid: the serial loop, kept as the bit-exact reference.
double push_pull_fill_ref(Image& img, const std::vector<uint8_t>& valid) {
  struct Level {
    int w, h;
    std::vector<glm::vec4> p;
  };
  std::vector<Level> lv;
  lv.push_back({img.width, img.height, std::vector<glm::vec4>(img.pixels())});
  for (size_t i = 0; i < img.pixels(); ++i) {
    const float* s = &img.data[i * size_t(img.channels)];
    lv[0].p[i] = valid[i] ? glm::vec4(s[0], s[1], s[2], 1.f) : glm::vec4(0.f);
  }
  double taps = 0;
  while (lv.back().w > 1 || lv.back().h > 1) {
    const Level& f = lv.back();
    Level c{(f.w + 1) / 2, (f.h + 1) / 2, {}};
    c.p.assign(size_t(c.w) * size_t(c.h), glm::vec4(0.f));
    for (int y = 0; y < c.h; ++y)
      for (int x = 0; x < c.w; ++x) {
        glm::vec4 acc(0.f);
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            int fx = std::min(2 * x + dx, f.w - 1), fy = std::min(2 * y + dy, f.h - 1);
            acc += f.p[size_t(fy) * size_t(f.w) + size_t(fx)];
          }
        if (acc.a > 1.f) acc /= acc.a;
        c.p[size_t(y) * size_t(c.w) + size_t(x)] = acc;
      }
    taps += 4.0 * double(c.w) * double(c.h);
    lv.push_back(std::move(c));
  }
  for (size_t l = lv.size() - 1; l-- > 0;) {
    Level& f = lv[l];
    const Level& c = lv[l + 1];
    for (int y = 0; y < f.h; ++y)
      for (int x = 0; x < f.w; ++x) {
        glm::vec4& q = f.p[size_t(y) * size_t(f.w) + size_t(x)];
        if (q.a >= 1.f) continue;
        double px = (x + 0.5) * 0.5 - 0.5, py = (y + 0.5) * 0.5 - 0.5;
        int x0 = int(std::floor(px)), y0 = int(std::floor(py));
        float tx = float(px - x0), ty = float(py - y0);
        glm::vec4 acc(0.f);
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            int cx = std::clamp(x0 + dx, 0, c.w - 1), cy = std::clamp(y0 + dy, 0, c.h - 1);
            float wgt = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty);
            const glm::vec4& s = c.p[size_t(cy) * size_t(c.w) + size_t(cx)];
            if (s.a > 0.f) acc += wgt * glm::vec4(glm::vec3(s) / s.a, 1.f);
          }
        taps += 4;
        if (acc.a > 0.f) {
          glm::vec3 col = glm::vec3(acc) / acc.a;
          q = glm::vec4(glm::vec3(q) + (1.f - q.a) * col, 1.f);
        }
      }
  }
  for (size_t i = 0; i < img.pixels(); ++i) {
    if (valid[i]) continue;
    float* d = &img.data[i * size_t(img.channels)];
    const glm::vec4& q = lv[0].p[i];
    glm::vec3 col = q.a > 0.f ? glm::vec3(q) / q.a : glm::vec3(0.f);
    d[0] = col.x;
    d[1] = col.y;
    d[2] = col.z;
  }
  return taps;
}

TEST(MappingFastPath, PushPullFillParallelBitIdenticalToSerialLoop) {
  // Sizes odd/even/degenerate; a smaller call after a larger one reuses the per-thread pyramid.
  for (int threads : {1, 2})
    for (auto wh : {std::pair<int, int>{97, 61}, {1, 1}, {2, 7}, {64, 64}, {5, 3}}) {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(threads));
      const int w = wh.first, h = wh.second;
      Image a = noise_image(w, h, 17u + uint32_t(w)), b = a;
      std::vector<uint8_t> valid(a.pixels());
      uint32_t s = 99u + uint32_t(h);
      for (auto& v : valid) {
        s = s * 1664525u + 1013904223u;
        v = (s >> 29) == 0 ? 1 : 0;  // ~1/8 valid: many holes on every level
      }
      const double ta = push_pull_fill(a, valid), tb = push_pull_fill_ref(b, valid);
      EXPECT_EQ(ta, tb) << w << "x" << h << " threads " << threads;
      EXPECT_EQ(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)), 0)
          << w << "x" << h << " threads " << threads;
    }
}
