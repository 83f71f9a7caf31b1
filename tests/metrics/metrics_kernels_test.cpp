// Pins the optimised metric kernels (SSIM's prepared reference and ring-buffered passes, FLIP's
// preparation) to straightforward implementations kept here: full-size planes, one loop per
// step, the same arithmetic in the same order. Equality is bitwise (EXPECT_EQ on doubles),
// at one and several threads.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "metrics_test_util.h"
#include "sim/core/error.h"
#include "sim/core/math.h"
#include "sim/metrics/metrics.h"

using namespace fovsim;

namespace {

// SSIM as docs/metrics.md states it, in the summation order fovsim has always used: the
// 11-tap Gaussian (sigma 1.5, normalised in tap order) applied horizontally then vertically to
// full-size planes of x, y, x^2, y^2, xy (luma as double), each 1-D pass summed as
// g[5] v[5] + sum_{k=0..4} g[k] (v[k] + v[10-k]); the mean over the valid region summed per row
// in x order, then over rows.
double reference_ssim(const Image& a, const Image& b) {
  const int W = a.width, H = a.height, R = 5, T = 11;
  double g[T], gs = 0;
  for (int k = 0; k < T; ++k) {
    const double x = k - R;
    g[k] = std::exp(-0.5 / (1.5 * 1.5) * x * x);
    gs += g[k];
  }
  for (double& v : g) v /= gs;
  auto lum = [](const Image& im, int x, int y) -> double {
    const float* p = im.at(x, y);
    return im.channels == 1 ? double(p[0]) : double(luma(p[0], p[1], p[2]));
  };
  std::vector<double> plane[5];
  for (auto& p : plane) p.resize(size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double la = lum(a, x, y), lb = lum(b, x, y);
      const size_t i = size_t(y) * W + x;
      plane[0][i] = la;
      plane[1][i] = lb;
      plane[2][i] = la * la;
      plane[3][i] = lb * lb;
      plane[4][i] = la * lb;
    }
  std::vector<double> h[5], v[5];
  for (int c = 0; c < 5; ++c) {
    h[c].assign(size_t(W) * H, 0.0);
    v[c].assign(size_t(W) * H, 0.0);
    for (int y = 0; y < H; ++y)
      for (int x = R; x < W - R; ++x) {
        const double* s = &plane[c][size_t(y) * W + x - R];
        double acc = g[R] * s[R];
        for (int k = 0; k < R; ++k) acc += g[k] * (s[k] + s[2 * R - k]);
        h[c][size_t(y) * W + x] = acc;
      }
    for (int y = R; y < H - R; ++y)
      for (int x = R; x < W - R; ++x) {
        auto at = [&](int yy) { return h[c][size_t(yy) * W + x]; };
        double acc = g[R] * at(y);
        for (int k = 0; k < R; ++k) acc += g[k] * (at(y - R + k) + at(y + R - k));
        v[c][size_t(y) * W + x] = acc;
      }
  }
  const double C1 = 0.01 * 0.01, C2 = 0.03 * 0.03;
  double total = 0;
  for (int y = R; y < H - R; ++y) {
    double s = 0;
    for (int x = R; x < W - R; ++x) {
      const size_t i = size_t(y) * W + x;
      const double ux = v[0][i], uy = v[1][i];
      const double vx = v[2][i] - ux * ux, vy = v[3][i] - uy * uy, vxy = v[4][i] - ux * uy;
      s += ((2 * ux * uy + C1) * (2 * vxy + C2)) / ((ux * ux + uy * uy + C1) * (vx + vy + C2));
    }
    total += s;
  }
  return total / (double(W - 2 * R) * double(H - 2 * R));
}

// FLIP preparation (FLIP.md §4.1-5.3) per pixel on full planes, in the arithmetic order of
// fovsim's implementation: sRGB -> linear through flip_detail's table, YCxCz; separable
// clamp-to-edge passes, each tap sum accumulated from 0 in tap order (horizontal on
// scale v + offset, then vertical); filtered YCxCz -> XYZ -> RGB clamped -> XYZ -> Lab (cube
// root above (6/29)^3) -> Hunt; edge/point magnitudes.
FlipPrepared reference_prepare(const Image& img, double ppd) {
  const flip_detail::Kernels k = flip_detail::kernels(ppd);
  const int W = img.width, H = img.height, C = img.channels;
  const size_t N = img.pixels();
  const double M[3][3] = {
      {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
      {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
      {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};
  const double Mi[3][3] = {{3.241003275, -1.537398934, -0.498615861},
                           {-0.969224334, 1.875930071, 0.041554224},
                           {0.055639423, -0.204011202, 1.057148933}};
  const double Xn = 0.950428545, Yn = 1.0, Zn = 1.088900371;
  const double iXn = 1.052156925, iYn = 1.0, iZn = 0.918357670;
  std::vector<double> ycc[3];
  for (auto& p : ycc) p.resize(N);
  for (size_t i = 0; i < N; ++i) {
    const float* px = &img.data[i * C];
    const double r = px[0], g = C >= 3 ? px[1] : px[0], b = C >= 3 ? px[2] : px[0];
    const double R = flip_detail::srgb_to_linear_table(r), G = flip_detail::srgb_to_linear_table(g),
                 B = flip_detail::srgb_to_linear_table(b);
    const double X = M[0][0] * R + M[0][1] * G + M[0][2] * B;
    const double Y = M[1][0] * R + M[1][1] * G + M[1][2] * B;
    const double Z = M[2][0] * R + M[2][1] * G + M[2][2] * B;
    const double y = Y * iYn;
    ycc[0][i] = 116.0 * y - 16.0;
    ycc[1][i] = 500.0 * (X * iXn - y);
    ycc[2][i] = 200.0 * (y - Z * iZn);
  }
  auto cl = [](int v, int n) { return std::min(std::max(v, 0), n - 1); };
  auto filter = [&](const std::vector<double>& in, const std::vector<double>& kx,
                    const std::vector<double>& ky, int r, double scale, double offset) {
    std::vector<double> h(N), v(N);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        double acc = 0;
        for (int i = 0; i <= 2 * r; ++i)
          acc += kx[i] * (scale * in[size_t(y) * W + cl(x + i - r, W)] + offset);
        h[size_t(y) * W + x] = acc;
      }
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        double acc = 0;
        for (int j = 0; j <= 2 * r; ++j) acc += ky[j] * h[size_t(cl(y + j - r, H)) * W + x];
        v[size_t(y) * W + x] = acc;
      }
    return v;
  };
  const auto fy = filter(ycc[0], k.y, k.y, k.r_s, 1.0, 0.0);
  const auto fcx = filter(ycc[1], k.cx, k.cx, k.r_s, 1.0, 0.0);
  const auto fcz1 = filter(ycc[2], k.cz1, k.cz1, k.r_s, 1.0, 0.0);
  const auto fcz2 = filter(ycc[2], k.cz2, k.cz2, k.r_s, 1.0, 0.0);
  const double s = 1.0 / 116.0, o = 16.0 / 116.0;
  const auto ex = filter(ycc[0], k.d, k.g, k.r_f, s, o), ey = filter(ycc[0], k.g, k.d, k.r_f, s, o);
  const auto px = filter(ycc[0], k.s, k.g, k.r_f, s, o), py = filter(ycc[0], k.g, k.s, k.r_f, s, o);
  auto f = [](double t) {
    const double d = 6.0 / 29.0;
    return t > d * d * d ? flip_detail::lab_cube_root(t) : t / (3.0 * d * d) + 4.0 / 29.0;
  };
  FlipPrepared out;
  out.width = W;
  out.height = H;
  out.ppd = ppd;
  for (auto* p : {&out.L, &out.A, &out.B, &out.edge, &out.point}) p->resize(N);
  for (size_t i = 0; i < N; ++i) {
    const double t = (fy[i] + 16.0) / 116.0, cz = fcz1[i] + fcz2[i];
    const double X = Xn * (t + fcx[i] / 500.0), Y = Yn * t, Z = Zn * (t - cz / 200.0);
    double rgb[3];
    for (int a = 0; a < 3; ++a)
      rgb[a] = std::min(std::max(Mi[a][0] * X + Mi[a][1] * Y + Mi[a][2] * Z, 0.0), 1.0);
    const double X2 = M[0][0] * rgb[0] + M[0][1] * rgb[1] + M[0][2] * rgb[2];
    const double Y2 = M[1][0] * rgb[0] + M[1][1] * rgb[1] + M[1][2] * rgb[2];
    const double Z2 = M[2][0] * rgb[0] + M[2][1] * rgb[1] + M[2][2] * rgb[2];
    const double fx = f(X2 * iXn), fyv = f(Y2 * iYn), fz = f(Z2 * iZn);
    const double L = 116.0 * fyv - 16.0;
    out.L[i] = L;
    out.A[i] = 0.01 * L * 500.0 * (fx - fyv);
    out.B[i] = 0.01 * L * 200.0 * (fyv - fz);
    out.edge[i] = std::sqrt(ex[i] * ex[i] + ey[i] * ey[i]);
    out.point[i] = std::sqrt(px[i] * px[i] + py[i] * py[i]);
  }
  return out;
}

// FLIP.md §4.7-4.8, §5.4, §6 per pixel, as flip() evaluates it (log/exp form of the powers),
// and the mean summed per row, then over rows.
double reference_flip_map(const FlipPrepared& r, const FlipPrepared& t, std::vector<float>& map) {
  const double cmax = flip_detail::c_max(), knee = 0.4 * cmax, inv_sqrt2 = 1.0 / std::sqrt(2.0);
  const double ln_knee_d = std::log(knee) / 0.7, ln_pt_knee = std::log(0.95 / knee);
  map.assign(size_t(r.width) * r.height, 0.f);
  double total = 0;
  for (int y = 0; y < r.height; ++y) {
    double s = 0;
    for (int x = 0; x < r.width; ++x) {
      const size_t i = size_t(y) * r.width + x;
      const double da = r.A[i] - t.A[i], db = r.B[i] - t.B[i];
      const double d = std::fabs(r.L[i] - t.L[i]) + std::sqrt(da * da + db * db);
      const double df = std::sqrt(inv_sqrt2 * std::max(std::fabs(r.edge[i] - t.edge[i]),
                                                       std::fabs(r.point[i] - t.point[i])));
      double v;
      if (d == 0.0) {
        v = df == 1.0 ? 1.0 : 0.0;
      } else if (std::log(d) < ln_knee_d) {
        v = std::exp((1.0 - df) * (0.7 * std::log(d) + ln_pt_knee));
      } else {
        const double e = std::exp(0.7 * std::log(d));
        const double dc = 0.95 + (e - knee) / (cmax - knee) * (1.0 - 0.95);
        v = df == 0.0 ? dc : std::pow(dc, 1.0 - df);
      }
      map[i] = float(v);
      s += v;
    }
    total += s;
  }
  return total / double(map.size());
}

size_t mismatches(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return std::max(a.size(), b.size());
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += !(a[i] == b[i]);  // bitwise for non-NaN values
  return n;
}

}  // namespace

TEST(MetricsKernels, FlipPrepareAndMapMatchStraightforwardEvaluationBitForBit) {
  // Odd sizes; values across the sRGB knee and both Lab branches (dark pixels: t <= (6/29)^3);
  // ppd 3 is the quickstart's (3-tap filters), 20 and 45 have wide filters and clamped edges.
  const int W = 53, H = 41;
  Image a = testutil::pattern(W, H, 3, 91, 0.3), b = testutil::pattern(W, H, 3, 92, 0.5);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if ((x + y) % 9 == 0)
        for (int c = 0; c < 3; ++c) b.at(x, y)[c] = c == 1 ? 0.002f : 0.03f;
  for (int c = 0; c < 3; ++c) a.at(4, 5)[c] = 1.f;
  // Out-of-range and edge values (the sRGB table clamps them): below 0, 0, above 1, just below 1.
  const float odd[4][3] = {
      {-0.2f, 0.f, 1.5f}, {0.f, 0.f, 0.f}, {2.f, 1.f, 0.99999f}, {1e-9f, 0.5f, -0.f}};
  for (int j = 0; j < 4; ++j)
    for (int c = 0; c < 3; ++c) {
      b.at(7 + j, 3)[c] = odd[j][c];
      a.at(20, 10 + j)[c] = odd[3 - j][c];
    }
  Image grey = testutil::pattern(W, H, 1, 93, 0.4);
  for (double ppd : {3.0, 20.0, 45.0}) {
    const FlipPrepared ra = reference_prepare(a, ppd), rb = reference_prepare(b, ppd);
    std::vector<float> want_map;
    const double want = reference_flip_map(ra, rb, want_map);
    for (int threads : {1, 3}) {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(threads));
      FlipPrepared pa, pb;
      FlipWorkspace ws;
      flip_prepare(a, ppd, pa, &ws);
      flip_prepare(b, ppd, pb, &ws);
      for (auto [got, ref] : {std::pair{&pa, &ra}, std::pair{&pb, &rb}}) {
        EXPECT_EQ(mismatches(got->L, ref->L), 0u) << "L ppd " << ppd << " tbb " << threads;
        EXPECT_EQ(mismatches(got->A, ref->A), 0u) << "A ppd " << ppd;
        EXPECT_EQ(mismatches(got->B, ref->B), 0u) << "B ppd " << ppd;
        EXPECT_EQ(mismatches(got->edge, ref->edge), 0u) << "edge ppd " << ppd;
        EXPECT_EQ(mismatches(got->point, ref->point), 0u) << "point ppd " << ppd;
      }
      Image map;
      EXPECT_EQ(flip(pa, pb, &map), want) << "ppd " << ppd << " tbb " << threads;
      EXPECT_EQ(map.data, want_map) << "ppd " << ppd;
      EXPECT_EQ(flip(a, b, ppd), want) << "ppd " << ppd;
      FlipPrepared pg;
      flip_prepare(grey, ppd, pg);
      const FlipPrepared rg = reference_prepare(grey, ppd);
      EXPECT_EQ(mismatches(pg.L, rg.L) + mismatches(pg.A, rg.A) + mismatches(pg.edge, rg.edge), 0u)
          << "grey ppd " << ppd;
    }
  }
}

TEST(MetricsKernels, SsimMatchesStraightforwardEvaluationBitForBit) {
  struct Case {
    int w, h, c;
    double noise;
  };
  // Smallest size, odd sizes, more rows than one TBB block (64), grey and RGBA.
  for (Case k : {Case{11, 11, 3, 0.2}, Case{37, 23, 3, 0.5}, Case{257, 203, 3, 0.3},
                 Case{61, 150, 1, 0.1}, Case{40, 90, 4, 0.4}}) {
    Image a = testutil::pattern(k.w, k.h, k.c, 71),
          b = testutil::pattern(k.w, k.h, k.c, 72, k.noise);
    const double want = reference_ssim(a, b);
    SsimPrepared pb;
    ssim_prepare(b, pb);
    for (int threads : {1, 3}) {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(threads));
      EXPECT_EQ(ssim(a, b), want) << k.w << "x" << k.h << "x" << k.c << " tbb " << threads;
      EXPECT_EQ(ssim(a, pb), want) << k.w << "x" << k.h << "x" << k.c << " tbb " << threads;
    }
    // The prepared image serves several test images.
    Image a2 = testutil::pattern(k.w, k.h, k.c, 73, 0.6);
    EXPECT_EQ(ssim(a2, pb), reference_ssim(a2, b));
  }
}

TEST(MetricsKernels, SsimPreparedChecksTheImage) {
  SsimPrepared p;
  ssim_prepare(testutil::pattern(20, 30, 3, 1), p);
  EXPECT_THROW(ssim(testutil::pattern(20, 31, 3, 2), p), Error);
  EXPECT_THROW(ssim(testutil::pattern(20, 30, 1, 2), p), Error);
  EXPECT_THROW(ssim_prepare(testutil::pattern(10, 30, 3, 1), p), Error);
  EXPECT_THROW(ssim_prepare(Image(20, 30, 2), p), Error);
}

// compute_metrics reports SSIM 1 for identical images without filtering them (the `full`
// method); the full computation gives exactly 1 too, for any images in [0,1].
TEST(MetricsKernels, SsimOfIdenticalImagesIsExactlyOne) {
  std::vector<Image> imgs = {testutil::pattern(33, 27, 3, 5, 0.9), testutil::pattern(64, 80, 1, 6),
                             Image(15, 12, 3, 0.f), Image(15, 12, 3, 1.f)};
  Image spikes(30, 20, 3, 0.f);  // isolated extreme and tiny values
  for (size_t i = 0; i < spikes.data.size(); i += 7) spikes.data[i] = (i % 2) ? 1.f : 1e-30f;
  imgs.push_back(spikes);
  for (const Image& im : imgs) {
    EXPECT_EQ(reference_ssim(im, im), 1.0);
    EXPECT_EQ(ssim(im, im), 1.0);
    Image copy = im;
    const Camera cam = testutil::camera(im.width, im.height, 90, 80);
    const std::vector<float> ecc(im.pixels(), 10.f);
    MetricsConfig cfg;
    cfg.set("flip", false);
    cfg.set("fpsnr", false);
    cfg.set("regions", false);
    cfg.set("temporal", false);
    EXPECT_EQ(compute_metrics(cfg, copy, im, cam, ecc, nullptr).get("ssim"), 1.0);
  }
}

TEST(MetricsKernels, ComputeMetricsReusesThePreparedReferenceOnlyWhileItIsUnchanged) {
  const int W = 45, H = 38;
  const Camera cam = testutil::camera(W, H, 90, 80);
  const std::vector<float> ecc = eccentricity_map(cam, glm::dvec3(0.1, 0, -1));
  Image ref = testutil::pattern(W, H, 3, 81), t1 = testutil::pattern(W, H, 3, 82, 0.4),
        t2 = testutil::pattern(W, H, 3, 83, 0.4);
  MetricsConfig cfg;
  cfg.set("temporal", false);
  MetricsScratch sc;
  auto same = [&](const Image& t, const Image& r) {
    const MetricValues with = compute_metrics(cfg, t, r, cam, ecc, nullptr, &sc);
    const MetricValues without = compute_metrics(cfg, t, r, cam, ecc, nullptr);
    ASSERT_EQ(with.items().size(), without.items().size());
    for (size_t i = 0; i < with.items().size(); ++i)
      EXPECT_EQ(with.items()[i].second, without.items()[i].second) << with.items()[i].first;
    EXPECT_EQ(with.get("ssim"), reference_ssim(t, r));
  };
  same(t1, ref);
  same(t2, ref);
  Image ref2 = ref;
  ref2.data[100] = 0.f;  // one value changed: both preparations are redone
  same(t1, ref2);
  same(t1, ref);
}
