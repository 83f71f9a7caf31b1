// Scale invariance of the methods (docs/fidelity.md "Scale invariance of the methods"): every size
// a method defines on the screen is in display pixels and applied at render.scale x that size.
// Per method: KFR's internal and post filters (Meng 2018 §2.2.3, eq. 2.14), fVRS's tiles and
// rates (Franke et al. 2021 §8.4), the hyperbolic layers' pixel sizes (Ye et al. 2022 §5.1) and
// TWFR's hole levels (Franke et al. 2021 §5.2); and the flags when a size falls below a pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "sim/foveation/factory.h"
#include "sim/foveation/frame.h"
#include "sim/foveation/mapping.h"
#include "sim/foveation/twfr_confidence.h"

using namespace fovsim;

namespace {

// Variance (pixels^2) of the response to a unit impulse at column cx of row y (channel 0).
double row_variance(const Image& img, int y, int cx) {
  double sum = 0, var = 0;
  for (int x = 0; x < img.width; ++x) {
    const double v = img.at(x, y)[0];
    sum += v;
    var += v * double(x - cx) * (x - cx);
  }
  return var / sum;
}

Image impulse(int W, int H, int cx, int cy) {
  Image img(W, H, 3, 0.f);
  for (int c = 0; c < 3; ++c) img.at(cx, cy)[c] = 1.f;
  return img;
}

bool has_flag(const FrameOutput& o, const std::string& f) {
  return std::find(o.flags.begin(), o.flags.end(), f) != o.flags.end();
}

Display display_of(int W, int H) {
  Display d;
  d.width = W;
  d.height = H;
  d.fov_h_deg = 90.0;
  d.fov_v_deg = rad2deg(2.0 * std::atan(double(H) / W));  // square pixels
  return d;
}

// One frame of a built-in scene at W x H, the gaze at the centre, and a method run on it with a
// given render_scale (as the engine sets it for a scaled display).
struct World {
  Display d;
  Scene scene;
  std::unique_ptr<Renderer> r;
  FrameData fd;
  World(int W, int H) : d(display_of(W, H)) {
    Params p(Json{{"type", "atrium"}}, "test");
    scene = make_scene(p, std::string(FOVSIM_SOURCE_DIR) + "/models");
    r = std::make_unique<Renderer>(scene, RenderSettings{});
    TraceSample s;
    s.head_pos = glm::dvec3(scene.default_eye);
    prepare_frame(*r, d, s, 0, kShadingChannels, nullptr, fd);
  }
  FrameOutput run(const std::string& method, Json params, double render_scale, bool debug = false) {
    Params p(params, "test");
    auto m = make_method(method, p);
    FrameContext ctx = fd.context(scene, *r, d, debug);
    ctx.render_scale = render_scale;
    FrameOutput out;
    m->render(ctx, out);
    return out;
  }
};

}  // namespace

TEST(ScaleInvariance, KernelWithVarianceHasThatVariance) {
  // Native internal AA: exactly [1 2 1] / 4.
  const std::vector<float> k = kernel_with_variance(0.5);
  ASSERT_EQ(k.size(), 3u);
  EXPECT_EQ(k[0], 0.25f);
  EXPECT_EQ(k[1], 0.5f);
  EXPECT_EQ(k[2], 0.25f);
  for (double v : {0.02, 0.125, 0.5, 0.8, 2.0, 9.0, 40.0}) {
    const std::vector<float> kv = kernel_with_variance(v);
    EXPECT_EQ(kv.size() % 2, 1u);
    double sum = 0;
    for (float w : kv) {
      EXPECT_GE(w, 0.f);
      sum += w;
    }
    EXPECT_NEAR(sum, 1.0, 1e-5) << v;
    EXPECT_NEAR(kernel_variance(kv), v, 1e-4 * std::max(1.0, v)) << v;
  }
}

// Meng 2018 eq. 2.14: the post filter of size code eta is the native kernel at scale 1 and has
// scale^2 its variance (half its width at scale 0.5) at a reduced scale.
TEST(ScaleInvariance, KfrPostFilterWidthScalesWithRenderScale) {
  for (int eta = 3; eta <= 39; eta += 2) {
    const std::vector<float> native = post_aa_kernel_native(eta);
    EXPECT_EQ(post_aa_kernel(eta, 1.0), native) << eta;
    const double v1 = kernel_variance(native);
    EXPECT_NEAR(std::sqrt(kernel_variance(post_aa_kernel(eta, 0.5))), 0.5 * std::sqrt(v1), 1e-4)
        << eta;
    EXPECT_NEAR(kernel_variance(post_aa_kernel(eta, 0.25)), v1 / 16, 1e-4) << eta;
  }
  // Through variable_gaussian: an impulse's spread at scale 0.5 has half the standard deviation;
  // the taps counted are the native kernel's at both scales (the display's filter work).
  for (int eta : {5, 15, 39}) {
    Image a = impulse(101, 5, 50, 2), b = a;
    const std::vector<uint8_t> code(a.pixels(), uint8_t(eta));
    const double ta = variable_gaussian(a, code, 39, nullptr, 1.0);
    const double tb = variable_gaussian(b, code, 39, nullptr, 0.5);
    EXPECT_NEAR(std::sqrt(row_variance(b, 2, 50)), 0.5 * std::sqrt(row_variance(a, 2, 50)), 1e-3)
        << eta;
    EXPECT_EQ(ta, tb);
    EXPECT_EQ(ta, 2.0 * eta * double(a.pixels()));
  }
}

// Meng 2018 §2.2.3: the internal 3x3 Gaussian has variance 0.5 LP px^2 at scale 1 and 0.5 s^2 at s.
TEST(ScaleInvariance, KfrInternalFilterVarianceScalesWithRenderScale) {
  for (double s : {1.0, 0.5, 0.25, 2.0}) {
    Image img = impulse(41, 41, 20, 20);
    const double taps = gaussian3x3_from(img, 0, true, nullptr, s);
    EXPECT_NEAR(row_variance(img, 20, 20), 0.5 * s * s, 1e-4) << s;
    EXPECT_EQ(taps, 6.0 * 41 * 41);
  }
}

TEST(ScaleInvariance, KfrFlagsFiltersBelowAPixel) {
  World w(64, 48);
  const Json p{{"sigma", 1.8}};
  EXPECT_FALSE(has_flag(w.run("kfr", p, 1.0), "kfr_filter_below_pixel"));
  EXPECT_TRUE(has_flag(w.run("kfr", p, 0.5), "kfr_filter_below_pixel"));
  EXPECT_FALSE(has_flag(w.run("kfr", Json{{"internal_aa", false}, {"post_aa", false}}, 0.5),
                        "kfr_filter_below_pixel"));
}

// Franke et al. 2021 §8.4's 4x4 tiles and 1/2/4 rates are display pixels: a run at render scale
// 0.5 on a W x H image (a 2W x 2H display) reports the shaded samples the 2W x 2H run shades,
// divided by the pixel scale 4 (no edge extras: those depend on content).
TEST(ScaleInvariance, FvrsTilesAndRatesAreDisplayPixels) {
  World full(128, 96), half(64, 48);
  const Json p{{"edge_aware", false}};
  const FrameOutput a = full.run("fvrs", p, 1.0), b = half.run("fvrs", p, 0.5);
  const double na = a.counters.get(Counter::shaded_samples);
  const double nb = b.counters.get(Counter::shaded_samples);
  EXPECT_NEAR(4.0 * nb / na, 1.0, 0.03) << na << " " << nb;
  EXPECT_FALSE(has_flag(b, "fvrs_rate_rounded"));
  // The image: at 0.5 the 2x2-rate ring is one simulated pixel per coarse pixel (shaded at every
  // pixel, equal to the direct shading), at 1 a quarter of it is.
  auto exact_fraction = [&](const FrameOutput& o) {
    const Image& ref = *half.fd.context(half.scene, *half.r, half.d, false).direct;
    size_t same = 0;
    for (size_t i = 0; i < ref.pixels(); ++i)
      same +=
          o.image.data[3 * i] == ref.data[3 * i] && o.image.data[3 * i + 1] == ref.data[3 * i + 1];
    return double(same) / double(ref.pixels());
  };
  const double f1 = exact_fraction(half.run("fvrs", p, 1.0)), f05 = exact_fraction(b);
  EXPECT_GT(f05, f1 + 0.1) << f05 << " " << f1;
  // At 0.25 the 2x2 rate is half a simulated pixel: held at one, flagged.
  World quarter(32, 24);
  EXPECT_TRUE(has_flag(quarter.run("fvrs", p, 0.25), "fvrs_rate_rounded"));
  EXPECT_FALSE(has_flag(a, "fvrs_rate_rounded"));
}

// Ye et al. 2022 §5.1's layer pixel sizes s2 = 2, s3 = 12.35 are display pixels.
TEST(ScaleInvariance, HyperbolicLayerSizesAreDisplayPixels) {
  World full(128, 96), half(64, 48);
  const Json p = Json::object();
  const FrameOutput a = full.run("hyperbolic", p, 1.0), b = half.run("hyperbolic", p, 0.5);
  const double na = a.counters.get(Counter::shaded_samples);
  const double nb = b.counters.get(Counter::shaded_samples);
  EXPECT_NEAR(4.0 * nb / na, 1.0, 0.1) << na << " " << nb;
  EXPECT_FALSE(has_flag(b, "hyperbolic_layer_below_pixel"));
  // The outer layer at 0.5 has pixels of 12.35 / 2 simulated pixels: ceil(64 / 6.175) = 11 wide
  // (ceil(64 / 12.35) = 6 at scale 1 on the same image).
  auto outer_width = [](const FrameOutput& o) {
    for (auto& [name, img] : o.debug)
      if (name == "layer_outer") return img.width;
    return -1;
  };
  EXPECT_EQ(outer_width(half.run("hyperbolic", p, 0.5, true)), 11);
  EXPECT_EQ(outer_width(half.run("hyperbolic", p, 1.0, true)), 6);
  // s2 = 2 at scale 0.25 is half a simulated pixel.
  World quarter(32, 24);
  EXPECT_TRUE(has_flag(quarter.run("hyperbolic", p, 0.25), "hyperbolic_layer_below_pixel"));
}

// Franke et al. 2021 §5.2: c_s = A^m with m in display mip levels; a simulated level-m hole at
// scale 0.5 is a display level m + 1 hole.
TEST(ScaleInvariance, TwfrHoleLevelsAreDisplayLevels) {
  const int W = 4, H = 1;
  std::vector<float> ecc(4, 80.f), cc(4, 1.f), conf;
  std::vector<uint8_t> level = {0, 1, 2, 3}, redraw;
  twfr::ConfidenceInputs in;
  in.eccentricity = ecc.data();
  in.hole_level = level.data();
  in.contrast = cc.data();
  twfr::ConfidenceParams p;
  p.epsilon = 0.f;
  twfr::compute_redraw_map(in, p, W, H, conf, redraw);
  EXPECT_FLOAT_EQ(conf[1], 0.6f);
  EXPECT_FLOAT_EQ(conf[2], 0.36f);
  p.level_offset = 1.f;  // render.scale 0.5
  twfr::compute_redraw_map(in, p, W, H, conf, redraw);
  EXPECT_FLOAT_EQ(conf[0], 1.f);  // reprojected: no hole
  EXPECT_FLOAT_EQ(conf[1], 0.36f);
  EXPECT_FLOAT_EQ(conf[2], 0.216f);
  EXPECT_NEAR(conf[3], 0.1296f, 1e-6);
}

TEST(ScaleInvariance, TwfrFlagsHolesBelowAPixel) {
  World w(32, 24);
  EXPECT_TRUE(has_flag(w.run("twfr", Json::object(), 0.5), "twfr_holes_below_pixel"));
  EXPECT_FALSE(has_flag(w.run("twfr", Json::object(), 1.0), "twfr_holes_below_pixel"));
}

// Weier et al. 2016's p(e) is per display pixel: at scale 0.5 a simulated pixel (4 display
// pixels) is sampled with 1 - (1 - p)^4, and the shaded count stays the 2W x 2H display's.
TEST(ScaleInvariance, LinearProbabilityIsPerDisplayPixel) {
  World full(128, 96), half(64, 48);
  const Json p{{"r1", 2.0}, {"r2", 6.0}, {"p_min", 0.05}};
  const FrameOutput a = full.run("linear", p, 1.0), b = half.run("linear", p, 0.5);
  const double na = a.counters.get(Counter::shaded_samples);
  const double nb = b.counters.get(Counter::shaded_samples);
  EXPECT_NEAR(4.0 * nb / na, 1.0, 0.08) << na << " " << nb;
  // The simulated pixels sampled (the mask): at 0.5 a peripheral pixel is sampled with
  // 1 - 0.95^4 = 0.185 instead of 0.05, so the mask holds more of them than at scale 1.
  auto mask_count = [](const FrameOutput& o) {
    for (auto& [name, img] : o.debug)
      if (name == "sample_mask") {
        double n = 0;
        for (float v : img.data) n += v;
        return n;
      }
    return -1.0;
  };
  const double m05 = mask_count(half.run("linear", p, 0.5, true));
  const double m1 = mask_count(half.run("linear", p, 1.0, true));
  EXPECT_GT(m05, 1.5 * m1) << m05 << " " << m1;
}
