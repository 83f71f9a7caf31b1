// `fovsim compare` logic: load an image pair as the FLIP reference tool does, then PSNR, SSIM
// and the LDR-FLIP mean (docs/metrics.md, "fovsim compare").
#include "sim/metrics/compare.h"

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/metrics/flip.h"
#include "sim/metrics/metrics.h"

namespace fovsim {

Image read_ldr_rgb(const std::string& path) {
  if (!std::filesystem::exists(path)) throw Error(path, "no such file");
  check_input_file(path);  // a FIFO or /dev/zero is refused before the decoder blocks on it
  // Raw colour values: OpenImageIO premultiplies PNG colour by alpha unless asked not to; the
  // FLIP tool drops alpha without compositing.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) throw Error(path, "cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  const int W = spec.width, H = spec.height, C = spec.nchannels;
  if (W <= 0 || H <= 0 || C <= 0) throw Error(path, "empty image");
  // The header's size is checked before anything is allocated (files.h max_image_pixels).
  const double max_px = max_image_pixels();
  if (double(W) * double(H) > max_px || C > 16)
    throw Error(path, "image header claims " + std::to_string(W) + "x" + std::to_string(H) + "x" +
                          std::to_string(C) + ", over the limit of " +
                          std::to_string(int64_t(max_px)) +
                          " pixels (set FOVSIM_MAX_IMAGE_MPIXELS to raise it)");
  const size_t n = size_t(W) * size_t(H) * size_t(C);
  std::vector<float> v(n);
  const auto base = spec.format.basetype;
  if (base == OIIO::TypeDesc::UINT8 || base == OIIO::TypeDesc::UINT16) {
    // Integer files: exact bytes, then byte / 255 as the reference tool (stb_image) does.
    std::vector<uint16_t> raw(n);
    if (!in->read_image(0, 0, 0, C, OIIO::TypeDesc::UINT16, raw.data()))
      throw Error(path, "cannot decode image: " + in->geterror());
    const bool wide = base == OIIO::TypeDesc::UINT16;
    for (size_t i = 0; i < n; ++i) {
      // UINT8 read as UINT16 is v * 257; either way the high byte is the 8-bit value.
      const unsigned byte = wide ? unsigned(raw[i]) >> 8 : unsigned(raw[i]) / 257u;
      v[i] = float(byte) / 255.0f;
    }
  } else if (!in->read_image(0, 0, 0, C, OIIO::TypeDesc::FLOAT, v.data())) {
    throw Error(path, "cannot decode image: " + in->geterror());
  }
  in->close();
  Image out(W, H, 3);
  for (size_t i = 0; i < out.pixels(); ++i) {
    const float* p = &v[i * size_t(C)];
    for (int c = 0; c < 3; ++c) out.data[3 * i + size_t(c)] = C >= 3 ? p[c] : p[0];
  }
  return out;
}

ImageComparison compare_images(const Image& ref, const Image& test, double ppd,
                               const std::string& ref_name, const std::string& test_name) {
  if (ref.width != test.width || ref.height != test.height)
    throw Error("compare", "images differ in size: " + ref_name + " is " +
                               std::to_string(ref.width) + "x" + std::to_string(ref.height) + ", " +
                               test_name + " is " + std::to_string(test.width) + "x" +
                               std::to_string(test.height));
  check_flip_ppd(ppd, ref.width, ref.height, "--ppd");
  ImageComparison c;
  c.width = ref.width;
  c.height = ref.height;
  c.ppd = ppd;
  c.psnr = psnr(test, ref);
  c.ssim = (ref.width >= 11 && ref.height >= 11) ? ssim(test, ref) : std::nan("");
  c.flip = flip(ref, test, ppd);
  return c;
}

ImageComparison compare_files(const std::string& ref_path, const std::string& test_path,
                              double ppd) {
  Image ref = read_ldr_rgb(ref_path), test = read_ldr_rgb(test_path);
  return compare_images(ref, test, ppd, ref_path, test_path);
}

Json comparison_json(const ImageComparison& c) {
  Json j;
  j["psnr"] = std::isinf(c.psnr) ? Json("inf") : Json(c.psnr);
  j["ssim"] = std::isnan(c.ssim) ? Json(nullptr) : Json(c.ssim);
  j["flip"] = c.flip;
  j["ppd"] = c.ppd;
  j["width"] = c.width;
  j["height"] = c.height;
  return j;
}

std::string comparison_text(const ImageComparison& c) {
  char buf[256];
  std::string psnr = std::isinf(c.psnr) ? "inf" : std::to_string(c.psnr);
  std::snprintf(buf, sizeof buf, "%.6f", c.psnr);
  if (!std::isinf(c.psnr)) psnr = buf;
  std::string ssim = "n/a (image smaller than 11x11)";
  if (!std::isnan(c.ssim)) {
    std::snprintf(buf, sizeof buf, "%.6f", c.ssim);
    ssim = buf;
  }
  std::snprintf(buf, sizeof buf, "%dx%d, ppd %.4f\n", c.width, c.height, c.ppd);
  std::string out = std::string("images  ") + buf;
  out += "psnr    " + psnr + " dB\n";
  out += "ssim    " + ssim + "\n";
  std::snprintf(buf, sizeof buf, "flip    %.6f\n", c.flip);
  out += buf;
  return out;
}

}  // namespace fovsim
