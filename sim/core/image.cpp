// Image helpers and I/O through OpenImageIO (prefer a library for image I/O).
#include "sim/core/image.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/math.h"

namespace fovsim {

Image to_luma(const Image& rgb) {
  if (rgb.channels == 1) return rgb;
  Image out(rgb.width, rgb.height, 1);
  const size_t n = rgb.pixels();
  for (size_t i = 0; i < n; ++i) {
    const float* p = &rgb.data[i * size_t(rgb.channels)];
    out.data[i] = luma(p[0], p[1], p[2]);
  }
  return out;
}

namespace {

// True when the file at `p` is a complete image of its kind: a PNG ends with its IEND chunk
// (00 00 00 00 'IEND' AE 42 60 82), an EXR starts with its magic number and is not empty.
// Encoders through stdio may not report a short write on a full disk; this check does.
bool looks_complete(const std::string& p, bool is_exr) {
  std::FILE* f = std::fopen(p.c_str(), "rb");
  if (!f) return false;
  unsigned char buf[12] = {0};
  bool ok = false;
  if (is_exr) {
    ok = std::fread(buf, 1, 4, f) == 4 && buf[0] == 0x76 && buf[1] == 0x2f && buf[2] == 0x31 &&
         buf[3] == 0x01;
  } else if (std::fseek(f, -12, SEEK_END) == 0 && std::fread(buf, 1, 12, f) == 12) {
    static const unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    ok = std::equal(buf, buf + 12, iend);
  }
  std::fclose(f);
  return ok;
}

}  // namespace

void write_image(const std::string& path, const Image& img) {
  if (img.empty()) throw Error(path, "refusing to write an empty image");
  std::string ext = std::filesystem::path(path).extension().string();
  bool is_exr = ext == ".exr";
  // Written to a temporary name, checked, then renamed (files.h write_atomic): a full disk
  // never leaves a truncated or empty image under its final name.
  write_atomic(
      path,
      [&](const std::string& tmp) {
        auto out = OIIO::ImageOutput::create(tmp);
        if (!out) throw Error(path, "unsupported image format \"" + ext + "\" (use .png or .exr)");
        OIIO::ImageSpec spec(img.width, img.height, img.channels,
                             is_exr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
        // OIIO's EXR writer stamps the current time (capDate) unless DateTime is set: a
        // fixed value keeps the same config's files byte-identical between runs (the run's
        // time is in manifest.json).
        if (is_exr) spec.attribute("DateTime", "1970:01:01 00:00:00");
        if (!out->open(tmp, spec))
          throw Error(path, "cannot open image for writing: " + out->geterror());
        bool ok;
        if (is_exr) {
          ok = out->write_image(OIIO::TypeDesc::FLOAT, img.data.data());
        } else {
          std::vector<unsigned char> bytes(img.data.size());
          for (size_t i = 0; i < bytes.size(); ++i) {
            float v = img.data[i];
            v = std::isfinite(v) ? clamp01(v) : 0.f;
            bytes[i] = static_cast<unsigned char>(std::lround(v * 255.f));
          }
          ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
        }
        ok = out->close() && ok;
        if (!ok) throw Error(path, "image write failed: " + out->geterror());
      },
      [&](const std::string& tmp) -> std::string {
        return looks_complete(tmp, is_exr) ? "" : "image write incomplete (disk full?)";
      });
}

void check_finite_image(const Image& img, const std::string& what) {
  const size_t n = img.data.size();
  size_t i = 0;
  for (; i < n; ++i)
    if (!std::isfinite(img.data[i])) break;
  if (i == n) return;
  const size_t c = size_t(std::max(1, img.channels)), px = i / c;
  const size_t w = size_t(std::max(1, img.width));
  char b[200];
  std::snprintf(b, sizeof b,
                "pixel (%zu, %zu) channel %zu is %s: a non-finite image is never scored (check the "
                "scene's colours, lights and transforms, and the method's parameters)",
                px % w, px / w, i % c, std::isnan(img.data[i]) ? "NaN" : "infinite");
  throw Error(what, b);
}

Image read_image(const std::string& path) {
  check_input_file(path);  // a FIFO or device never blocks the decoder
  QuietStderr quiet;       // libpng's own error line: the thrown error says it once
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error(path, "cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  Image img(spec.width, spec.height, spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.data.data()))
    throw Error(path, "cannot decode image: " + in->geterror());
  in->close();
  return img;
}

// Polynomial fit of Google's Turbo colour map (Mikhailov 2019), public domain approximation.
static glm::vec3 turbo(float t) {
  t = clamp01(t);
  const glm::vec4 kr(0.13572138f, 4.61539260f, -42.66032258f, 132.13108234f);
  const glm::vec4 kg(0.09140261f, 2.19418839f, 4.84296658f, -14.18503333f);
  const glm::vec4 kb(0.10667330f, 12.64194608f, -60.58204836f, 110.36276771f);
  const glm::vec2 kr2(-152.94239396f, 59.28637943f), kg2(4.27729857f, 2.82956604f),
      kb2(-89.90310912f, 27.34824973f);
  glm::vec4 v4(1.f, t, t * t, t * t * t);
  glm::vec2 v2 = glm::vec2(v4.z, v4.w) * v4.z;
  return glm::clamp(
      glm::vec3(glm::dot(v4, kr) + glm::dot(v2, kr2), glm::dot(v4, kg) + glm::dot(v2, kg2),
                glm::dot(v4, kb) + glm::dot(v2, kb2)),
      0.f, 1.f);
}

Image heatmap(const Image& scalar, float lo, float hi) {
  Image out(scalar.width, scalar.height, 3);
  float inv = hi > lo ? 1.f / (hi - lo) : 0.f;
  for (size_t i = 0; i < scalar.pixels(); ++i) {
    float v = scalar.data[i * size_t(scalar.channels)];
    glm::vec3 c = turbo(std::isfinite(v) ? (v - lo) * inv : 1.f);
    out.data[3 * i] = c.r;
    out.data[3 * i + 1] = c.g;
    out.data[3 * i + 2] = c.b;
  }
  return out;
}

}  // namespace fovsim
