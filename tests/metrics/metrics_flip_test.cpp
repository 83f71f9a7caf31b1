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
