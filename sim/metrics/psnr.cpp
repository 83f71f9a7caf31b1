// MSE, PSNR and foveated PSNR (docs/architecture.md "Metrics"). Values are display-encoded, data
// range 1.
//
// FPSNR (Lee, Pattichis, Bovik 2002, "Foveated video quality assessment", IEEE TMM 4(1)):
//   f_c(e) = e2 ln(1/CT0) / (alpha (e + e2))   foveal cutoff frequency, cycles/degree
//   CT0 = 1/64 (minimal contrast threshold), alpha = 0.106 (spatial-frequency decay),
//   e2 = 2.3 deg (half-resolution eccentricity)
//   w(x) = min(f_c(e(x)), ppd(x) / 2)          clipped at the display's Nyquist frequency
//   FPSNR = 10 log10(1 / (sum_x w(x) err(x)^2 / sum_x w(x)))
#include <algorithm>
#include <cmath>

#include "sim/metrics/error_sums.h"
#include "sim/metrics/metrics.h"

namespace fovsim {

namespace {
constexpr double kCT0 = 1.0 / 64.0;
constexpr double kAlpha = 0.106;
constexpr double kE2 = 2.3;
}  // namespace

double fpsnr_weight(double ecc_deg, double ppd) {
  static const double kNum = kE2 * std::log(1.0 / kCT0) / kAlpha;
  const double fc = kNum / (std::max(ecc_deg, 0.0) + kE2);
  return std::min(fc, 0.5 * ppd);
}

double local_ppd(const Camera& cam, double px, double py) {
  // Direction through tan-plane point (u, v, -1). For the unit direction n, |dn/du| =
  // sqrt(1 + v^2) / (1 + u^2 + v^2) and |dn/dv| = sqrt(1 + u^2) / (1 + u^2 + v^2) (radians per
  // tan-plane unit); du/dpx = 2 tan_half_h / W, dv/dpy = 2 tan_half_v / H.
  const double u = (2.0 * px / cam.width - 1.0) * cam.tan_half_h;
  const double v = (1.0 - 2.0 * py / cam.height) * cam.tan_half_v;
  const double r2 = 1.0 + u * u + v * v;
  const double rad_per_px_h = (2.0 * cam.tan_half_h / cam.width) * std::sqrt(1.0 + v * v) / r2;
  const double rad_per_px_v = (2.0 * cam.tan_half_v / cam.height) * std::sqrt(1.0 + u * u) / r2;
  const double deg = kPi / 180.0;
  return 0.5 * (deg / rad_per_px_h + deg / rad_per_px_v);
}

double flip_ppd(const Camera& cam) {
  return local_ppd(cam, 0.5 * cam.width, 0.5 * cam.height);
}

double mse(const Image& a, const Image& b) {
  detail::check_same_size(a, b, "metrics.mse");
  detail::ErrorSums s = detail::error_sums(a, b, {});
  return s.sq / s.n;
}

double psnr(const Image& a, const Image& b) {
  detail::check_same_size(a, b, "metrics.psnr");
  return detail::psnr_from_mse(mse(a, b));
}

double fpsnr(const Image& a, const Image& b, const std::vector<float>& ecc_deg, const Camera& cam) {
  detail::check_same_size(a, b, "metrics.fpsnr");
  detail::check_ecc(a, ecc_deg, "metrics.fpsnr");
  detail::check_cam(a, cam, "metrics.fpsnr");
  detail::ErrorSumsRequest req;
  req.weighted = true;
  req.ecc = &ecc_deg;
  req.cam = &cam;
  detail::ErrorSums s = detail::error_sums(a, b, req);
  return detail::psnr_from_mse(s.w_sq / s.w);
}

}  // namespace fovsim
