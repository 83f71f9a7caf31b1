#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "metrics_test_util.h"
#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/metrics/metrics.h"

using namespace fovsim;
namespace fs = std::filesystem;

static std::string data_dir() {
  return std::string(FOVSIM_SOURCE_DIR) + "/tests/data/metrics/";
}

TEST(MetricsSsim, IdenticalImagesAreOne) {
  Image a = testutil::pattern(50, 40, 3, 3);
  EXPECT_NEAR(ssim(a, a), 1.0, 1e-12);
  Image g = testutil::pattern(11, 11, 1, 4);  // smallest allowed size: one window
  EXPECT_NEAR(ssim(g, g), 1.0, 1e-12);
}

TEST(MetricsSsim, BoundedAndDecreasesWithNoise) {
  Image a = testutil::pattern(60, 50, 1, 5, 0.0);
  double prev = 1.0;
  for (double amp : {0.05, 0.2, 0.5}) {
    Image b = a;
    Rng rng(7);
    for (float& v : b.data) v += float(amp * (rng.uniform() - 0.5));
    double s = ssim(a, b);
    EXPECT_LT(s, prev);
    EXPECT_GT(s, -1.0);
    prev = s;
  }
}

TEST(MetricsSsim, TooSmallThrows) {
  Image a(10, 20, 1);
  try {
    ssim(a, a);
    FAIL() << "no throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.where(), "metrics.ssim");
    EXPECT_NE(std::string(e.what()).find("smaller than the 11x11 window"), std::string::npos);
  }
}

// Values computed once with skimage by tests/data/metrics/make_ssim_fixtures.py.
TEST(MetricsSsim, MatchesCommittedSkimageFixtures) {
  nlohmann::json j = nlohmann::json::parse(read_file(data_dir() + "expected.json"));
  ASSERT_GE(j["cases"].size(), 5u);
  for (auto& [name, e] : j["cases"].items()) {
    Image a = read_image(data_dir() + name + "_a.png");
    Image b = read_image(data_dir() + name + "_b.png");
    ASSERT_EQ(a.width, e["width"].get<int>()) << name;
    ASSERT_EQ(a.height, e["height"].get<int>()) << name;
    ASSERT_EQ(a.channels, e["channels"].get<int>()) << name;
    EXPECT_NEAR(ssim(a, b), e["ssim"].get<double>(), 1e-4) << name;
    EXPECT_NEAR(ssim(a, b), e["ssim"].get<double>(), 1e-6)
        << name << " (expected well inside 1e-4)";
    EXPECT_NEAR(mse(a, b), e["mse"].get<double>(), 1e-8) << name;
    EXPECT_NEAR(psnr(a, b), e["psnr"].get<double>(), 1e-5) << name;
  }
}

// Live cross-check against skimage on images it has never seen (skipped without skimage).
TEST(MetricsSsim, MatchesLiveSkimage) {
  const char* py = "/usr/bin/python3";
  if (!fs::exists(py) ||
      std::system("/usr/bin/python3 -c 'import skimage.metrics' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "no /usr/bin/python3 with skimage";
  fs::path dir = fs::temp_directory_path() / ("fovsim_metrics_ssim_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string script =
      "import sys, numpy as np\n"
      "from skimage.metrics import structural_similarity as S\n"
      "w, h = int(sys.argv[3]), int(sys.argv[4])\n"
      "a = np.fromfile(sys.argv[1], dtype='<f4').reshape(h, w).astype(np.float64)\n"
      "b = np.fromfile(sys.argv[2], dtype='<f4').reshape(h, w).astype(np.float64)\n"
      "print(repr(S(a, b, gaussian_weights=True, sigma=1.5, use_sample_covariance=False, "
      "data_range=1)))\n";
  write_file_atomic((dir / "ssim.py").string(), script);
  struct Case {
    int w, h;
    double noise;
    uint64_t seed;
  };
  for (Case c : {Case{97, 141, 0.3, 11}, Case{23, 300, 0.05, 12}, Case{128, 12, 0.6, 13}}) {
    Image a = testutil::pattern(c.w, c.h, 1, c.seed);
    Image b = testutil::pattern(c.w, c.h, 1, c.seed + 100, c.noise);
    auto dump = [&](const Image& im, const char* n) {
      std::ofstream f(dir / n, std::ios::binary);
      f.write(reinterpret_cast<const char*>(im.data.data()),
              std::streamsize(im.data.size() * sizeof(float)));
    };
    dump(a, "a.f32");
    dump(b, "b.f32");
    std::string cmd = std::string(py) + " " + (dir / "ssim.py").string() + " " +
                      (dir / "a.f32").string() + " " + (dir / "b.f32").string() + " " +
                      std::to_string(c.w) + " " + std::to_string(c.h) + " > " +
                      (dir / "out.txt").string();
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    double expected = std::stod(read_file((dir / "out.txt").string()));
    EXPECT_NEAR(ssim(a, b), expected, 1e-4) << c.w << "x" << c.h;
    EXPECT_NEAR(ssim(a, b), expected, 1e-9) << c.w << "x" << c.h << " (double precision agreement)";
  }
  fs::remove_all(dir);
}
