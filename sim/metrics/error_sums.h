// Internal: one fused, deterministic pass over the per-pixel squared error that feeds MSE,
// FPSNR and the region/band RMSEs (so each formula lives in one place and the image is
// read once per frame). Not part of the public metrics contract.
#pragma once
#include <vector>

#include "sim/core/image.h"
#include "sim/display/display.h"

namespace fovsim {
namespace detail {

struct ErrorSumsRequest {
  bool weighted = false;  // accumulate FPSNR sums (needs ecc + cam)
  bool regions = false;   // fovea/periphery/band sums (needs ecc)
  double fovea_deg = 5.0;
  const std::vector<double>* band_edges = nullptr;  // strictly increasing
  const std::vector<float>* ecc = nullptr;
  const Camera* cam = nullptr;
  double ppd_scale = 1.0;  // ppd of the real display / ppd of `cam` (1 / render.scale)
};

struct ErrorSums {
  double sq = 0;           // sum over pixels of the channel-mean squared error
  double n = 0;            // pixel count
  double w_sq = 0, w = 0;  // FPSNR: sum w e^2, sum w
  double fovea_sq = 0, fovea_n = 0, periph_sq = 0, periph_n = 0;
  std::vector<double> band_sq, band_n;  // one per band [edges[i], edges[i+1])
};

// `where` names the public function for error messages ("metrics.mse").
void check_same_size(const Image& a, const Image& b, const char* where);
void check_ecc(const Image& a, const std::vector<float>& ecc, const char* where);
void check_cam(const Image& a, const Camera& cam, const char* where);

// Per-row partial sums in parallel (TBB), then a serial sum in row order: the result is
// bit-identical at any thread count.
ErrorSums error_sums(const Image& a, const Image& b, const ErrorSumsRequest& req);

// 10 log10(1 / m) with m a mean squared error on data range 1 (+inf when m == 0).
double psnr_from_mse(double m);

}  // namespace detail
}  // namespace fovsim
