// Confidence function, redraw map (Franke et al. 2021 §5.2, §7) and OR-mipmap queries (§6.1).
#include "sim/foveation/twfr_confidence.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/core/rng.h"

using namespace fovsim;
using namespace fovsim::twfr;

TEST(TwfrConfidence, EccentricitySmoothStep) {
  EXPECT_EQ(eccentricity_confidence(0.f, 10.f, 30.f), 0.f);
  EXPECT_EQ(eccentricity_confidence(10.f, 10.f, 30.f), 0.f);
  EXPECT_NEAR(eccentricity_confidence(20.f, 10.f, 30.f), 0.5f, 1e-6);
  EXPECT_EQ(eccentricity_confidence(30.f, 10.f, 30.f), 1.f);
  EXPECT_EQ(eccentricity_confidence(80.f, 10.f, 30.f), 1.f);
  float prev = -1.f;
  for (float phi = 0.f; phi < 40.f; phi += 0.25f) {
    float c = eccentricity_confidence(phi, 10.f, 30.f);
    EXPECT_GE(c, prev);
    prev = c;
  }
  // phi_F == phi_0: a step; phi_F = 0: only the gaze point itself has zero confidence.
  EXPECT_EQ(eccentricity_confidence(10.f, 10.f, 10.f), 0.f);
  EXPECT_EQ(eccentricity_confidence(10.001f, 10.f, 10.f), 1.f);
  EXPECT_EQ(eccentricity_confidence(0.f, 0.f, 30.f), 0.f);
  EXPECT_GT(eccentricity_confidence(0.01f, 0.f, 30.f), 0.f);
}

namespace {
struct Field {
  int W = 40, H = 30;
  std::vector<float> ecc, cc;
  std::vector<uint8_t> level, dyn, fovea;
  std::vector<uint16_t> age;
  explicit Field(uint64_t seed, float phi_f = 10.f) {
    Rng r(seed);
    size_t n = size_t(W) * size_t(H);
    ecc.resize(n);
    cc.resize(n);
    level.resize(n);
    dyn.resize(n);
    fovea.resize(n);
    age.resize(n);
    for (size_t i = 0; i < n; ++i) {
      ecc[i] = float(r.uniform(0, 60));
      fovea[i] = ecc[i] < phi_f;
      double u = r.uniform();
      level[i] = u < 0.6 ? 0 : (u < 0.97 ? uint8_t(1 + r.below(6)) : kUncovered);
      cc[i] = level[i] == 0 ? 1.f : float(r.uniform(0.5, 1));
      dyn[i] = level[i] == 0 && r.uniform() < 0.2;
      age[i] = uint16_t(r.below(12));
    }
  }
  ConfidenceInputs inputs() const {
    ConfidenceInputs in;
    in.eccentricity = ecc.data();
    in.hole_level = level.data();
    in.contrast = cc.data();
    in.dynamic = dyn.data();
    in.age = age.data();
    in.fovea = fovea.data();
    return in;
  }
};
}  // namespace

TEST(TwfrConfidence, ProductOfTheFourTerms) {
  Field f(3);
  ConfidenceParams p;
  std::vector<float> conf;
  std::vector<uint8_t> redraw;
  compute_redraw_map(f.inputs(), p, f.W, f.H, conf, redraw);
  for (size_t i = 0; i < conf.size(); ++i) {
    if (f.fovea[i] || f.level[i] == kUncovered) {
      EXPECT_NE(redraw[i], 0);
      continue;
    }
    float ce = eccentricity_confidence(f.ecc[i], p.phi_f, p.phi_0);
    float expect = ce * (f.level[i] ? f.cc[i] * std::pow(p.A, float(f.level[i])) : 1.f) *
                   (f.dyn[i] ? std::pow(p.D, float(f.age[i])) : 1.f);
    EXPECT_NEAR(conf[i], expect, 1e-5f);
    EXPECT_EQ(redraw[i] != 0, conf[i] <= p.epsilon);
  }
}

TEST(TwfrConfidence, EpsilonExtremesAndMonotonicity) {
  Field f(11);
  ConfidenceParams p;
  std::vector<float> conf;
  std::vector<uint8_t> prev, redraw;
  size_t prev_count = 0;
  for (float eps : {0.f, 0.05f, 0.1f, 0.2f, 0.25f, 0.5f, 0.9f, 1.f}) {
    p.epsilon = eps;
    ConfidenceStats st = compute_redraw_map(f.inputs(), p, f.W, f.H, conf, redraw);
    if (!prev.empty())
      for (size_t i = 0; i < redraw.size(); ++i)
        if (prev[i]) {
          EXPECT_NE(redraw[i], 0) << "redraw set must grow with epsilon";
        }
    EXPECT_GE(st.redrawn, prev_count);
    prev_count = st.redrawn;
    prev = redraw;
    if (eps == 0.f) {
      // Only c == 0 (fovea, c_e = 0) and uncovered pixels.
      for (size_t i = 0; i < redraw.size(); ++i)
        EXPECT_EQ(redraw[i] != 0, f.fovea[i] || f.level[i] == kUncovered || f.ecc[i] <= p.phi_f);
    }
    if (eps == 1.f) {
      EXPECT_EQ(st.redrawn, redraw.size());
    }
  }
}

TEST(TwfrConfidence, DynamicPixelsRedrawnAfterAgeImpliedByD) {
  // c_e = 1, reprojected, dynamic: redrawn iff D^t <= epsilon, i.e. t >= log(eps) / log(D).
  ConfidenceParams p;
  const int n = 20;
  std::vector<float> ecc(n, 50.f), cc(n, 1.f), conf;
  std::vector<uint8_t> level(n, 0), dyn(n, 1), fovea(n, 0), redraw;
  std::vector<uint16_t> age(n);
  for (int i = 0; i < n; ++i) age[size_t(i)] = uint16_t(i);
  ConfidenceInputs in;
  in.eccentricity = ecc.data();
  in.hole_level = level.data();
  in.contrast = cc.data();
  in.dynamic = dyn.data();
  in.age = age.data();
  in.fovea = fovea.data();
  compute_redraw_map(in, p, n, 1, conf, redraw);
  const int tmax = int(std::ceil(std::log(p.epsilon) / std::log(p.D)));  // 6 for 0.2 / 0.75
  EXPECT_EQ(tmax, 6);
  for (int t = 0; t < n; ++t) EXPECT_EQ(redraw[size_t(t)] != 0, t >= tmax) << "age " << t;
}

TEST(TwfrOrMip, AnyMatchesBruteForce) {
  Rng r(5);
  for (int trial = 0; trial < 4; ++trial) {
    const int W = 37 + trial * 13, H = 21 + trial * 7;
    std::vector<uint8_t> map(size_t(W) * size_t(H), 0);
    for (int k = 0; k < 3 + trial; ++k) map[r.below(uint32_t(map.size()))] = 1;
    OrMip mip;
    mip.build(map, W, H);
    for (int q = 0; q < 400; ++q) {
      int x0 = int(r.below(uint32_t(W + 10))) - 5, y0 = int(r.below(uint32_t(H + 10))) - 5;
      int x1 = x0 + int(r.below(uint32_t(W))), y1 = y0 + int(r.below(uint32_t(H)));
      bool brute = false;
      for (int y = std::max(y0, 0); y <= std::min(y1, H - 1); ++y)
        for (int x = std::max(x0, 0); x <= std::min(x1, W - 1); ++x)
          brute = brute || map[size_t(y) * W + x];
      bool got = mip.any(x0, y0, x1, y1);
      // The query is conservative (coarse texels may include neighbours) but never misses.
      if (brute) {
        EXPECT_TRUE(got);
      }
      if (x1 - x0 == 0 && y1 - y0 == 0) {
        EXPECT_EQ(got, brute);
      }
    }
    std::vector<uint8_t> empty(map.size(), 0);
    mip.build(empty, W, H);
    EXPECT_FALSE(mip.any(0, 0, W - 1, H - 1));
  }
}
