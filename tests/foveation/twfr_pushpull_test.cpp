// Push-pull hole filling (Franke et al. 2021 §5.1) and contrast confidence (§5.2).
#include "sim/foveation/twfr_pushpull.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "sim/core/rng.h"

using namespace fovsim;
using namespace fovsim::twfr;

namespace {
Image constant_image(int w, int h, float r, float g, float b) {
  Image im(w, h, 3);
  for (size_t i = 0; i < im.pixels(); ++i) {
    im.data[3 * i] = r;
    im.data[3 * i + 1] = g;
    im.data[3 * i + 2] = b;
  }
  return im;
}
}  // namespace

TEST(TwfrPushPull, NoHolesLeavesImageUntouched) {
  Image im = constant_image(17, 9, 0.2f, 0.4f, 0.6f);
  im.data[5] = 3.f;
  Image orig = im;
  std::vector<uint8_t> valid(im.pixels(), 1), level;
  std::vector<float> cc;
  PushPull pp;
  PushPullStats st = push_pull_fill(im, valid, nullptr, 1.f, level, cc, pp);
  EXPECT_EQ(st.holes, 0u);
  EXPECT_EQ(st.uncovered, 0u);
  EXPECT_EQ(im.data, orig.data);
  for (size_t i = 0; i < im.pixels(); ++i) {
    EXPECT_EQ(level[i], 0);
    EXPECT_EQ(cc[i], 1.f);
  }
}

TEST(TwfrPushPull, SinglePixelHoleFilledAtLevelOneWithExactColour) {
  Image im = constant_image(16, 16, 0.3f, 0.5f, 0.1f);
  std::vector<uint8_t> valid(im.pixels(), 1), level;
  std::vector<float> cc;
  const size_t hole = 5 * 16 + 7;
  valid[hole] = 0;
  im.data[3 * hole] = 99.f;
  PushPull pp;
  PushPullStats st = push_pull_fill(im, valid, nullptr, 1.f, level, cc, pp);
  EXPECT_EQ(st.holes, 1u);
  EXPECT_EQ(st.holes_per_level[1], 1u);
  EXPECT_EQ(level[hole], 1);
  EXPECT_NEAR(im.data[3 * hole], 0.3f, 1e-6);
  EXPECT_NEAR(im.data[3 * hole + 1], 0.5f, 1e-6);
  EXPECT_NEAR(cc[hole], 1.f, 1e-6);  // no luminance difference -> full contrast confidence
}

TEST(TwfrPushPull, MipLevelGrowsWithHoleSize) {
  const int N = 64;
  Image im = constant_image(N, N, 0.5f, 0.5f, 0.5f);
  std::vector<uint8_t> valid(im.pixels(), 1), level;
  std::vector<float> cc;
  auto punch = [&](int x0, int y0, int s) {
    for (int y = y0; y < y0 + s; ++y)
      for (int x = x0; x < x0 + s; ++x) valid[size_t(y) * N + size_t(x)] = 0;
  };
  punch(0, 0, 2);     // aligned 2x2: level 2
  punch(32, 32, 16);  // aligned 16x16: level 5 at its centre
  PushPull pp;
  push_pull_fill(im, valid, nullptr, 1.f, level, cc, pp);
  EXPECT_EQ(level[0], 2);
  EXPECT_EQ(level[size_t(40) * N + 40], 5);
  EXPECT_LT(level[0], level[size_t(40) * N + 40]);
}

TEST(TwfrPushPull, ContrastConfidenceFromChildrenLuminanceRange) {
  // 2x2 image: one hole, one bright pixel, two black ones -> level-1 texel c_c = 1 - 0.5 (Lmax -
  // Lmin).
  Image im(2, 2, 3, 0.f);
  std::vector<uint8_t> valid = {0, 1, 1, 1}, level;
  std::vector<float> cc;
  float white[3] = {1.f, 1.f, 1.f};
  for (int k = 0; k < 3; ++k) im.data[3 + k] = 1.f;
  PushPull pp;
  push_pull_fill(im, valid, nullptr, 1.f, level, cc, pp);
  const float lw = display_luminance(white, 1.f);
  EXPECT_GT(lw, 0.5f);
  EXPECT_LE(lw, 1.f);
  EXPECT_EQ(level[0], 1);
  EXPECT_NEAR(cc[0], 1.f - 0.5f * lw, 1e-5);
  EXPECT_NEAR(im.data[0], 1.f / 3.f, 1e-6);  // average of the three valid children
}

TEST(TwfrPushPull, NothingValidMeansUncovered) {
  Image im(8, 5, 3, 0.f);
  std::vector<uint8_t> valid(im.pixels(), 0), level;
  std::vector<float> cc;
  PushPull pp;
  PushPullStats st = push_pull_fill(im, valid, nullptr, 1.f, level, cc, pp);
  EXPECT_EQ(st.uncovered, im.pixels());
  EXPECT_EQ(st.holes, 0u);
  for (size_t i = 0; i < im.pixels(); ++i) {
    EXPECT_EQ(level[i], kUncovered);
    EXPECT_EQ(cc[i], 0.f);
  }
}

TEST(TwfrPushPull, SkippedPixelsAreNotFilled) {
  Image im = constant_image(8, 8, 1.f, 1.f, 1.f);
  std::vector<uint8_t> valid(im.pixels(), 1), skip(im.pixels(), 0), level;
  std::vector<float> cc;
  valid[9] = 0;
  skip[9] = 1;
  im.data[27] = 0.25f;
  PushPull pp;
  PushPullStats st = push_pull_fill(im, valid, skip.data(), 1.f, level, cc, pp);
  EXPECT_EQ(st.holes, 0u);
  EXPECT_EQ(level[9], kUncovered);
  EXPECT_EQ(im.data[27], 0.25f);
}

TEST(TwfrPushPull, FilledColoursAreConvexCombinationsAndFinite) {
  Rng rng(7);
  const int W = 37, H = 23;
  Image im(W, H, 3);
  std::vector<uint8_t> valid(im.pixels()), level;
  std::vector<float> cc;
  float lo = 1e9f, hi = -1e9f;
  for (size_t i = 0; i < im.pixels(); ++i) {
    valid[i] = rng.uniform() < 0.3;
    for (int k = 0; k < 3; ++k) {
      im.data[3 * i + size_t(k)] = float(rng.uniform(0, 5));
      if (valid[i]) {
        lo = std::min(lo, im.data[3 * i + size_t(k)]);
        hi = std::max(hi, im.data[3 * i + size_t(k)]);
      }
    }
  }
  PushPull pp;
  PushPullStats st = push_pull_fill(im, valid, nullptr, 1.f, level, cc, pp);
  EXPECT_EQ(st.uncovered, 0u);
  for (size_t i = 0; i < im.pixels(); ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(im.data[3 * i + size_t(k)], lo - 1e-5f);
      EXPECT_LE(im.data[3 * i + size_t(k)], hi + 1e-5f);
    }
    EXPECT_GE(cc[i], 0.5f);  // L in [0, 1] -> c_c in [0.5, 1]
    EXPECT_LE(cc[i], 1.f);
  }
}
