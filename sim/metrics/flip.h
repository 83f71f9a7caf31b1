// LDR-FLIP (Andersson, Nilsson, Akenine-Moeller, Oskarsson, Aastroem, Fairchild, "FLIP: A
// Difference Evaluator for Alternating Images", HPG 2020), implemented from the restatement in
// ../shared/metrics/FLIP.md (which follows the reference code NVlabs/flip v1.6). Inputs are
// display-encoded sRGB images in [0,1]; the observer is one pixels-per-degree value.
// Arithmetic is float64 (FLIP.md §9: within ~1e-4 per pixel of the float32 reference tool).
#pragma once
#include <string>
#include <vector>

#include "sim/core/image.h"
#include "sim/core/params.h"

namespace fovsim {

// FLIP.md §2: the reference tool's default observer, 0.7 m from a 0.7 m wide 3840 px display:
// 3840 pi / 180 = 67.0206 pixels per degree.
double flip_default_ppd();

// The per-pixel LDR-FLIP error map E in [0,1] of `test` against `reference` (FLIP.md §7),
// written into `map` (resized to width x height x 1; its storage is reused between calls),
// and returns its unweighted mean (§8, accumulated in double, in row order: bit-identical at
// any thread count). 3- or 4-channel images use RGB (alpha dropped); 1-channel images are grey
// copied to RGB (§1). Throws fovsim::Error("metrics.flip", ...) for a size or channel mismatch,
// an empty image, or ppd not finite and > 0.
double flip(const Image& reference, const Image& test, double ppd, Image* map = nullptr);

// One image prepared for FLIP at one ppd (FLIP.md §7 steps 2-5 and 8): the Hunt-adjusted Lab of
// its CSF-filtered version and its edge/point magnitudes. Preparing a reference once and
// comparing several test images with it gives the same numbers as flip(ref, test, ppd).
struct FlipPrepared {
  int width = 0, height = 0;
  double ppd = 0;
  std::vector<double> L, A, B, edge, point;  // row-major, width * height
};
// Working planes of flip_prepare (3 doubles per pixel; the filtered planes stay in per-task row
// rings). Passing the same workspace every time (e.g. every frame of a run, for reference and
// test alike) avoids allocating them per call.
struct FlipWorkspace {
  std::vector<double> ycc[3];
};
// The largest pixels per degree FLIP accepts for a width x height image. FLIP's filter radii
// grow linearly with ppd (Andersson et al. 2020 §4.4 and §5.2: about 0.135 ppd pixels); a
// radius beyond max(64, the longer image side) only repeats clamped edge pixels at a cost of
// O(pixels x radius), so ppd is bounded there: max(64, max(width, height)) / 0.1351. Beyond it
// flip_prepare, flip and compare_images throw fovsim::Error naming the limit (no allocation
// or work sized by ppd happens first).
double flip_max_ppd(int width, int height);
// The pixels per degree FLIP accepts for any image (`compare --ppd`'s range): below its lower
// bound the CSF filters are narrower than a pixel's numerical floor and E is NaN.
Range flip_ppd_range();
// Throws fovsim::Error(where, ...) unless ppd is in flip_ppd_range() and <= flip_max_ppd(width,
// height).
void check_flip_ppd(double ppd, int width, int height, const std::string& where);
void flip_prepare(const Image& img, double ppd, FlipPrepared& out, FlipWorkspace* ws = nullptr);
// As flip() above on prepared images (same size, same ppd, else fovsim::Error).
double flip(const FlipPrepared& reference, const FlipPrepared& test, Image* map = nullptr);

// Internals exposed for the unit tests (FLIP.md §10 sanity values).
namespace flip_detail {
struct Kernels {
  int r_s = 0, r_f = 0;
  std::vector<double> y, cx, cz1, cz2;  // CSF taps (2 r_s + 1): Y', C_x, C_z's two Gaussians
  std::vector<double> g, d, s;          // feature taps (2 r_f + 1): Gaussian, edge, point
};
Kernels kernels(double ppd);
double c_max();  // largest compressed HyAB distance (green vs blue), FLIP.md §4.8
double srgb_to_linear_table(double c);  // §4.1 as flip_prepare evaluates it (interpolated table)
double lab_cube_root(double t);         // §4.6 cube root as flip_prepare evaluates it
}  // namespace flip_detail

// Colour-maps a FLIP error map ([0,1], 1 channel) with a magma-like ramp (black -> purple ->
// orange -> pale yellow), the colour map of the reference tool's error images. The ramp is a
// 6th-degree polynomial fit of matplotlib's "magma" (docs/metrics.md).
Image flip_colormap(const Image& map);

}  // namespace fovsim
