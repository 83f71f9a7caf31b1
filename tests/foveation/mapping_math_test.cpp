// Property tests of the image-mapping math (Meng 2018 eqs. 2.10-2.13, Ye et al. 2022 eqs. 4-7),
// kernels, densities, iso-budget and parameter validation. No rendering here.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sim/core/error.h"
#include "sim/foveation/density.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/mapping.h"
#include "sim/foveation/mapping_spec.h"
#include "tests/common/method_lists.h"

using namespace fovsim;

namespace {
const int kW = 96, kH = 80;
const double kSigmas[] = {1.0, 1.0 + 1e-9, 1.8, 2.6, 8.0, 32.0};
const double kAlphas[] = {0.25, 0.5, 1.0, 4.0, 8.0, 16.0};
const double kFs[] = {1e-9, 0.05, 0.38, 1.0, 1e9};
// Gaze: exact centre, a pixel centre, the four edges, the four corners, outside.
std::vector<glm::dvec2> gazes() {
  return {{kW * 0.5, kH * 0.5},
          {30.5, 20.5},
          {0, kH * 0.5},
          {kW, kH * 0.5},
          {kW * 0.5, 0},
          {kW * 0.5, kH},
          {0, 0},
          {kW, 0},
          {0, kH},
          {kW, kH},
          {-50, 30},
          {kW + 1e6, -1e6}};
}
}  // namespace

TEST(Kernel, InverseAndEndpoints) {
  for (auto kind : {KernelKind::Power, KernelKind::Sine, KernelKind::Exp})
    for (double a : kAlphas) {
      KernelFn k{kind, a};
      EXPECT_NEAR(k.K(0), 0, 1e-12);
      EXPECT_NEAR(k.K(1), 1, 1e-12);
      for (double x = 0.05; x < 1; x += 0.1) {
        EXPECT_NEAR(k.Kinv(k.K(x)), x, 1e-9) << KernelFn::name(kind) << " a=" << a;
        EXPECT_TRUE(std::isfinite(k.Kinv_deriv(x)));
        EXPECT_GT(k.K(x + 0.01), k.K(x));  // monotonic
      }
    }
}

// Forward(inverse(u, v)) == (u, v) for LP-buffer points that land on the screen, and
// inverse(forward(x, y)) == (x, y) for screen points at least 1 px from the fovea (the
// valid region: radii below 1 px clamp to u = 0). Bound: 1e-6 px.
TEST(LogPolar, RoundTripWithinBound) {
  for (auto kind : {KernelKind::Power, KernelKind::Sine, KernelKind::Exp})
    for (double a : kAlphas)
      for (double sg : {1.0, 1.8, 2.6}) {
        int w = reduced_size(kW, sg), h = reduced_size(kH, sg);
        for (auto g : gazes()) {
          if (std::abs(g.x) > 1e5) continue;  // far gaze: covered by the finiteness test
          auto m = LogPolarMap::make(kW, kH, w, h, g, KernelFn{kind, a});
          for (int y = 0; y < kH; y += 7)
            for (int x = 0; x < kW; x += 5) {
              double px = x + 0.5, py = y + 0.5;
              if (std::hypot(px - g.x, py - g.y) < 1.0) continue;
              glm::dvec2 uv = m.forward(px, py);
              // Where K^-1 is extremely flat the map is ill-conditioned; only test where u
              // resolves the radius (du/dr > 1e-7 LP px per screen px).
              if (m.density(px, py) < 1e-12) continue;
              glm::dvec2 back = m.inverse(uv.x, uv.y);
              ASSERT_NEAR(back.x, px, 1e-6 * std::max(1.0, std::hypot(px - g.x, py - g.y)))
                  << KernelFn::name(kind) << " a=" << a << " g=" << g.x << "," << g.y;
              ASSERT_NEAR(back.y, py, 1e-6 * std::max(1.0, std::hypot(px - g.x, py - g.y)));
            }
        }
      }
}

TEST(LogPolar, GazeDependentL) {
  // Eq. 2.12-2.13: L is the log of the largest fovea-corner distance.
  auto m = LogPolarMap::make(kW, kH, 10, 10, {10, 20}, KernelFn{});
  EXPECT_NEAR(m.L, std::log(std::hypot(kW - 10.0, kH - 20.0)), 1e-12);
  auto c = LogPolarMap::make(kW, kH, 10, 10, {kW * 0.5, kH * 0.5}, KernelFn{});
  EXPECT_NEAR(c.L, std::log(std::hypot(kW * 0.5, kH * 0.5)), 1e-12);
  // The farthest corner maps to u = w (K^-1(1) = 1).
  EXPECT_NEAR(m.forward(kW, kH).x, 10.0, 1e-9);
}

TEST(LogPolar, FiniteEverywhereIncludingGazeOnPixelCentre) {
  for (double sg : kSigmas)
    for (double a : kAlphas)
      for (auto g : gazes()) {
        int w = reduced_size(kW, sg), h = reduced_size(kH, sg);
        auto m = LogPolarMap::make(kW, kH, w, h, g, KernelFn{KernelKind::Power, a});
        for (double y : {0.5, g.y, 40.5, 79.5})
          for (double x : {0.5, g.x, 48.5, 95.5}) {
            glm::dvec2 uv = m.forward(x, y);
            ASSERT_TRUE(std::isfinite(uv.x) && std::isfinite(uv.y));
            ASSERT_GE(uv.x, 0);
            ASSERT_LE(uv.x, w);
            ASSERT_GE(uv.y, 0);
            ASSERT_LT(uv.y, h);
            ASSERT_TRUE(std::isfinite(m.density(x, y)));
            glm::dvec2 p = m.inverse(uv.x, uv.y);
            ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y));
          }
      }
}

TEST(Rect, RoundTripAndRangeAllQuadrants) {
  for (double sg : kSigmas)
    for (double fx : kFs)
      for (double fy : kFs)
        for (auto g : gazes()) {
          int w = reduced_size(kW, sg), h = reduced_size(kH, sg);
          auto m = RectMap::make(kW, kH, w, h, g, fx * kW, fy * kH);
          for (int y = 0; y < kH; y += 9)
            for (int x = 0; x < kW; x += 11) {
              glm::dvec2 uv = m.forward(x + 0.5, y + 0.5);
              ASSERT_TRUE(std::isfinite(uv.x) && std::isfinite(uv.y));
              ASSERT_GE(uv.x, 0);
              ASSERT_LE(uv.x, w);
              ASSERT_GE(uv.y, 0);
              ASSERT_LE(uv.y, h);
              ASSERT_TRUE(std::isfinite(m.density(x + 0.5, y + 0.5)));
              // Round trip where the map is well conditioned (f not extreme): 1e-6 px.
              if (fx >= 0.05 && fx <= 1 && fy >= 0.05 && fy <= 1) {
                glm::dvec2 b = m.inverse(uv.x, uv.y);
                ASSERT_NEAR(b.x, x + 0.5, 1e-6) << "fx=" << fx << " g=" << g.x;
                ASSERT_NEAR(b.y, y + 0.5, 1e-6);
              }
            }
          // Inverse of every buffer pixel centre lies on the screen (RMFR uses the whole buffer).
          for (int v = 0; v < h; v += std::max(1, h / 7))
            for (int u = 0; u < w; u += std::max(1, w / 7)) {
              glm::dvec2 p = m.inverse(u + 0.5, v + 0.5);
              ASSERT_TRUE(p.x >= 0 && p.x <= kW && p.y >= 0 && p.y <= kH) << p.x << "," << p.y;
            }
        }
}

TEST(Rect, IdentityForHugeFAndSigmaOne) {
  auto m = RectMap::make(kW, kH, kW, kH, {30.5, 20.5}, 1e9 * kW, 1e9 * kH);
  for (int x = 0; x < kW; ++x) EXPECT_NEAR(m.ax.forward(x + 0.5), x + 0.5, 1e-6);
  EXPECT_NEAR(m.density(10.5, 70.5), 1.0, 1e-6);
}

TEST(Rect, DensityIntegratesToBufferSize) {
  // Sum over pixel centres of du/dx dv/dy ~ w h (the whole RS-buffer is used, Ye et al. 2022
  // §3.3.3).
  auto m = RectMap::make(kW, kH, 37, 31, {30.5, 20.5}, 0.38 * kW, 0.38 * kH);
  double sum = 0;
  const int n = 8;  // midpoint rule on 8x8 sub-cells per pixel
  for (int y = 0; y < kH * n; ++y)
    for (int x = 0; x < kW * n; ++x) sum += m.density((x + 0.5) / n, (y + 0.5) / n) / (n * n);
  EXPECT_NEAR(sum / (37.0 * 31.0), 1.0, 2e-3);
}

TEST(Mapping, ReducedSize) {
  EXPECT_EQ(reduced_size(1440, 1.0), 1440);
  EXPECT_EQ(reduced_size(1440, 1.0 + 1e-9), 1440);
  EXPECT_EQ(reduced_size(1440, 2.6), 554);
  EXPECT_EQ(reduced_size(80, 32), 3);
  EXPECT_EQ(reduced_size(80, 1e9), 1);
}

TEST(Mapping, BilinearWrapsAndClamps) {
  Image img(2, 2, 3);
  img.at(0, 0)[0] = 1;  // (0,0) red = 1
  img.at(1, 1)[0] = 3;
  EXPECT_NEAR(bilinear(img, 0.5, 0.5, false).x, 1.0, 1e-6);
  EXPECT_NEAR(bilinear(img, 1.0, 1.0, false).x, 1.0, 1e-6);  // mean of 1,0,0,3
  EXPECT_NEAR(bilinear(img, -5, -5, false).x, 1.0, 1e-6);
  // wrap: y = 0 sits between row 1 (above, wrapped) and row 0
  EXPECT_NEAR(bilinear(img, 0.5, 0.0, true).x, 0.5, 1e-6);
  EXPECT_TRUE(std::isfinite(bilinear(img, std::nan(""), 1e300, true).x));
}

TEST(Mapping, PushPullFillsHolesKeepsSamples) {
  Image img(16, 12, 3, 0.f);
  std::vector<uint8_t> valid(img.pixels(), 0);
  for (int y = 0; y < 12; y += 3)
    for (int x = 0; x < 16; x += 3) {
      valid[size_t(y) * 16 + size_t(x)] = 1;
      for (int c = 0; c < 3; ++c) img.at(x, y)[c] = 0.25f;
    }
  push_pull_fill(img, valid);
  for (float v : img.data) EXPECT_NEAR(v, 0.25f, 1e-5);  // constant stays constant
}

TEST(Mapping, VariableGaussianPreservesConstant) {
  Image img(20, 10, 3, 0.7f);
  std::vector<uint8_t> eta(img.pixels(), 39);
  eta[0] = 1;
  double taps = variable_gaussian(img, eta, 39);
  EXPECT_GT(taps, 0);
  for (float v : img.data) EXPECT_NEAR(v, 0.7f, 1e-5);
}

TEST(MappingParams, InvalidValuesAreConfigErrorsWithPath) {
  auto expect_err = [](const std::string& method, Json j, const std::string& needle) {
    Params p(j, "cfg.json", "methods[0]");
    try {
      make_method(method, p);
      FAIL() << "expected error for " << j.dump();
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_err("kfr", Json{{"sigma", 0.5}}, "cfg.json: methods[0].sigma");
  expect_err("kfr", Json{{"sigma", std::numeric_limits<double>::quiet_NaN()}}, "methods[0].sigma");
  expect_err("kfr", Json{{"alpha", 0}}, "methods[0].alpha");
  expect_err("kfr", Json{{"kernel", "cubic"}}, "methods[0].kernel");
  expect_err("rmfr", Json{{"fx", 0}}, "methods[0].fx");
  expect_err("rmfr", Json{{"fy", -1}}, "methods[0].fy");
  expect_err("rmfr", Json{{"fx", 0.3}, {"fx_px", 100}}, "methods[0].fx_px");
  expect_err("rmfr", Json{{"sigma", 2}, {"sigmaa", 3}}, "methods[0].sigmaa");
  expect_err("linear", Json{{"r1", 30}, {"r2", 20}}, "methods[0].r2");
  expect_err("linear", Json{{"p_min", 0}}, "methods[0].p_min");
  expect_err("hyperbolic", Json{{"s3", 0.5}}, "methods[0].s3");
  expect_err("fvrs", Json{{"target_shaded_fraction", 1.5}}, "methods[0].target_shaded_fraction");
  // Valid ones construct and report their columns.
  Params ok(Json{{"sigma", 2.0}, {"fx_px", 100.0}, {"fy", 0.3}}, "cfg.json");
  auto m = make_method("rmfr", ok);
  auto cols = m->param_columns();
  ASSERT_GE(cols.size(), 3u);
  EXPECT_EQ(cols[0].first, "sigma");
  EXPECT_EQ(cols[1].first, "fx_px");
  EXPECT_EQ(cols[2].first, "fy");
}

TEST(IsoBudget, SolvesEachMethodToTarget) {
  Display d;
  d.width = kW * 2;
  d.height = kH * 2;
  d.fov_h_deg = 98;
  d.fov_v_deg = 90;
  Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  MappingView v = MappingView::at(cam, {d.width * 0.5, d.height * 0.5});
  const double total = double(d.width) * d.height;
  for (const std::string& m : test::iso_budget_methods()) {
    Params p(Json::object());
    MappingSpec s = MappingSpec::from_params(m, p), out;
    double got = 0;
    EXPECT_TRUE(solve_iso_budget(s, v, 0.2, out, &got)) << m;
    // Discrete counts (buffer rounding, block rates): within 1.5 % of the screen.
    EXPECT_NEAR(got, 0.2, 0.015) << m;
    EXPECT_NEAR(expected_shaded_samples(out, v) / total, got, 1e-12);
  }
  // Unreachable: fvrs cannot go below 1/16.
  Params p(Json::object());
  MappingSpec s = MappingSpec::from_params("fvrs", p), out;
  double got = 0;
  EXPECT_FALSE(solve_iso_budget(s, v, 0.01, out, &got));
  EXPECT_NEAR(got, 1.0 / 16, 0.01);
}

TEST(Density, RmfrAndKfrScaleAsInverseSigmaSquared) {
  Display d;
  d.width = 288;
  d.height = 320;
  Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  MappingView v = MappingView::at(cam, {144, 160});
  // The subset whose whole W/sigma x H/sigma buffer is shaded (rmfr_auto: f chosen per frame).
  for (std::string m : {"kfr", "rmfr"}) {
    Params p(Json{{"sigma", 1.5}}), q(Json{{"sigma", 3.0}});
    double a = expected_shaded_samples(MappingSpec::from_params(m, p), v);
    double b = expected_shaded_samples(MappingSpec::from_params(m, q), v);
    EXPECT_NEAR(a / b, 4.0, 0.12) << m;  // 1/sigma^2 up to buffer rounding
  }
}
