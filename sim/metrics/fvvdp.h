// FovVideoVDP v1.2 (calibration "fvvdp_1_20"): Mantiuk, Denes, Chapiro, Kaplanyan, Rufo, Bachy,
// Lian, Patney, "FovVideoVDP: A Visible Difference Predictor for Wide Field-of-View Video", ACM
// TOG 40(4) 2021, implemented from the restatement in ../shared/metrics/FovVideoVDP.md, which
// follows the reference code (pyfvvdp v1.2.x) including the quirks that change numbers. Section
// numbers (§) below are that restatement's.
//
// Inputs are display-encoded sRGB images in [0,1] (fovsim::Image, 3 channels; the values a run
// compares). Output: JOD (10 = no visible difference). Per-pixel work is float32; every large
// sum is formed in a fixed order (the per-band pooling sum as the reference's float32 CPU
// kernel forms it, FvvdpOptions::torch_threads), so results are bit-identical at any thread
// count.
//
// A run scores N methods against one reference per frame: FvvdpReferenceStream holds the
// reference side of a frame (its temporal history, pyramid, adaptation luminance and CSF values,
// which depend on the reference and the gaze only) and is pushed once per frame;
// FvvdpTestStream holds one method's history and is pushed once per frame after the reference.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/image.h"
#include "sim/display/display.h"

namespace fovsim {

// What the metric needs of a display (§3).
struct FvvdpDisplay {
  std::string name;
  int width = 0, height = 0;  // native resolution, pixels
  double ppd = 0;             // pixels per degree at the centre (§3.2)
  double w_m = 0, h_m = 0;    // physical size, metres
  double d_m = 0;             // viewing distance, metres
  double y_peak = 0;          // cd/m²
  double y_black = 0;         // cd/m², including reflected ambient light (§3.1)

  // §3.1/§3.2 from the reference display database's keys. Exactly one of diagonal_inches > 0 or
  // fov_diagonal_deg > 0. contrast <= 0 and min_luminance <= 0 mean absent (C = 500).
  static FvvdpDisplay from_spec(const std::string& name, int width, int height,
                                double viewing_distance_m, double diagonal_inches,
                                double fov_diagonal_deg, double max_luminance, double contrast,
                                double min_luminance, double ambient_lux, double k_refl = 0.005);
  // The four entries of §3.3: standard_4k, standard_fhd, standard_hmd, htc_vive_pro. Throws
  // fovsim::Error for another name.
  static FvvdpDisplay standard(const std::string& name);
  // From a fovsim display: its geometry keys (viewing_distance_m with diagonal_inches or
  // fov_diagonal_deg) when given, else its FOV (w_m = 2 d tan(fov_h/2), d = viewing distance or
  // 3 m); its photometry keys.
  static FvvdpDisplay from_display(const Display& d);
  // The same physical display sampled at w x h pixels (ppd scales with w; §3.2 formula).
  FvvdpDisplay scaled_to(int w, int h) const;
  // "FovVideoVDP v1.2, 75.4 [pix/deg], Lpeak=200, Lblack=0.5979 [cd/m^2], non-foveated, (name)"
  std::string describe(bool foveated) const;
};

// Options of a stream. fps <= 0: every pushed frame is a still image (§5.1; no temporal
// channel). fps > 0: consecutive pushes are a video at fps Hz (§5.2; fps must give L >= 2 taps,
// i.e. fps > 4).
// How the per-band pooling sum of §10 (1) is accumulated. The reference computes it with
// torch.norm, whose CPU kernel (binary_kernel_reduce with NormOps) keeps a float32 accumulator
// and adds the pixels in row-major order, one chunk per thread. Where D is clamped at 1e4 on
// many pixels (low pixels per degree, large differences), the equal terms round the same way
// and the float32 sum drifts: 1e-3 to 2.6e-3 JOD on blurred 1440x1600 pairs on htc_vive_pro
// (docs/metrics.md, "Pooling precision"). `torch_threads` = N > 0 reproduces the reference run
// with N intra-op threads (N only matters for a still image: a video's D has one output per
// channel and frame, which torch reduces one by one); 0 sums in double, as the spec's
// float64 implementation does.
constexpr int kFvvdpTorchThreads = 1;    // the reference on one thread
constexpr int kFvvdpTorchGrain = 32768;  // at::internal::GRAIN_SIZE

struct FvvdpOptions {
  double fps = 0;
  bool foveated = false;
  int torch_threads = kFvvdpTorchThreads;
};

struct FvvdpBandState;  // per-band reference data (internal)
struct FvvdpFrames;     // a stream's luminance, temporal filtering and pyramids (internal)

class FvvdpReferenceStream {
 public:
  // `display` as the frames are sampled (use scaled_to for a simulation at render.scale < 1).
  // Frames pushed must be width x height (the display's resolution is not required: §1).
  FvvdpReferenceStream(const FvvdpDisplay& display, int width, int height, FvvdpOptions opt);
  ~FvvdpReferenceStream();
  FvvdpReferenceStream(FvvdpReferenceStream&&) noexcept;
  FvvdpReferenceStream& operator=(FvvdpReferenceStream&&) noexcept;

  // Pushes the next reference frame (display-encoded RGB or grey) with the gaze in pixels from
  // the top-left (used only when foveated; §3.4). Throws fovsim::Error on a size mismatch.
  void push(const Image& ref, double gaze_px_x, double gaze_px_y);
  // As push with the default gaze (⌊W/2⌋, ⌊H/2⌋).
  void push(const Image& ref);
  void reset();  // forget the history (the next push is frame 0)

  int frames() const { return frames_; }  // frames pushed since construction/reset
  int width() const { return W_; }
  int height() const { return H_; }
  int bands() const { return int(band_freq_.size()); }
  int channels() const { return video_ ? 2 : 1; }  // sustained (+ transient for video)
  bool video() const { return video_; }
  const std::vector<double>& band_frequencies() const { return band_freq_; }  // cpd (§6.1)
  const FvvdpDisplay& display() const { return disp_; }
  const FvvdpOptions& options() const { return opt_; }
  const std::vector<double>& temporal_sustained() const { return fs_; }
  const std::vector<double>& temporal_transient() const { return ft_; }
  // For tests: the last frame's adaptation luminance and sensitivity S of band b, channel c.
  const std::vector<float>& adaptation(int b) const;
  const std::vector<float>& sensitivity(int b, int c) const;

 private:
  friend class FvvdpTestStream;
  struct Impl;
  FvvdpDisplay disp_;
  FvvdpOptions opt_;
  int W_ = 0, H_ = 0;
  bool video_ = false;
  int frames_ = 0;
  std::vector<double> band_freq_, fs_, ft_;
  std::unique_ptr<Impl> impl_;
};

class FvvdpTestStream {
 public:
  explicit FvvdpTestStream(const FvvdpReferenceStream& ref);
  ~FvvdpTestStream();
  FvvdpTestStream(FvvdpTestStream&&) noexcept;
  FvvdpTestStream& operator=(FvvdpTestStream&&) noexcept;

  // Scores the next test frame against the reference's current frame (push the reference
  // first; the frame counts must then agree, else fovsim::Error). Returns this frame's Q_tc
  // (§10 step 3) and records it.
  double push(const Image& test, const FvvdpReferenceStream& ref);
  // push() of the test frame `same` has just been pushed (against another reference of the
  // same display, temporal filters and bands: metrics.foveation_loss's second reference), using
  // same's luminance, temporal filtering and pyramids of it instead of computing them again;
  // the same value as push(test, ref). Precondition: since their last reset() both streams
  // were given the same test frames (checked: frame counts, display and filters; where they
  // differ it is push(test, ref)). Once a stream has used another's frames it must keep doing
  // so until reset(): its own history is not kept (an InternalError otherwise).
  double push(const Image& test, const FvvdpReferenceStream& ref, const FvvdpTestStream& same,
              const FvvdpReferenceStream& same_ref);
  // push() of a test frame that the reference stream `frames_of` (of the same display and
  // filters as `ref`) has just been pushed: its luminance, temporal filtering and pyramids are
  // used (metrics.foveation_loss's floor: `full` scored against the reference while it is the
  // foveation-loss reference too). The same value as push(test, ref); where the streams differ
  // it is push(test, ref). The borrowing rule above applies.
  double push(const Image& test, const FvvdpReferenceStream& ref,
              const FvvdpReferenceStream& frames_of);
  void reset();

  int frames() const { return int(q_tc_.size()); }
  // Q[b][c] of the last frame (§10 step 1, without the transient weight), c = 0 sustained, 1
  // transient (0 for images).
  double q_band(int b, int c) const { return last_q_[size_t(b)][size_t(c)]; }
  const std::vector<std::array<double, 2>>& q_bands() const { return last_q_; }
  const std::vector<double>& q_per_frame() const { return q_tc_; }
  double mean_q() const;  // §10 step 4 over the frames pushed
  // Supra-threshold heat map of each pushed frame (off by default; costs one map per band):
  // the per-band D maps (transient x 0.25 added to the sustained) collapsed as a Laplacian
  // pyramid, then mapped to JOD-like units |jod_a| D^0.5916 (0 = no visible difference), as
  // the reference's heat maps (Mantiuk et al. 2021 reference code). 1 channel, frame size.
  void enable_heatmap(bool on) { heat_on_ = on; }
  const Image& heatmap() const { return heat_; }
  double jod() const;  // fvvdp_jod_from_q(mean_q())

 private:
  struct Impl;
  // The scoring of push(); `shared`: another stream's frames holding this test frame's planes.
  double score(const Image& test, const FvvdpReferenceStream& ref, const FvvdpFrames* shared);
  std::unique_ptr<Impl> impl_;
  std::vector<double> q_tc_;
  std::vector<std::array<double, 2>> last_q_;
  bool heat_on_ = false;
  bool borrowed_ = false;  // scored a frame with another stream's frame data since reset()
  Image heat_;
};

// JOD of a pooled Q (§10 step 4, §11): 10 − 0.0161713 · Q^0.5915616.
double fvvdp_jod_from_q(double mean_q);

struct FvvdpResult {
  double jod = 10;
  double mean_q = 0;  // mean over frames of Q_tc (§10 step 4)
  int frames = 0, bands = 0, channels = 1;
  std::vector<double> band_freq;                      // cpd
  std::vector<std::vector<std::array<double, 2>>> q;  // q[n][b][c] (§10 step 1)
  std::vector<double> q_tc;                           // per frame
  std::string display_line;                           // FvvdpDisplay::describe
};

// One-shot: test.size() == ref.size() frames; N = 1 is the still-image path (fps ignored), N >= 2
// a video at fps. gaze_px: empty (default gaze), one point for all frames, or one per frame.
FvvdpResult fvvdp(const std::vector<Image>& test, const std::vector<Image>& ref,
                  const FvvdpDisplay& display, double fps, bool foveated,
                  const std::vector<std::pair<double, double>>& gaze_px = {},
                  int torch_threads = kFvvdpTorchThreads);

// FovVideoVDP in a run: the registry's sequence-metric interface (sim/metrics/registry.h),
// registered in registry.cpp. Frames of the simulated size on the display scaled to it, the gaze
// of each frame when metrics.fvvdp_foveated; heat maps `<label>_fvvdp.png` (JOD-like units per
// pixel, colour ramp 0 .. 1).
struct SequenceMetric;
const SequenceMetric& fvvdp_sequence_metric();

// Internals exposed for the unit tests (spec sanity values).
namespace fvvdp_detail {
// §8.2 formula (without the sensitivity correction), omega in Hz, rho cpd, L cd/m², e degrees.
double csf_formula(double rho, double omega, double L, double e);
// §8.3 table lookup (without the correction); omega 0 or 5.
double csf_table(double rho, double omega, double L, double e);
int filter_length(double fps);
void temporal_taps(double fps, std::vector<double>& fs, std::vector<double>& ft);
// Frames after a (re)start until the sustained temporal filter (§5.2) has 95% of its weight on
// frames of the video instead of the replicated first frame: the smallest k with
// fs[0] + ... + fs[k] >= 0.95 (frames 0 .. k-1 are still settling). 15 frames (0.167 s) at
// 90 Hz; 0 for still images (fps <= 0).
int settle_frames(double fps);
std::vector<double> band_frequencies(int height, int width, double ppd);
// The sum of v[0..n) as torch.norm's CPU kernel forms it with `threads` intra-op threads
// (float32; chunks of ceil(n / min(threads, ceil(n / grain))) values, combined in order), or in
// double when threads == 0.
double torch_cpu_sum(const float* v, size_t n, int threads);
}  // namespace fvvdp_detail

}  // namespace fovsim
