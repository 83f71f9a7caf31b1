// `fovsim compare` as a user runs it: text and JSON output, FLIP sanity values through files,
// and one-line errors with exit 2.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/core/files.h"
#include "sim/core/image.h"
#include "sim/core/params.h"
#include "sim/metrics/compare.h"
#include "sim/metrics/flip.h"
#include "tests/app/app_util.h"

using namespace fovsim_test;

namespace {

fovsim::Image uniform(int w, int h, float v) {
  return fovsim::Image(w, h, 3, v);
}

fovsim::Image pattern(int w, int h, int seed) {
  fovsim::Image im(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        im.at(x, y)[c] = float(0.5 + 0.45 * std::sin(0.7 * x * (c + 1) + 0.3 * y * seed + seed));
  return im;
}

int line_count(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

}  // namespace

TEST(CompareCli, JsonMatchesLibraryAndSpecValues) {
  std::string dir = temp_dir("compare");
  fovsim::write_image(dir + "/black.png", uniform(24, 20, 0.f));
  fovsim::write_image(dir + "/white.png", uniform(24, 20, 1.f));
  auto r = run_cmd(fovsim_bin() + " compare " + dir + "/black.png " + dir +
                   "/white.png --ppd 20 --json");
  ASSERT_EQ(r.code, 0) << r.output;
  fovsim::Json j = fovsim::Json::parse(r.output);
  EXPECT_NEAR(j.at("flip").get<double>(), 0.96738, 1e-4);  // FLIP.md §10.3
  EXPECT_NEAR(j.at("psnr").get<double>(), 0.0, 1e-9);      // MSE 1
  EXPECT_NEAR(j.at("ppd").get<double>(), 20.0, 0);
  EXPECT_TRUE(j.contains("ssim"));

  fovsim::write_image(dir + "/a.png", pattern(40, 30, 1));
  fovsim::write_image(dir + "/b.png", pattern(40, 30, 2));
  auto r2 = run_cmd(fovsim_bin() + " compare " + dir + "/a.png " + dir + "/b.png --json");
  ASSERT_EQ(r2.code, 0) << r2.output;
  fovsim::Json j2 = fovsim::Json::parse(r2.output);
  fovsim::Image a = fovsim::read_ldr_rgb(dir + "/a.png"), b = fovsim::read_ldr_rgb(dir + "/b.png");
  EXPECT_EQ(j2.at("flip").get<double>(), fovsim::flip(a, b, fovsim::flip_default_ppd()));
  EXPECT_NEAR(j2.at("ppd").get<double>(), 67.0206, 1e-4);  // the FLIP tool's default observer
  EXPECT_GT(j2.at("flip").get<double>(), 0.0);
  EXPECT_LT(j2.at("ssim").get<double>(), 1.0);

  auto same = run_cmd(fovsim_bin() + " compare " + dir + "/a.png " + dir + "/a.png --json");
  ASSERT_EQ(same.code, 0) << same.output;
  fovsim::Json js = fovsim::Json::parse(same.output);
  EXPECT_EQ(js.at("psnr").get<std::string>(), "inf");
  EXPECT_EQ(js.at("flip").get<double>(), 0.0);
  EXPECT_EQ(js.at("ssim").get<double>(), 1.0);

  auto text = run_cmd(fovsim_bin() + " compare " + dir + "/a.png " + dir + "/b.png");
  ASSERT_EQ(text.code, 0) << text.output;
  for (const char* k : {"psnr", "ssim", "flip"})
    EXPECT_NE(text.output.find(k), std::string::npos) << text.output;
}

TEST(CompareCli, ErrorsAreOneLineAndExit2) {
  std::string dir = temp_dir("compare_err");
  fovsim::write_image(dir + "/a.png", uniform(24, 20, 0.2f));
  fovsim::write_image(dir + "/small.png", uniform(23, 20, 0.2f));
  auto missing = run_cmd(fovsim_bin() + " compare " + dir + "/a.png " + dir + "/nope.png");
  EXPECT_EQ(missing.code, 2) << missing.output;
  EXPECT_EQ(line_count(missing.output), 1) << missing.output;
  EXPECT_NE(missing.output.find("nope.png: no such file"), std::string::npos) << missing.output;

  auto size = run_cmd(fovsim_bin() + " compare " + dir + "/a.png " + dir + "/small.png");
  EXPECT_EQ(size.code, 2) << size.output;
  EXPECT_EQ(line_count(size.output), 1) << size.output;
  EXPECT_NE(size.output.find("images differ in size"), std::string::npos) << size.output;
  EXPECT_NE(size.output.find("24x20"), std::string::npos) << size.output;
  EXPECT_NE(size.output.find("23x20"), std::string::npos) << size.output;

  auto ppd = run_cmd(fovsim_bin() + " compare " + dir + "/a.png " + dir + "/a.png --ppd 0");
  EXPECT_EQ(ppd.code, 2) << ppd.output;
  EXPECT_NE(ppd.output.find("--ppd"), std::string::npos) << ppd.output;

  fovsim::write_image(dir + "/tiny.png", uniform(5, 4, 0.3f));
  auto tiny = run_cmd(fovsim_bin() + " compare " + dir + "/tiny.png " + dir + "/tiny.png --json");
  ASSERT_EQ(tiny.code, 0) << tiny.output;
  EXPECT_TRUE(fovsim::Json::parse(tiny.output).at("ssim").is_null());
}

namespace {

// FovVideoVDP.md §15.2: Gr(H, W, a, P) as an 8-bit grating, and U(H, W, v).
fovsim::Image fv_grating(int h, int w, double a, double p) {
  fovsim::Image im(w, h, 3);
  for (int x = 0; x < w; ++x) {
    const float v =
        float(std::floor(128 + a * std::sin(2 * 3.14159265358979323846 * x / p) + 0.5)) / 255.f;
    for (int y = 0; y < h; ++y)
      for (int c = 0; c < 3; ++c) im.at(x, y)[c] = v;
  }
  return im;
}

}  // namespace

TEST(CompareCli, FvvdpImagePairAndSequence) {
  std::string dir = temp_dir("compare_fvvdp");
  fovsim::write_image(dir + "/g8.png", fv_grating(256, 256, 8, 16));
  fovsim::write_image(dir + "/u.png", uniform(256, 256, 128.f / 255.f));
  auto r = run_cmd(fovsim_bin() + " compare " + dir + "/u.png " + dir +
                   "/g8.png --fvvdp --display standard_4k --json");
  ASSERT_EQ(r.code, 0) << r.output;
  fovsim::Json j = fovsim::Json::parse(r.output);
  EXPECT_NEAR(j.at("fvvdp_jod").get<double>(), 7.8812, 2e-4);  // spec §15.2 row C8
  EXPECT_EQ(j.at("bands").size(), 7u);
  EXPECT_NEAR(j.at("bands")[2].at("q_sustained").get<double>(), 3062.1, 3062.1 * 2e-4);
  EXPECT_EQ(j.at("mode").get<std::string>(), "image");
  EXPECT_EQ(j.at("display").get<std::string>(),
            "FovVideoVDP v1.2, 75.4 [pix/deg], Lpeak=200, Lblack=0.5979 [cd/m^2], non-foveated, "
            "(standard_4k)");
  // --gaze implies foveated (row F2); identical inputs give exactly 10.
  auto f = run_cmd(fovsim_bin() + " compare " + dir + "/u.png " + dir +
                   "/g8.png --fvvdp --display htc_vive_pro --gaze 0,0 --json");
  ASSERT_EQ(f.code, 0) << f.output;
  EXPECT_NEAR(fovsim::Json::parse(f.output).at("fvvdp_jod").get<double>(), 8.9266, 2e-4);
  EXPECT_TRUE(fovsim::Json::parse(f.output).at("foveated").get<bool>());
  auto same = run_cmd(fovsim_bin() + " compare " + dir + "/g8.png " + dir +
                      "/g8.png --fvvdp --display standard_fhd --foveated --json");
  ASSERT_EQ(same.code, 0) << same.output;
  EXPECT_EQ(fovsim::Json::parse(same.output).at("fvvdp_jod").get<double>(), 10.0);
  auto text = run_cmd(fovsim_bin() + " compare " + dir + "/u.png " + dir +
                      "/g8.png --fvvdp --display standard_4k");
  ASSERT_EQ(text.code, 0) << text.output;
  EXPECT_NE(text.output.find("fvvdp_jod  7.881"), std::string::npos) << text.output;

  // Folders of PNG frames in name order: row I (8 frames at 30 fps on standard_fhd).
  fovsim::make_dirs(dir + "/ref");
  fovsim::make_dirs(dir + "/test");
  for (int k = 0; k < 8; ++k) {
    const std::string n = "/f" + std::to_string(k) + ".png";
    fovsim::write_image(dir + "/ref" + n, uniform(128, 128, 128.f / 255.f));
    fovsim::write_image(dir + "/test" + n, fv_grating(128, 128, 8, 16));
  }
  auto v = run_cmd(fovsim_bin() + " compare " + dir + "/ref " + dir +
                   "/test --fvvdp --display standard_fhd --fps 30 --json");
  ASSERT_EQ(v.code, 0) << v.output;
  fovsim::Json jv = fovsim::Json::parse(v.output);
  EXPECT_NEAR(jv.at("fvvdp_jod").get<double>(), 6.5871, 2e-4);
  EXPECT_EQ(jv.at("frames").get<int>(), 8);
  EXPECT_EQ(jv.at("mode").get<std::string>(), "video");
  EXPECT_FALSE(jv.at("bands")[0].at("q_transient").is_null());
}

TEST(CompareCli, FvvdpBadInputIsOneLineExit2) {
  std::string dir = temp_dir("compare_fvvdp_err");
  fovsim::make_dirs(dir + "/a");
  fovsim::make_dirs(dir + "/b");
  for (int k = 0; k < 3; ++k) {
    fovsim::write_image(dir + "/a/" + std::to_string(k) + ".png", uniform(32, 32, 0.3f));
    if (k < 2) fovsim::write_image(dir + "/b/" + std::to_string(k) + ".png", uniform(32, 32, 0.4f));
  }
  fovsim::write_image(dir + "/x.png", uniform(32, 32, 0.3f));
  fovsim::write_image(dir + "/y.png", uniform(40, 32, 0.3f));
  struct Bad {
    std::string args, needle;
  } bad[] = {
      {dir + "/a " + dir + "/a --fvvdp --display standard_fhd", "--fps"},
      {dir + "/a " + dir + "/b --fvvdp --display standard_fhd --fps 30", "frames"},
      {dir + "/x.png " + dir + "/y.png --fvvdp --display standard_fhd", "same size"},
      {dir + "/x.png " + dir + "/x.png --fvvdp --display nope", "available: "},
      {dir + "/x.png " + dir + "/x.png --fvvdp --display standard_fhd --gaze 3", "--gaze"},
      {dir + "/x.png " + dir + "/x.png --display standard_fhd", "need --fvvdp"},
  };
  for (const auto& b : bad) {
    auto r = run_cmd(fovsim_bin() + " compare " + b.args);
    EXPECT_EQ(r.code, 2) << b.args << "\n" << r.output;
    EXPECT_EQ(line_count(r.output), 1) << r.output;
    EXPECT_NE(r.output.find(b.needle), std::string::npos) << r.output;
  }
}
