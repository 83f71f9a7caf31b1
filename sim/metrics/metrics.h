// Image-quality metrics (docs/architecture.md "Metrics"), on display-encoded values in [0,1]. Each
// metric is declared once here and defined once in sim/metrics/*.cpp. Formulas and config keys:
// docs/metrics.md.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "sim/core/image.h"
#include "sim/core/named_values.h"
#include "sim/core/param_info.h"
#include "sim/core/params.h"
#include "sim/display/display.h"
#include "sim/metrics/flip.h"

namespace fovsim {

// All functions throw fovsim::Error("metrics.<name>", ...) when the two images differ in
// size or channel count, or an eccentricity map does not have width*height entries.
double mse(const Image& a, const Image& b);  // mean over all pixels and channels
// 10 log10(1 / MSE), data range 1. Returns +inf for identical images (no cap here;
// frames.csv writes it as "inf", see docs/metrics.md).
double psnr(const Image& a, const Image& b);
// SSIM (Wang et al. 2004) on Rec.709 luma: 11x11 Gaussian window sigma 1.5, K1 0.01, K2 0.03,
// population covariance; equals skimage structural_similarity(gaussian_weights=True,
// sigma=1.5, use_sample_covariance=False, data_range=1) (mean over the cropped valid region).
// Images smaller than 11x11 throw (as skimage does).
double ssim(const Image& a, const Image& b);
// The second image of ssim() prepared once (its luma and, over the valid region, G * y and
// G * y^2): ssim(a, prepared b) equals ssim(a, b) bit for bit, so a frame's reference serves
// every method's image. ssim_prepare throws as ssim() does (2 channels, smaller than 11x11);
// ssim(a, p) throws when a's size or channel count differs from the prepared image's.
struct SsimPrepared {
  int width = 0, height = 0, channels = 0;  // 0 until prepared
  std::vector<double> luma;                 // width * height
  std::vector<double> mu, mom2;             // (width - 10) * (height - 10), row-major
};
void ssim_prepare(const Image& b, SsimPrepared& out);
double ssim(const Image& a, const SsimPrepared& b);
// Foveated PSNR (Lee, Pattichis, Bovik 2002): per-pixel weight = cutoff frequency
// f_c(e) = e2 ln(1/CT0) / (alpha (e + e2)), CT0 = 1/64, alpha = 0.106, e2 = 2.3 deg,
// clipped at the local Nyquist frequency ppd/2 of the display.
// FPSNR = 10 log10(1 / (sum w e^2 / sum w)), e^2 = per-pixel squared error (channel mean).
double fpsnr(const Image& a, const Image& b, const std::vector<float>& ecc_deg, const Camera& cam);

// The FPSNR weight of one pixel: min(f_c(ecc_deg), ppd / 2), in cycles/degree.
double fpsnr_weight(double ecc_deg, double ppd);
// Local pixels per degree at pixel point (px, py): the analytic (h -> 0) limit of
// Camera::ppd_at (mean of the horizontal and vertical angular sampling rates of the
// rectilinear projection); cheap enough to evaluate per pixel.
double local_ppd(const Camera& cam, double px, double py);

struct MetricsConfig {
  // FovVideoVDP (Mantiuk et al. 2021): per-frame `fvvdp_q`, `fvvdp_jod`; summary `fvvdp_jod`
  // pooled over the run (sim/metrics/registry.h). Computed by the run engine through the
  // registry's SequenceMetric (fvvdp_sequence_metric, sim/metrics/fvvdp.h), not by
  // compute_metrics.
  bool fvvdp = true;
  bool fvvdp_foveated = true;  // foveated around the frame's true gaze (false: non-foveated)
  // Every metric also against `full` at the methods' own sampling rate (one sample per pixel of
  // the shared G-buffer, default lighting): `<metric>_fl`, the foveation loss alone, without
  // the 1-spp-vs-converged aliasing floor that the ground-truth columns include. Computed by
  // the run engine.
  bool foveation_loss = true;
  double fovea_deg = 5.0;                                    // fovea radius for rmse_fovea
  std::vector<double> band_edges_deg{0, 5, 10, 20, 30, 60};  // rmse_ecc_<a>_<b> columns
  // Not a config key: set by the runner to 1 / render.scale so FPSNR's Nyquist clip is that
  // of the real display even when the simulation runs at a reduced resolution.
  double ppd_scale = 1.0;
  // The per-frame metrics' toggles (each declared by its metric, sim/metrics/frame_metric.h:
  // `psnr`, `regions`, `flip`, `flip_images`, ...): on(key) is the value set, else the declared
  // default; a key no metric declares is an internal error.
  bool on(const std::string& key) const;
  void set(const std::string& key, bool value) { toggles[key] = value; }
  std::map<std::string, bool> toggles;  // the ones set (by the config or the caller)
  static MetricsConfig from_params(Params& p);
};
// The declaration of the `metrics` block's keys (parsing, defaults, ranges, docs).
const ParamTable<MetricsConfig>& metrics_config_table();

// Column name of the eccentricity band [a, b): "rmse_ecc_<a>_<b>", numbers printed
// shortest ("0", "5", "2.5" -> "2p5"); flip_band_column gives "flip_ecc_<a>_<b>".
std::string band_column(double a, double b);
std::string flip_band_column(double a, double b);

// The pixels per degree that drive FLIP in a run: local_ppd at the centre of the (simulated)
// image, i.e. of the pixels FLIP is given (docs/metrics.md, "FLIP").
double flip_ppd(const Camera& cam);

// State for the temporal error: frame-to-frame change of the error image in the periphery.
struct TemporalState {
  Image prev_error;  // signed error (test - ref), luma
  Image scratch;     // reused buffer for the current frame's error (no per-frame allocation)
  void reset() { prev_error = Image(); }
};

// Temporal error: RMS over peripheral pixels (ecc >= fovea_deg) of err_t - err_{t-1}, where
// err = luma(test) - luma(ref). NaN when `st` holds no previous error (first frame after
// reset, or a size change); always stores err_t into `st`.
double temporal_error(const Image& test, const Image& ref, const std::vector<float>& ecc_deg,
                      double fovea_deg, TemporalState& st);

// Scratch that compute_metrics reuses across calls (one per caller thread, e.g. per run cell):
// each per-frame metric's own (frame_metric.h: its preparation of the reference, made once and
// reused while the reference pixels are unchanged — every method of a frame shares it; checked
// by comparing the pixels, so it is never stale — and what it keeps of the last call, e.g.
// FLIP's error map for the error images).
struct FrameMetricScratch;
struct MetricsScratch {
  MetricsScratch();
  ~MetricsScratch();
  MetricsScratch(MetricsScratch&&) noexcept;
  MetricsScratch& operator=(MetricsScratch&&) noexcept;
  Image ref_pixels;  // the pixels the metrics' reference preparations were made from
  std::vector<std::unique_ptr<FrameMetricScratch>> per_metric;  // frame_metrics() order
};

// Computes every enabled per-frame metric (frame_metrics(), in that order) and returns them by
// column name: psnr, ssim, fpsnr, rmse_fovea, rmse_periphery, rmse_ecc_<a>_<b>, flip,
// flip_ecc_<a>_<b>, temporal_error (NaN on the first frame). Region RMSEs are over all
// channels of the pixels in the region; FLIP bands are the mean FLIP error of the band's
// pixels; an empty region is NaN. With `scratch`, a metric reuses its prepared reference and
// leaves what it keeps of the call there (FLIP: its error map); the numbers are the same with
// or without it. `same_test`: the scratch of another compute_metrics of the same test image
// against another reference, whose preparations of the test image a metric may reuse (FLIP's
// at flip_ppd(cam)); the numbers are the same with or without it.
// Metric values are not counters (counter_list.h): their columns depend on the config.
using MetricValues = NamedValues;
MetricValues compute_metrics(const MetricsConfig& cfg, const Image& test, const Image& ref,
                             const Camera& cam, const std::vector<float>& ecc_deg,
                             TemporalState* temporal, MetricsScratch* scratch = nullptr,
                             const MetricsScratch* same_test = nullptr);

}  // namespace fovsim
