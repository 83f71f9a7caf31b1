// `fovsim compare`: PSNR, SSIM and LDR-FLIP of one image pair read from files. The app only
// parses the arguments and prints what these functions return.
#pragma once
#include <string>
#include <vector>

#include "sim/core/image.h"
#include "sim/core/params.h"
#include "sim/metrics/fvvdp.h"

namespace fovsim {

// Reads an image file as display-encoded RGB in [0,1] the way the FLIP reference tool loads it
// (FLIP.md §1): 8-bit values v / 255; 16-bit values reduced to 8 bits (v >> 8) first; alpha
// dropped (not composited); grey copied to all three channels. Float files (EXR, ...) are read
// as they are. Throws fovsim::Error naming the path when the file is missing or unreadable.
Image read_ldr_rgb(const std::string& path);

// Peak memory of `fovsim compare` per pixel of the pair (both images, FLIP's prepared planes
// and workspace, the error map; measured with /usr/bin/time -v, bench/README.md "Memory:
// trace validate/stats and compare"):
// what the header check's message quotes beside max_image_pixels (files.h).
inline constexpr double kCompareBytesPerPixel = 140;

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

// ---- `fovsim compare --fvvdp`: FovVideoVDP v1.2 (Mantiuk et al. 2021) of an image pair or of
// two PNG sequences (docs/metrics.md, "FovVideoVDP").

// As read_ldr_rgb, with FovVideoVDP's decoding (FovVideoVDP.md §1): 16-bit values v / 65535,
// and a grey file stays one channel (Y = L).
Image read_fvvdp_image(const std::string& path);

// A PNG file (one frame) or a folder of PNG frames in name order. Throws fovsim::Error naming
// the path for a missing or empty folder or an unreadable file.
std::vector<std::string> frame_files(const std::string& path);

// "X,Y" in pixels from the top-left; throws fovsim::Error("--gaze", ...) when malformed.
std::pair<double, double> parse_gaze(const std::string& s);

// The frame rates FovVideoVDP accepts for a sequence (`compare --fps`): its temporal filters
// need more than 4 Hz (FovVideoVDP.md §4).
Range fvvdp_fps_range();

struct FvvdpCompareOptions {
  std::string display;     // a name from models/displays/ or a path
  std::string models_dir;  // where models/displays/ lives
  double fps = 0;          // 0 = not given (required for sequences)
  bool foveated = false;   // implied by a gaze
  bool has_gaze = false;
  double gaze_x = 0, gaze_y = 0;
  int torch_threads = kFvvdpTorchThreads;  // FvvdpOptions::torch_threads
};

struct FvvdpComparison {
  FvvdpResult result;
  FvvdpDisplay display;
  int width = 0, height = 0, frames = 0;
  double fps = 0;  // 0 for an image
  bool foveated = false;
  double gaze_x = 0, gaze_y = 0;           // the gaze used (foveated only)
  int torch_threads = kFvvdpTorchThreads;  // how the pooling sums were formed
};

// Names of the displays in models_dir/displays (sorted).
std::vector<std::string> display_names(const std::string& models_dir);
// Throws fovsim::Error located at "--display", "--fps", "--gaze" or the file for bad input:
// unknown display (the available ones listed), frame counts or sizes that differ, a sequence
// without --fps.
FvvdpComparison compare_fvvdp(const std::string& ref_path, const std::string& test_path,
                              const FvvdpCompareOptions& opt);
// {"fvvdp_jod", "q", "display", "display_name", "ppd", "y_peak", "y_black", "foveated", "gaze",
//  "frames", "fps", "mode", "width", "height", "bands": [{"rho_cpd", "q_sustained",
//  "q_transient"}]} (band values: §10 step 1, mean over frames).
Json fvvdp_comparison_json(const FvvdpComparison& c);
std::string fvvdp_comparison_text(const FvvdpComparison& c);

}  // namespace fovsim
