// LDR-FLIP against the sanity values of ../shared/metrics/FLIP.md §10.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <string>

#include "metrics_test_util.h"
#include "sim/core/error.h"
#include "sim/metrics/flip.h"

using namespace fovsim;

namespace {

Image uniform(int w, int h, int r, int g, int b) {
  Image im(w, h, 3);
  for (size_t i = 0; i < im.pixels(); ++i) {
    im.data[3 * i] = float(r / 255.0);
    im.data[3 * i + 1] = float(g / 255.0);
    im.data[3 * i + 2] = float(b / 255.0);
  }
  return im;
}

void expect_taps(const std::vector<double>& got, const std::vector<double>& want, double rel) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i)
    EXPECT_NEAR(got[i], want[i], std::fabs(want[i]) * rel + 1e-12) << "tap " << i;
}

double sum(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s;
}

}  // namespace

TEST(MetricsFlip, Constants) {
  EXPECT_NEAR(flip_default_ppd(), 67.0206, 1e-4);
  EXPECT_NEAR(flip_detail::c_max(), 41.27610, 1e-5);
  auto k67 = flip_detail::kernels(flip_default_ppd());
  EXPECT_EQ(k67.r_s, 10);
  EXPECT_EQ(k67.r_f, 9);
  auto k20 = flip_detail::kernels(20.0);
  EXPECT_EQ(k20.r_s, 3);
  EXPECT_EQ(k20.r_f, 3);
  for (const auto* k : {&k67, &k20}) {
    EXPECT_NEAR(sum(k->y), 1.0, 1e-12);
    EXPECT_NEAR(sum(k->cx), 1.0, 1e-12);
    EXPECT_NEAR(sum(k->g), 1.0, 1e-12);
    EXPECT_NEAR(sum(k->cz1) * sum(k->cz1) + sum(k->cz2) * sum(k->cz2), 1.0,
                1e-12);  // 2-D C_z kernel sums to 1
    for (const auto* t : {&k->d, &k->s}) {
      double pos = 0, neg = 0;
      for (double v : *t) (v > 0 ? pos : neg) += v;
      EXPECT_NEAR(pos, 1.0, 1e-12);
      EXPECT_NEAR(neg, -1.0, 1e-12);
    }
  }
}

TEST(MetricsFlip, KernelTapsAtPpd20) {
  auto k = flip_detail::kernels(20.0);
  expect_taps(
      k.y,
      {2.99139e-21, 7.51011e-10, 5.194099e-3, 0.9896118, 5.194099e-3, 7.51011e-10, 2.99139e-21},
      1e-5);
  expect_taps(
      k.cx, {6.24020e-19, 8.02475e-9, 9.331925e-3, 0.9813361, 9.331925e-3, 8.02475e-9, 6.24020e-19},
      1e-5);
  expect_taps(k.cz1,
              {1.500864e-3, 0.03279538, 0.2086876, 0.3867153, 0.2086876, 0.03279538, 1.500864e-3},
              1e-5);
  expect_taps(k.cz2,
              {3.797762e-5, 5.280622e-3, 0.1019952, 0.2736598, 0.1019952, 5.280622e-3, 3.797762e-5},
              1e-5);
  expect_taps(k.g, {6.0340e-4, 0.02484983, 0.2312885, 0.4865165, 0.2312885, 0.02484983, 6.0340e-4},
              1e-4);
  expect_taps(k.d, {6.40103e-3, 0.1757424, 0.8178566, 0, -0.8178566, -0.1757424, -6.40103e-3},
              1e-5);
  expect_taps(k.s, {0.01536798, 0.2528983, 0.2317338, -1, 0.2317338, 0.2528983, 0.01536798}, 1e-5);
}

TEST(MetricsFlip, UniformImagesMatchSpecValues) {
  struct Case {
    int r0, g0, b0, r1, g1, b1;
    double want;
  };
  const Case cases[] = {{0, 0, 0, 255, 255, 255, 0.96738},
                        {0, 255, 0, 0, 0, 255, 1.0},
                        {255, 0, 0, 0, 255, 0, 0.98666},
                        {128, 128, 128, 160, 160, 160, 0.33302}};
  for (double ppd : {flip_default_ppd(), 20.0, 5.0}) {
    for (const Case& c : cases) {
      Image a = uniform(23, 17, c.r0, c.g0, c.b0), b = uniform(23, 17, c.r1, c.g1, c.b1);
      Image map;
      const double m = flip(a, b, ppd, &map);
      EXPECT_NEAR(m, c.want, 1e-4)
          << "ppd " << ppd << " case " << c.r0 << "," << c.g0 << "," << c.b0;
      ASSERT_EQ(map.width, 23);
      ASSERT_EQ(map.height, 17);
      ASSERT_EQ(map.channels, 1);
      for (float v : map.data) EXPECT_NEAR(v, c.want, 1e-4);
    }
  }
}

TEST(MetricsFlip, IdenticalIsZeroAndSwapIsSymmetric) {
  Image a = testutil::pattern(37, 29, 3, 11, 0.4), b = testutil::pattern(37, 29, 3, 12, 0.4);
  for (double ppd : {3.0, 20.0, 67.0}) {
    Image m0, m1, m2;
    EXPECT_EQ(flip(a, a, ppd, &m0), 0.0);
    for (float v : m0.data) EXPECT_EQ(v, 0.f);
    const double ab = flip(a, b, ppd, &m1), ba = flip(b, a, ppd, &m2);
    EXPECT_EQ(ab, ba);
    EXPECT_EQ(m1.data, m2.data);
    EXPECT_GT(ab, 0.0);
    for (float v : m1.data) {
      EXPECT_GE(v, 0.f);
      EXPECT_LE(v, 1.f);
    }
  }
}

TEST(MetricsFlip, ErrorGrowsAsPpdFalls) {
  // A fine texture vs its blurred-out mean: at high ppd the eye's CSF blurs the texture away.
  Image a = testutil::pattern(64, 48, 3, 3, 0.5), b = uniform(64, 48, 128, 128, 128);
  double prev = 2.0;
  for (double ppd : {4.0, 10.0, 20.0, 40.0, 80.0}) {
    const double m = flip(a, b, ppd);
    EXPECT_LT(m, prev) << "ppd " << ppd;
    prev = m;
  }
}

TEST(MetricsFlip, TransposedInputsGiveTransposedMap) {
  const int W = 97, H = 61;
  Image a(W, H, 3, 0.1f), b = a;
  for (int c = 0; c < 3; ++c) b.at(3, 2)[c] = 1.f;  // bright dot near a corner
  b.at(W - 2, H - 5)[1] = 0.8f;
  Image at(H, W, 3), bt(H, W, 3);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 3; ++c) {
        at.at(y, x)[c] = a.at(x, y)[c];
        bt.at(y, x)[c] = b.at(x, y)[c];
      }
  for (double ppd : {8.0, 30.0}) {
    Image m, mt;
    const double s = flip(a, b, ppd, &m), st = flip(at, bt, ppd, &mt);
    EXPECT_NEAR(s, st, 1e-9);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) EXPECT_NEAR(m.at(x, y)[0], mt.at(y, x)[0], 1e-6) << x << "," << y;
    EXPECT_GT(m.at(3, 2)[0], 0.5f);
    EXPECT_EQ(m.at(W / 2, H / 2)[0], 0.f);  // far from both dots
  }
}

TEST(MetricsFlip, GreyAndAlphaInputs) {
  Image rgb = testutil::pattern(20, 18, 3, 5, 0.3), rgb2 = testutil::pattern(20, 18, 3, 6, 0.3);
  Image rgba(20, 18, 4), rgba2(20, 18, 4);
  for (size_t i = 0; i < rgb.pixels(); ++i)
    for (int c = 0; c < 4; ++c) {
      rgba.data[4 * i + c] = c < 3 ? rgb.data[3 * i + c] : 0.25f;
      rgba2.data[4 * i + c] =
          c < 3 ? rgb2.data[3 * i + c] : 0.9f;  // alpha is dropped, not composited
    }
  EXPECT_EQ(flip(rgb, rgb2, 20.0), flip(rgba, rgba2, 20.0));
  Image g = testutil::pattern(20, 18, 1, 7), g2 = testutil::pattern(20, 18, 1, 8);
  Image g3(20, 18, 3), g23(20, 18, 3);
  for (size_t i = 0; i < g.pixels(); ++i)
    for (int c = 0; c < 3; ++c) {
      g3.data[3 * i + c] = g.data[i];
      g23.data[3 * i + c] = g2.data[i];
    }
  EXPECT_EQ(flip(g, g2, 20.0), flip(g3, g23, 20.0));
}

TEST(MetricsFlip, SameResultAtAnyThreadCount) {
  Image a = testutil::pattern(120, 90, 3, 21, 0.4), b = testutil::pattern(120, 90, 3, 22, 0.4);
  Image m1, m4;
  double s1 = 0, s4 = 0;
  tbb::task_arena one(1), four(4);
  one.execute([&] { s1 = flip(a, b, 15.0, &m1); });
  four.execute([&] { s4 = flip(a, b, 15.0, &m4); });
  EXPECT_EQ(s1, s4);
  EXPECT_EQ(m1.data, m4.data);
}

TEST(MetricsFlip, ErrorsNameTheProblem) {
  Image a(10, 10, 3), b(11, 10, 3);
  try {
    flip(a, b, 20.0);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "metrics.flip: images differ in size: 10x10x3 vs 11x10x3");
  }
  EXPECT_THROW(flip(a, a, 0.0), Error);
  EXPECT_THROW(flip(a, a, std::nan("")), Error);
  EXPECT_THROW(flip(Image(), Image(), 20.0), Error);
}

TEST(MetricsFlip, ColormapIsMagmaLike) {
  Image m(3, 1, 1);
  m.data = {0.f, 0.5f, 1.f};
  Image c = flip_colormap(m);
  ASSERT_EQ(c.channels, 3);
  EXPECT_LT(c.data[0] + c.data[1] + c.data[2], 0.05f);  // black at 0
  EXPECT_GT(c.data[3], c.data[5] - 0.1f);               // magenta-red at 0.5
  EXPECT_GT(c.data[6], 0.95f);                          // pale yellow at 1
  EXPECT_GT(c.data[7], 0.9f);
  EXPECT_LT(c.data[8], 0.85f);
  for (float v : c.data) {
    EXPECT_GE(v, 0.f);
    EXPECT_LE(v, 1.f);
  }
}

// An independent, direct evaluation of FLIP.md in its 2-D form (§4.4 2-D kernel over the
// square, §5.2 2-D edge/point kernels, clamp-to-edge, exact pow everywhere), written from the
// spec without the implementation's separable passes, table or log/exp rewrite.
namespace {

struct Lab3 {
  double v[3];
};

std::vector<double> direct_flip(const Image& r, const Image& t, double ppd) {
  const int W = r.width, H = r.height;
  const double M[3][3] = {
      {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
      {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
      {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};
  const double Mi[3][3] = {{3.241003275, -1.537398934, -0.498615861},
                           {-0.969224334, 1.875930071, 0.041554224},
                           {0.055639423, -0.204011202, 1.057148933}};
  const double wp[3] = {0.950428545, 1.0, 1.088900371};
  const double pi = 3.14159265358979323846;
  auto ycc = [&](const Image& im) {
    std::vector<Lab3> out(im.pixels());
    for (size_t i = 0; i < im.pixels(); ++i) {
      double lin[3], xyz[3] = {0, 0, 0};
      for (int c = 0; c < 3; ++c) {
        const double v = im.data[3 * i + c];
        lin[c] = std::min(
            1.0, std::max(0.0, v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4)));
      }
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) xyz[a] += M[a][c] * lin[c];
      out[i] = {{116 * xyz[1] / wp[1] - 16, 500 * (xyz[0] / wp[0] - xyz[1] / wp[1]),
                 200 * (xyz[1] / wp[1] - xyz[2] / wp[2])}};
    }
    return out;
  };
  const int rs = int(std::ceil(3 * std::sqrt(0.04 / (2 * pi * pi)) * ppd));
  const double A1[3] = {1, 1, 34.1}, B1[3] = {0.0047, 0.0053, 0.04}, A2[3] = {0, 0, 13.5},
               B2[3] = {1e-5, 1e-5, 0.025};
  std::vector<double> K[3];
  for (int k = 0; k < 3; ++k) {
    double sum = 0;
    for (int j = -rs; j <= rs; ++j)
      for (int i = -rs; i <= rs; ++i) {
        const double rho2 = (i * i + j * j) / (ppd * ppd);
        const double v = A1[k] * std::sqrt(pi / B1[k]) * std::exp(-pi * pi * rho2 / B1[k]) +
                         A2[k] * std::sqrt(pi / B2[k]) * std::exp(-pi * pi * rho2 / B2[k]);
        K[k].push_back(v);
        sum += v;
      }
    for (double& v : K[k]) v /= sum;
  }
  const double sigma = 0.5 * 0.082 * ppd;
  const int rf = int(std::ceil(3 * sigma));
  std::vector<double> Ed, Pt;  // 2-D kernels along x (the y direction uses the transpose)
  double ep = 0, en = 0, pp = 0, pn = 0;
  for (int j = -rf; j <= rf; ++j)
    for (int i = -rf; i <= rf; ++i) {
      const double g = std::exp(-(i * i + j * j) / (2 * sigma * sigma));
      const double e = -i * g, p = (i * i / (sigma * sigma) - 1) * g;
      Ed.push_back(e);
      Pt.push_back(p);
      (e > 0 ? ep : en) += std::fabs(e);
      (p > 0 ? pp : pn) += std::fabs(p);
    }
  for (double& v : Ed) v /= v > 0 ? ep : en;
  for (double& v : Pt) v /= v > 0 ? pp : pn;
  auto at = [&](int x, int y) {
    return size_t(std::min(std::max(y, 0), H - 1)) * W + size_t(std::min(std::max(x, 0), W - 1));
  };
  auto lab = [&](const std::vector<Lab3>& y, int x0, int y0) {
    double f[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int j = -rs; j <= rs; ++j)
        for (int i = -rs; i <= rs; ++i)
          f[k] += K[k][size_t((j + rs) * (2 * rs + 1) + i + rs)] * y[at(x0 + i, y0 + j)].v[k];
    const double tt = (f[0] + 16) / 116,
                 xyz[3] = {wp[0] * (tt + f[1] / 500), wp[1] * tt, wp[2] * (tt - f[2] / 200)};
    double rgb[3], x2[3] = {0, 0, 0};
    for (int a = 0; a < 3; ++a) {
      rgb[a] = 0;
      for (int c = 0; c < 3; ++c) rgb[a] += Mi[a][c] * xyz[c];
      rgb[a] = std::min(1.0, std::max(0.0, rgb[a]));
    }
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) x2[a] += M[a][c] * rgb[c];
    auto fl = [](double q) {
      const double d = 6.0 / 29;
      return q > d * d * d ? std::pow(q, 1.0 / 3) : q / (3 * d * d) + 4.0 / 29;
    };
    const double L = 116 * fl(x2[1] / wp[1]) - 16,
                 a = 500 * (fl(x2[0] / wp[0]) - fl(x2[1] / wp[1])),
                 b = 200 * (fl(x2[1] / wp[1]) - fl(x2[2] / wp[2]));
    return Lab3{{L, 0.01 * L * a, 0.01 * L * b}};
  };
  auto feat = [&](const std::vector<Lab3>& y, int x0, int y0, double& edge, double& point) {
    double ex = 0, ey = 0, px = 0, py = 0;
    for (int j = -rf; j <= rf; ++j)
      for (int i = -rf; i <= rf; ++i) {
        const double a = (y[at(x0 + i, y0 + j)].v[0] + 16) / 116;
        ex += Ed[size_t((j + rf) * (2 * rf + 1) + i + rf)] * a;
        px += Pt[size_t((j + rf) * (2 * rf + 1) + i + rf)] * a;
        ey += Ed[size_t((i + rf) * (2 * rf + 1) + j + rf)] * a;  // transposed kernel
        py += Pt[size_t((i + rf) * (2 * rf + 1) + j + rf)] * a;
      }
    edge = std::sqrt(ex * ex + ey * ey);
    point = std::sqrt(px * px + py * py);
  };
  const std::vector<Lab3> yr = ycc(r), yt = ycc(t);
  Lab3 g = {{0, 0, 0}}, bl = {{0, 0, 0}};
  {  // c_max from linear green and blue through the same Lab function (a 1x1 "image" is not needed)
    auto to_lab = [&](double R, double G, double B) {
      double x2[3] = {0, 0, 0}, rgb[3] = {R, G, B};
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) x2[a] += M[a][c] * rgb[c];
      auto fl = [](double q) { return std::pow(q, 1.0 / 3); };
      const double L = 116 * fl(x2[1] / wp[1]) - 16;
      return Lab3{{L, 0.01 * L * 500 * (fl(x2[0] / wp[0]) - fl(x2[1] / wp[1])),
                   0.01 * L * 200 * (fl(x2[1] / wp[1]) - fl(x2[2] / wp[2]))}};
    };
    g = to_lab(0, 1, 0);
    bl = to_lab(0, 0, 1);
  }
  auto hy = [](const Lab3& a, const Lab3& b) {
    return std::fabs(a.v[0] - b.v[0]) + std::hypot(a.v[1] - b.v[1], a.v[2] - b.v[2]);
  };
  const double cmax = std::pow(hy(g, bl), 0.7);
  std::vector<double> E(size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double e = std::pow(hy(lab(yr, x, y), lab(yt, x, y)), 0.7);
      const double dc = e < 0.4 * cmax ? e * 0.95 / (0.4 * cmax)
                                       : 0.95 + (e - 0.4 * cmax) / (cmax - 0.4 * cmax) * 0.05;
      double er, pr, et, pt;
      feat(yr, x, y, er, pr);
      feat(yt, x, y, et, pt);
      const double df =
          std::pow(std::max(std::fabs(er - et), std::fabs(pr - pt)) / std::sqrt(2.0), 0.5);
      E[size_t(y) * W + x] = std::pow(dc, 1 - df);
    }
  return E;
}

}  // namespace

TEST(MetricsFlip, MatchesDirect2DEvaluationOfTheSpec) {
  // Odd, non-square images with texture, a hard edge and a bright dot near a corner.
  const int W = 29, H = 21;
  Image a = testutil::pattern(W, H, 3, 61, 0.3), b = testutil::pattern(W, H, 3, 62, 0.3);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if (x > 17)
        for (int c = 0; c < 3; ++c) b.at(x, y)[c] = c == 2 ? 0.9f : 0.1f;
  for (int c = 0; c < 3; ++c) b.at(1, 2)[c] = 1.f;
  for (double ppd : {6.0, 20.0, 45.0}) {
    Image map;
    const double m = flip(a, b, ppd, &map);
    const std::vector<double> want = direct_flip(a, b, ppd);
    double mean = 0, worst = 0;
    for (size_t i = 0; i < want.size(); ++i) {
      mean += want[i];
      worst = std::max(worst, std::fabs(double(map.data[i]) - want[i]));
    }
    mean /= double(want.size());
    EXPECT_NEAR(m, mean, 1e-6) << "ppd " << ppd;
    EXPECT_LT(worst, 1e-5) << "ppd " << ppd;  // float map, exact-arithmetic reference
  }
}
