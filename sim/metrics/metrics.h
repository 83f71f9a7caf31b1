// Image-quality metrics (DESIGN §7), on display-encoded values in [0,1]. Each metric is
// defined once here, with its formula in metrics.cpp.
#pragma once
#include <string>
#include <vector>

#include "sim/core/counters.h"
#include "sim/core/image.h"
#include "sim/core/params.h"
#include "sim/display/display.h"

namespace fovsim {

double mse(const Image& a, const Image& b);   // mean over all pixels and channels
double psnr(const Image& a, const Image& b);  // 10 log10(1 / MSE), data range 1; +inf -> 100 cap? no: returns +inf if equal
// SSIM (Wang et al. 2004) on Rec.709 luma: 11x11 Gaussian window sigma 1.5, K1 0.01, K2 0.03,
// population covariance; equals skimage structural_similarity(gaussian_weights=True,
// sigma=1.5, use_sample_covariance=False, data_range=1) (mean over the cropped valid region).
double ssim(const Image& a, const Image& b);
// Foveated PSNR (Lee, Pattichis, Bovik 2002): per-pixel weight = cutoff frequency
// f_c(e) = e2 ln(1/CT0) / (alpha (e + e2)), CT0 = 1/64, alpha = 0.106, e2 = 2.3 deg,
// clipped at the local Nyquist frequency ppd/2 of the display.
double fpsnr(const Image& a, const Image& b, const std::vector<float>& ecc_deg, const Camera& cam);

struct MetricsConfig {
  bool psnr = true, ssim = true, fpsnr = true, regions = true, temporal = true;
  double fovea_deg = 5.0;                                  // fovea radius for rmse_fovea
  std::vector<double> band_edges_deg{0, 5, 10, 20, 30, 60};  // rmse_ecc_<a>_<b> columns
  static MetricsConfig from_params(Params& p);
};

// State for the temporal error: frame-to-frame change of the error image in the periphery.
struct TemporalState {
  Image prev_error;  // signed error (test - ref), luma
  void reset() { prev_error = Image(); }
};

// Computes every enabled metric and returns them by column name: psnr, ssim, fpsnr,
// rmse_fovea, rmse_periphery, rmse_ecc_<a>_<b>, temporal_error (NaN on the first frame).
Counters compute_metrics(const MetricsConfig& cfg, const Image& test, const Image& ref,
                         const Camera& cam, const std::vector<float>& ecc_deg, TemporalState* temporal);

}  // namespace fovsim
