// Fused squared-error pass behind MSE, PSNR, FPSNR and the region/band RMSEs.
#include "sim/metrics/error_sums.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <string>

#include "sim/core/error.h"
#include "sim/core/math.h"
#include "sim/metrics/metrics.h"

namespace fovsim {
namespace detail {

static std::string dims(const Image& a) {
  return std::to_string(a.width) + "x" + std::to_string(a.height) + "x" +
         std::to_string(a.channels);
}

void check_same_size(const Image& a, const Image& b, const char* where) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw Error(where, "images differ in size: " + dims(a) + " vs " + dims(b));
  if (a.empty()) throw Error(where, "empty image");
}

void check_ecc(const Image& a, const std::vector<float>& ecc, const char* where) {
  if (ecc.size() != a.pixels())
    throw Error(where, "eccentricity map has " + std::to_string(ecc.size()) +
                           " entries, image has " + std::to_string(a.pixels()) + " pixels");
}

void check_cam(const Image& a, const Camera& cam, const char* where) {
  if (cam.width != a.width || cam.height != a.height)
    throw Error(where, "camera is " + std::to_string(cam.width) + "x" + std::to_string(cam.height) +
                           ", image is " + std::to_string(a.width) + "x" +
                           std::to_string(a.height));
}

double psnr_from_mse(double m) {
  if (m <= 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(1.0 / m);
}

ErrorSums error_sums(const Image& a, const Image& b, const ErrorSumsRequest& req) {
  const int W = a.width, H = a.height, C = a.channels;
  const size_t nb = (req.regions && req.band_edges && req.band_edges->size() >= 2)
                        ? req.band_edges->size() - 1
                        : 0;
  // Per-row slots: sq, w_sq, w, fovea_sq, fovea_n, periph_sq, periph_n, then band sq/n pairs.
  const size_t K = 7 + 2 * nb;
  std::vector<double> rows(size_t(H) * K, 0.0);
  const double invC = 1.0 / C;
  const float* ecc = req.ecc ? req.ecc->data() : nullptr;
  const double* edges = nb ? req.band_edges->data() : nullptr;

  // FPSNR weight, factored per row/column (same formula as local_ppd and fpsnr_weight):
  //   ppd = 0.5 (deg/rate_h + deg/rate_v) = 0.5 deg r2 (A(v) + B(u)),
  //   A(v) = 1 / (kh sqrt(1+v^2)), B(u) = 1 / (kv sqrt(1+u^2)), r2 = 1 + u^2 + v^2.
  std::vector<double> col_u2, col_b;
  double kh = 0, kv = 0;
  const double deg = kPi / 180.0;
  if (req.weighted) {
    const Camera& cam = *req.cam;
    kh = 2.0 * cam.tan_half_h / cam.width;
    kv = 2.0 * cam.tan_half_v / cam.height;
    col_u2.resize(size_t(W));
    col_b.resize(size_t(W));
    for (int x = 0; x < W; ++x) {
      const double u = (2.0 * (x + 0.5) / cam.width - 1.0) * cam.tan_half_h;
      col_u2[size_t(x)] = u * u;
      col_b[size_t(x)] = 1.0 / (kv * std::sqrt(1.0 + u * u));
    }
  }

  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      double* s = &rows[size_t(y) * K];
      const float* pa = a.row(y);
      const float* pb = b.row(y);
      const float* er = ecc ? ecc + size_t(y) * size_t(W) : nullptr;
      double sq = 0, w_sq = 0, w = 0, f_sq = 0, f_n = 0, p_sq = 0, p_n = 0;
      double v2 = 0, row_a = 0;
      if (req.weighted) {
        const double v = (1.0 - 2.0 * (y + 0.5) / req.cam->height) * req.cam->tan_half_v;
        v2 = v * v;
        row_a = 1.0 / (kh * std::sqrt(1.0 + v2));
      }
      for (int x = 0; x < W; ++x) {
        double e2 = 0;
        for (int c = 0; c < C; ++c) {
          double d = double(pa[size_t(x) * C + c]) - double(pb[size_t(x) * C + c]);
          e2 += d * d;
        }
        e2 *= invC;
        sq += e2;
        if (req.weighted) {
          // Lee-Pattichis-Bovik 2002: weight = min(f_c(e), ppd/2) (docs/architecture.md "Metrics").
          const double ppd =
              0.5 * deg * (1.0 + col_u2[size_t(x)] + v2) * (row_a + col_b[size_t(x)]);
          const double wt = fpsnr_weight(er[x], ppd * req.ppd_scale);
          w_sq += wt * e2;
          w += wt;
        }
        if (req.regions) {
          const double e = er[x];
          if (e < req.fovea_deg) {
            f_sq += e2;
            f_n += 1;
          } else {
            p_sq += e2;
            p_n += 1;
          }
          for (size_t k = 0; k < nb; ++k) {
            if (e >= edges[k] && e < edges[k + 1]) {
              s[7 + 2 * k] += e2;
              s[8 + 2 * k] += 1;
              break;
            }
          }
        }
      }
      s[0] = sq;
      s[1] = w_sq;
      s[2] = w;
      s[3] = f_sq;
      s[4] = f_n;
      s[5] = p_sq;
      s[6] = p_n;
    }
  });

  // Serial sum in row order: deterministic regardless of how TBB split the rows.
  ErrorSums out;
  out.band_sq.assign(nb, 0.0);
  out.band_n.assign(nb, 0.0);
  for (int y = 0; y < H; ++y) {
    const double* s = &rows[size_t(y) * K];
    out.sq += s[0];
    out.w_sq += s[1];
    out.w += s[2];
    out.fovea_sq += s[3];
    out.fovea_n += s[4];
    out.periph_sq += s[5];
    out.periph_n += s[6];
    for (size_t k = 0; k < nb; ++k) {
      out.band_sq[k] += s[7 + 2 * k];
      out.band_n[k] += s[8 + 2 * k];
    }
  }
  out.n = double(a.pixels());
  return out;
}

}  // namespace detail
}  // namespace fovsim
