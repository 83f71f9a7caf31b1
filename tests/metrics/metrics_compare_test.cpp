// read_ldr_rgb and compare_images: files read as the FLIP reference tool reads them (FLIP.md §1).
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "sim/core/error.h"
#include "sim/metrics/compare.h"
#include "sim/metrics/flip.h"

using namespace fovsim;

namespace {

std::string tmp_path(const std::string& name) {
  auto d =
      std::filesystem::temp_directory_path() / ("fovsim_compare_" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return (d / name).string();
}

template <class T>
void write_raw(const std::string& path, int w, int h, int c, OIIO::TypeDesc type,
               const std::vector<T>& px) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(w, h, c, type);
  ASSERT_TRUE(out->open(path, spec));
  ASSERT_TRUE(out->write_image(type, px.data()));
  out->close();
}

}  // namespace

TEST(MetricsCompare, ReadsLikeTheFlipTool) {
  // 16-bit: reduced to the high byte, then / 255.
  const std::string p16 = tmp_path("a16.png");
  write_raw<uint16_t>(p16, 2, 1, 3, OIIO::TypeDesc::UINT16,
                      {0x8180, 0x00ff, 0xffff, 0x0100, 0x7fff, 0x0000});
  Image a = read_ldr_rgb(p16);
  ASSERT_EQ(a.channels, 3);
  const float want16[6] = {0x81 / 255.f, 0.f, 1.f, 1 / 255.f, 0x7f / 255.f, 0.f};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(a.data[size_t(i)], want16[i]) << i;
  // 8-bit RGBA: alpha dropped, not composited.
  const std::string p8 = tmp_path("a8.png");
  write_raw<uint8_t>(p8, 1, 1, 4, OIIO::TypeDesc::UINT8, {10, 200, 255, 0});
  Image b = read_ldr_rgb(p8);
  ASSERT_EQ(b.channels, 3);
  EXPECT_EQ(b.data[0], 10 / 255.f);
  EXPECT_EQ(b.data[1], 200 / 255.f);
  EXPECT_EQ(b.data[2], 1.f);
  // Grey: copied to all three channels.
  const std::string pg = tmp_path("g.png");
  write_raw<uint8_t>(pg, 1, 1, 1, OIIO::TypeDesc::UINT8, {77});
  Image g = read_ldr_rgb(pg);
  ASSERT_EQ(g.channels, 3);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(g.data[size_t(c)], 77 / 255.f);
  // Missing file: one message naming the path.
  try {
    read_ldr_rgb(tmp_path("missing.png"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.png: no such file"), std::string::npos)
        << e.what();
  }
}

TEST(MetricsCompare, ValuesAndErrors) {
  Image a(16, 12, 3, 0.f), b(16, 12, 3, 1.f);
  ImageComparison c = compare_images(a, b, 20.0);
  EXPECT_NEAR(c.flip, 0.96738, 1e-4);  // FLIP.md §10.3 black vs white
  EXPECT_EQ(c.psnr, 0.0);
  EXPECT_EQ(c.width, 16);
  Json j = comparison_json(compare_images(a, a, 20.0));
  EXPECT_EQ(j.at("psnr"), "inf");
  EXPECT_EQ(j.at("flip"), 0.0);
  EXPECT_EQ(j.at("ssim"), 1.0);
  EXPECT_NE(comparison_text(c).find("flip    0.967"), std::string::npos) << comparison_text(c);
  EXPECT_TRUE(
      comparison_json(compare_images(Image(5, 5, 3), Image(5, 5, 3), 20.0)).at("ssim").is_null());
  try {
    compare_images(a, Image(15, 12, 3), 20.0, "r.png", "t.png");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "compare: images differ in size: r.png is 16x12, t.png is 15x12");
  }
  EXPECT_THROW(compare_images(a, b, -1.0), Error);
}
