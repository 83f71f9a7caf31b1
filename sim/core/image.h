// Float images, interleaved channels, row 0 on top. Linear or display-encoded values;
// which one is stated by whoever produces the image.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace fovsim {

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> data;

  Image() = default;
  Image(int w, int h, int c, float fill = 0.f)
      : width(w), height(h), channels(c), data(size_t(w) * size_t(h) * size_t(c), fill) {}
  void resize(int w, int h, int c, float fill = 0.f) {
    width = w;
    height = h;
    channels = c;
    data.assign(size_t(w) * size_t(h) * size_t(c), fill);
  }
  size_t pixels() const { return size_t(width) * size_t(height); }
  bool empty() const { return data.empty(); }
  float* at(int x, int y) {
    return &data[(size_t(y) * size_t(width) + size_t(x)) * size_t(channels)];
  }
  const float* at(int x, int y) const {
    return &data[(size_t(y) * size_t(width) + size_t(x)) * size_t(channels)];
  }
  float* row(int y) { return at(0, y); }
  const float* row(int y) const { return at(0, y); }
};

// Luma (Rec. 709 weights) of an RGB image, or the single channel of a 1-channel image.
Image to_luma(const Image& rgb);

// Image I/O through OpenImageIO. PNG is written 8-bit (values clamped to [0,1]); EXR as float.
// Writes are atomic (temp file + rename). Throws fovsim::Error naming the path on failure.
void write_image(const std::string& path, const Image& img);
Image read_image(const std::string& path);

// Images are scored only when every value is finite: throws fovsim::Error(what, ...) naming
// the first pixel (x, y) and channel that holds a NaN or an infinity. `what` names the image
// ("frame 3: method \"kfr\" (label \"kfr\")", "frame 0: reference").
void check_finite_image(const Image& img, const std::string& what);

// Map a scalar image through a perceptually ordered colour ramp ('turbo'-like) in [lo, hi].
Image heatmap(const Image& scalar, float lo, float hi);

}  // namespace fovsim
