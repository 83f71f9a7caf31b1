// The metric registry: one declaration per image metric (its column, unit, better direction,
// how a run pools it, whether it is a headline metric). Every consumer reads it from here: the
// summary and its intervals, paired differences, the fidelity ladder, the convergence study,
// sweeps (iso-budget quality columns), the console summary, `fovsim info --json` and, through
// the run's manifest, the Python loaders and the plots (viz/common.py). Adding a metric is its
// file under sim/metrics/ plus one entry in registry.cpp (and, for a per-frame metric, its
// FrameMetric declaration in that file and one line in frame_metrics(); frame_metric.h).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "sim/core/image.h"
#include "sim/core/params.h"
#include "sim/display/display.h"

namespace fovsim {

struct MetricsConfig;

// ---- Sequence (stateful) metrics ----
// A metric whose value for a frame depends on the frames before it (FovVideoVDP's temporal
// channels) cannot be a function of one image pair. The run engine drives such a metric only
// through this interface, per cell: one reference stream per reference (the converged
// reference, `full` at the methods' sampling rate), pushed once per frame, and one test stream
// per method and reference. It names no metric: a new one is its file plus its registration.

// What a sequence metric is told once per run.
struct SequenceSetup {
  const Display* display = nullptr;  // the real display (photometry, geometry, refresh rate)
  int width = 0, height = 0;         // the simulated frames' size (render.scale applied)
  // > 0: consecutive pushes are a video at fps Hz; 0: every push is a still image (frames not
  // consecutive: frames.stride > 1, or --target units in random order).
  double fps = 0;
  const MetricsConfig* config = nullptr;
};

class SequenceReference {
 public:
  virtual ~SequenceReference() = default;
  // The next reference frame (display-encoded RGB in [0, 1]) and the true gaze in pixels from
  // the top-left of the frame (pixel centres at i + 0.5).
  virtual void push(const Image& ref, double gaze_x, double gaze_y) = 0;
  virtual void reset() = 0;  // forget the history: the next push is a first frame
};

class SequenceTest {
 public:
  virtual ~SequenceTest() = default;
  // Scores the next test frame against the reference's current frame (pushed first) and
  // returns the frame's value of the metric's `pooled_column`. With `heatmap` non-null, also
  // writes the frame's visualisation (RGB, frame size) there.
  virtual double push(const Image& test, const SequenceReference& ref, Image* heatmap) = 0;
  // push() of the test frame `same` (a test of the same metric, reset and pushed together with
  // this one) has just been pushed against `same_ref`: a metric may reuse same's work on the
  // test frame (FovVideoVDP: its luminance, temporal filtering and pyramids); the same value
  // as push(test, ref, heatmap), which is what this default does.
  virtual double push_same(const Image& test, const SequenceReference& ref, Image* heatmap,
                           const SequenceTest& same, const SequenceReference& same_ref) {
    (void)same;
    (void)same_ref;
    return push(test, ref, heatmap);
  }
  // push() of a test frame that the reference `frames_of` (of the same metric and setup) has
  // just been pushed: a metric may reuse its work on the frame; the same value as push(test,
  // ref, heatmap), which is what this default does.
  virtual double push_frames_of(const Image& test, const SequenceReference& ref, Image* heatmap,
                                const SequenceReference& frames_of) {
    (void)frames_of;
    return push(test, ref, heatmap);
  }
  virtual void reset() = 0;
};

struct SequenceMetric {
  bool (*enabled)(const MetricsConfig&) = nullptr;  // from the run's `metrics` block
  std::unique_ptr<SequenceReference> (*make_reference)(const SequenceSetup&) = nullptr;
  std::unique_ptr<SequenceTest> (*make_test)(const SequenceReference&) = nullptr;
  // What the run's manifest records under `manifest_key`, besides the engine's "mode", "fps"
  // and "why" (video or still images, and why).
  Json (*describe)(const SequenceSetup&) = nullptr;
  const char* manifest_key = "";
  // Frames after a (re)start before the metric's temporal filters have settled at `fps` (0:
  // still images, nothing to settle); the run leaves them out of the metric's means by default
  // (sim/experiment/startup.h). nullptr: 0.
  int (*settle_frames)(double fps) = nullptr;
  // Saved frames get `<label><heatmap_suffix>.png` (and `<label><heatmap_suffix>_fl.png`
  // against `full` at the same sampling); "" = no heat map.
  const char* heatmap_suffix = "";
  // Bytes one reference stream and one test stream of `setup` hold once they run, and the
  // working buffers of one push lent from a pool (one per push running at once) (the run
  // engine's memory estimate, docs/architecture.md "Memory"); nullptr: negligible.
  double (*reference_bytes)(const SequenceSetup&) = nullptr;
  double (*test_bytes)(const SequenceSetup&) = nullptr;
  double (*scratch_bytes)(const SequenceSetup&) = nullptr;
  // Whether a test stream fed by push_same or push_frames_of holds nothing of its own.
  bool borrowing_holds_nothing = false;
};

enum class Better { higher, lower };

// Suffix of a metric measured against `full` at the method's own sampling rate instead of the
// converged reference (metrics.foveation_loss): `psnr_fl`, `fvvdp_jod_fl`, `rmse_fovea_fl`, ...
// The foveation loss alone; the plain column is the loss against the ground truth.
inline constexpr const char* kFoveationLossSuffix = "_fl";

// How a configuration's per-frame values become its summary value.
enum class Pooling {
  // The mean of the per-frame values (PSNR, SSIM, FLIP, RMSEs); interval by batch means.
  frame_mean,
  // The per-frame column `pooled_column` holds a quantity whose mean over the frames is the
  // metric's pooled value before a monotone map `from_mean` (FovVideoVDP: per-frame Q, mean
  // over frames, then the JOD regression of Mantiuk et al. 2021 §11). The summary column is
  // from_mean(mean), its interval the batch-means interval of the mean mapped through
  // from_mean (asymmetric; `_ci95` is half its width), and a paired difference is the
  // difference of the pooled values with a batch-means interval over per-batch differences.
  sequence,
};

struct MetricDecl {
  std::string name;     // frames.csv / summary.csv column, or the prefix of a family
  bool family = false;  // name is a prefix: rmse_ecc_<a>_<b>, flip_ecc_<a>_<b>
  std::string unit;     // "dB", "1" (dimensionless), "JOD", "luma"
  std::string label;    // axis label for plots, e.g. "PSNR [dB]"
  Better better = Better::higher;
  Pooling pooling = Pooling::frame_mean;
  std::string pooled_column;              // Pooling::sequence: the per-frame column pooled
  double (*from_mean)(double) = nullptr;  // Pooling::sequence: pooled mean -> summary value
  // A stateful metric computed by the run engine through SequenceMetric (per frame it writes
  // `pooled_column` and `name` = from_mean(value)); nullptr: computed by compute_metrics.
  const SequenceMetric* sequence = nullptr;
  // Headline metrics are compared pairwise (paired.csv), shown in the console summary, the
  // fidelity ladder and the plots, and used as iso-budget quality columns.
  bool headline = false;
  // In the convergence study's stopping rule: none, within `--tol-db`, within `--tol-flip` (an
  // absolute tolerance on a [0, 1] metric) or within `--tol-jod`.
  enum class Tol { none, db, unit, jod } convergence_tol = Tol::none;
  // Its foveation-loss column (`<name>_fl`) is shown beside the headline metrics in the console
  // summary and the plots.
  bool show_fl = false;
  // Compared pairwise in paired.csv beside the headline metrics, with its foveation-loss column
  // (`<name>_fl`): the per-region errors a study reads, e.g. rmse_fovea_fl for the latency
  // what-if (docs/latency.md).
  bool paired = false;
  // printf precision of the metric in tables (console summary, fidelity report).
  int precision = 3;
  std::string cite;  // paper, author and year
  std::string doc;   // one line: what the value means
};

// Every image metric, in display order.
const std::vector<MetricDecl>& metric_registry();

// The declaration a column belongs to (exact name, or a family's prefix followed by the band
// suffix, each optionally followed by kFoveationLossSuffix); nullptr for a column that is not an
// image metric (costs, counters, parameters).
const MetricDecl* find_metric(const std::string& column);

// True when `column` is a foveation-loss column (ends in kFoveationLossSuffix and names a metric).
bool is_foveation_loss_column(const std::string& column);

// Headline metric names in registry order, then (with_fl) the `_fl` columns of those with
// show_fl.
std::vector<std::string> headline_metric_names(bool with_fl = false);

// The metrics paired.csv compares: headline_metric_names(true), then for every declaration
// with `paired` its name and its `_fl` column, in registry order.
std::vector<std::string> paired_metric_names();

// True when a larger value of `column` is better: the registry's direction for metrics; false
// (lower is better) for every other column (costs, times, counts).
bool higher_is_better(const std::string& column);

// The registry as JSON ([{"name", "family", "unit", "label", "better", "pooling",
// "pooled_column", "headline", "paired", "convergence_tol", "precision", "cite", "doc"}]): written
// into every run's manifest and by `fovsim info --json`, so viz and Python read the same list.
Json metric_registry_json();

}  // namespace fovsim
