// `fovsim compare`: PSNR, SSIM and LDR-FLIP of one image pair read from files. The app only
// parses the arguments and prints what these functions return.
#pragma once
#include <string>

#include "sim/core/image.h"
#include "sim/core/params.h"

namespace fovsim {

// Reads an image file as display-encoded RGB in [0,1] the way the FLIP reference tool loads it
// (FLIP.md §1): 8-bit values v / 255; 16-bit values reduced to 8 bits (v >> 8) first; alpha
// dropped (not composited); grey copied to all three channels. Float files (EXR, ...) are read
// as they are. Throws fovsim::Error naming the path when the file is missing or unreadable.
Image read_ldr_rgb(const std::string& path);

struct ImageComparison {
  int width = 0, height = 0;
  double ppd = 0;   // pixels per degree FLIP used
  double psnr = 0;  // dB, +inf for identical images
  double ssim = 0;  // NaN when the image is smaller than SSIM's 11x11 window
  double flip = 0;  // mean of the LDR-FLIP map
};

// `ref_name` / `test_name` name the inputs in errors (file paths for compare_files).
// Throws fovsim::Error for a size mismatch or a ppd that is not finite and > 0.
ImageComparison compare_images(const Image& ref, const Image& test, double ppd,
                               const std::string& ref_name = "reference",
                               const std::string& test_name = "test");
ImageComparison compare_files(const std::string& ref_path, const std::string& test_path,
                              double ppd);

// {"psnr": ..., "ssim": ..., "flip": ..., "ppd": ..., "width": ..., "height": ...};
// +inf PSNR is the string "inf", a missing SSIM is null.
Json comparison_json(const ImageComparison& c);
// Human-readable lines "psnr  <dB>", "ssim  <v>", "flip  <v>" (6 decimals, as the FLIP tool).
std::string comparison_text(const ImageComparison& c);

}  // namespace fovsim
