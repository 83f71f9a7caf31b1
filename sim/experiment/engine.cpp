#include "sim/experiment/engine.h"

#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <thread>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/hash.h"
#include "sim/core/limits.h"
#include "sim/core/memory_info.h"
#include "sim/core/param_table.h"
#include "sim/core/progress.h"
#include "sim/core/version.h"
#include "sim/core/watchdog.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/workload.h"
#include "sim/experiment/config.h"
#include "sim/experiment/frame_order.h"
#include "sim/experiment/gaze_source.h"
#include "sim/experiment/intervals.h"
#include "sim/experiment/jod_fidelity.h"
#include "sim/experiment/latency.h"
#include "sim/experiment/method_memo.h"
#include "sim/experiment/phase_times.h"
#include "sim/experiment/reference_cache.h"
#include "sim/experiment/run_config.h"
#include "sim/experiment/runner.h"
#include "sim/experiment/startup.h"
#include "sim/experiment/tracking_summary.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/frame.h"
#include "sim/foveation/simd_kernels.h"
#include "sim/metrics/metrics.h"
#include "sim/metrics/registry.h"
#include "sim/render/embree_device.h"
#include "sim/render/renderer.h"
#include "sim/trace/stats.h"
#include "sim/trace/trace.h"
#include "sim/trace/tracking.h"

namespace fovsim {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const std::vector<std::string>& per_cell_keys() {
  // Keys a cell reads for itself (Cell::parse); everything else is shared by the group and
  // enters reference_key. `workload` only changes the cost model's charges, never the images.
  static const std::vector<std::string> k = {"name",     "methods", "metrics",     "gpus",
                                             "outputs",  "comment", "description", "latency",
                                             "workload", "budget"};
  return k;
}

std::string reference_key(const Json& run_doc) {
  Json j = run_doc;
  if (j.is_object())
    for (auto& k : per_cell_keys()) j.erase(k);
  j.erase("sweep");
  return short_hash(j.dump());
}

namespace {

std::string iso_now() {
  std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

Json machine_info() {
  char host[256] = {0};
  ::gethostname(host, sizeof host - 1);
  // Code paths that ran (results do not depend on them; recorded for bug reports).
  return Json{{"hostname", host},
              {"hardware_threads", int(std::thread::hardware_concurrency())},
              {"embree_isa", embree_active_isa()},
              {"simd_path", simd_path_name(simd_path())}};
}

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct MethodRun {
  std::string label;
  std::string stem;  // safe_file_name(label): the only form of the label used in file names
  std::string method;
  std::unique_ptr<FoveationMethod> impl;
  std::unique_ptr<FoveationMethod> full;  // trace.on_invalid = full: rendered while lost
  bool was_full = false;                  // the previous frame was rendered by `full`
  TemporalState temporal;
  // This method's history in each sequence metric of the cell (Cell::seq, same order; e.g.
  // FovVideoVDP), and the same against `full` at the methods' sampling rate (foveation loss).
  std::vector<std::unique_ptr<SequenceTest>> seq, seq_fl;
  TemporalState temporal_fl;
  FrameOutput fo;  // reused every frame (its image keeps its storage)
  // The method memo (method_memo.h): `replay` holds this entry's whole sequence when an earlier
  // run computed it (the method is not run, its rows are built from it); else, with the memo
  // on, `rec` collects the sequence, stored under `memo_key` when the cell completes.
  std::optional<MemoEntry> replay;
  size_t replay_next = 0;
  std::unique_ptr<MemoEntry> rec;
  std::string memo_key;
};

struct ImageOutputs {
  std::set<int> frames;
  bool png = true, exr = false, debug = false;
};

// The images of one frame, queued while the methods run and written together at the end of
// the frame (write_all), in parallel: PNG compression is ~20 ms per image at the quickstart's
// resolution and ran serially on the frame-loop thread (bench/README.md "Scaling"). Each job
// owns a copy of its image, since the cell's display buffer is reused by the next method.
// Which file each image goes to does not depend on the order the jobs run in.
struct ImageJobs {
  std::vector<std::pair<std::string, Image>> jobs;
  void add(std::string path, Image img) { jobs.emplace_back(std::move(path), std::move(img)); }
  void write_all() {
    tbb::parallel_for(size_t(0), jobs.size(),
                      [&](size_t i) { write_image(jobs[i].first, jobs[i].second); });
    jobs.clear();
  }
};

void write_images(const std::string& dir, const std::string& stem, const Image& display_img,
                  const Image* linear, const ImageOutputs& io, ImageJobs& q) {
  if (io.png) q.add(dir + "/" + safe_file_name(stem) + ".png", display_img);
  if (io.exr && linear) q.add(dir + "/" + safe_file_name(stem) + ".exr", *linear);
}

Image error_heatmap(const Image& a, const Image& b) {
  Image e(a.width, a.height, 1);
  for (size_t i = 0; i < a.pixels(); ++i) {
    const float* p = &a.data[3 * i];
    const float* q = &b.data[3 * i];
    e.data[i] = std::fabs(luma(p[0], p[1], p[2]) - luma(q[0], q[1], q[2]));
  }
  return heatmap(e, 0.f, 0.25f);  // |luma error| 0 .. 0.25 mapped to the colour ramp
}

// Everything the references depend on, parsed once per group.
struct Shared {
  std::string models;
  uint64_t seed = 1;
  Display display, sim_display;
  double scale = 1;
  RenderSettings rs;
  std::unique_ptr<Scene> scene;  // the Renderer keeps a reference: stable address
  ToneMap tonemap;
  Trace trace;
  Trace raw_trace;               // before resampling: gaze at any time for the latency what-if
  TrackingPolicy tracking;       // trace.on_invalid (sim/trace/tracking.h)
  bool tracking_column = false;  // frames.csv `tracking`: a policy given or invalid frames
  int start = 0, stride = 1, count = 0;
  int warmup = 0;                // frames.warmup: rendered before `start`, not recorded
  bool include_startup = false;  // frames.include_startup (startup.h)
  double pixel_scale = 1;
  Json resolved;                 // resolved shared keys (for every cell's manifest)
  ReferenceCacheSettings cache;  // the `cache` block (reference_cache.h)
  Json scene_config;             // the resolved `scene` block (the reference cache's key)
  double memory_gb = 0;          // run.memory_gb (0: the option's, else the machine's)

  // Reads the shared keys in the order a single run reads them (the first error reported is
  // the same): display and render, scene and tone map, frame range, trace, the range's checks.
  void parse(Params& root, const std::string& cfg_file, const std::string& base_dir) {
    const RunSharedKeys top = run_shared_table().read(root);
    seed = uint64_t(top.seed);
    Params tp = parse_display_render(root);
    parse_scene(root, tp);
    // The frame range is read first so that only the part of the trace it uses is resampled
    // (a trace spanning 1e7 s with frames.count = 2 resamples 2 frames, not 1e7 s).
    Params fp = root.child("frames");
    const FramesBlock fb = frames_block_table().read(fp);
    start = fb.start;
    stride = fb.stride;
    count = fb.count;  // 0 = all available
    // Warm-up frames (frames.warmup): the first `warmup` frames of the range are rendered and
    // fed to every method (TWFR's cold first frame, temporal history) but not recorded; the
    // recorded frames, frames.count of them, follow.
    warmup = fb.warmup;
    include_startup = fb.include_startup;
    start += warmup * stride;
    parse_trace(root, base_dir, top.trace_placement);
    check_frame_range(fp, fb.on_short_trace);
    pixel_scale =
        double(display.width) * display.height / (double(sim_display.width) * sim_display.height);
    for (int k = 0; k < count && !tracking_column; ++k)
      tracking_column = !trace.samples[size_t(start + k * stride)].valid;
    {
      Params cp = root.child("cache");
      cache = ReferenceCacheSettings::from_params(cp);
    }
    {
      Params rp = root.child("run");
      memory_gb = run_block_table().read(rp).memory_gb;
    }
    scene_config = root.resolved().contains("scene") ? root.resolved()["scene"] : Json::object();
    (void)cfg_file;
  }

  // The display, the render block and the simulated display (render.scale, under
  // render.max_pixels). Returns render.tonemap, read after the scene (its exposure default).
  Params parse_display_render(Params& root) {
    display = Display::from_config(root, models);
    Params rp = root.child("render");
    const RenderBlock rb = render_block_table().read(rp);
    scale = rb.scale;
    rs = RenderSettings::from_params(rp);
    Params tp = rp.child("tonemap");
    sim_display = display.scaled(scale);
    // Images and G-buffers scale with the simulated pixel count: refuse before allocating.
    const double max_px = rb.max_pixels;
    const double px = double(sim_display.width) * double(sim_display.height);
    if (px > max_px)
      rp.fail("scale",
              "simulated resolution " + std::to_string(sim_display.width) + "x" +
                  std::to_string(sim_display.height) + " (" + format_number(px) +
                  " pixels) is over the limit render.max_pixels = " + format_number(max_px) +
                  " (lower render.scale or raise render.max_pixels)");
    return tp;
  }

  // The scene and the tone map (whose exposure defaults to the scene's).
  void parse_scene(Params& root, Params& tp) {
    Params sp = root.child("scene");
    scene = with_memory_context(
        root.where("scene"), "building the scene",
        "lower scene.complexity, use a coarser scene or lower scene.max_triangles",
        [&] { return std::make_unique<Scene>(make_scene(sp, models)); });
    ToneMapBlock tb;
    tb.exposure = scene->exposure;  // the default
    tonemap_block_table().read_into(tp, tb);
    tonemap.exposure = tb.exposure;
    const std::string& curve = tb.curve;
    tonemap.curve = curve == "aces"
                        ? ToneMap::Curve::Aces
                        : (curve == "reinhard" ? ToneMap::Curve::Reinhard : ToneMap::Curve::Clamp);
  }

  // The trace: loaded and resampled to the refresh rate over only the frames the run uses (the
  // raw trace is kept for the latency what-if), placed at the scene's default eye
  // (trace_placement "scene"), every head position within the coordinate bound.
  void parse_trace(Params& root, const std::string& base_dir, const std::string& placement) {
    const double needed_s =
        count > 0 ? (double(start) + double(count - 1) * stride + 2.0) / display.refresh_hz
                  : INFINITY;
    Params trp = root.child("trace");
    tracking_column = trp.has("on_invalid");  // else only when a recorded frame is invalid
    Trace raw_trace = with_memory_context(
        root.where("trace"), "reading and resampling the trace",
        "lower trace.max_samples, frames.count or the trace's length", [&] {
          Trace raw = load_trace(trp, display, base_dir, needed_s, &tracking);
          trace = resample(raw, display.refresh_hz,
                           raw.samples.empty() ? INFINITY : raw.samples.front().t + needed_s);
          return raw;
        });
    this->raw_trace = raw_trace;
    if (trace.samples.empty())
      throw Error(root.where("trace"), "trace has no samples after resampling");
    if (placement == "scene") {
      // The trace's first head position is placed at the scene's default eye (recordings use
      // their own world origin); orientation is kept as recorded.
      glm::dvec3 p0 = trace.samples.front().head_pos;
      for (auto& s : trace.samples) s.head_pos = glm::dvec3(scene->default_eye) + (s.head_pos - p0);
    }
    // The eye points the renderer traces from, within the bound `trace validate` applies.
    for (const auto& s : trace.samples)
      for (int c = 0; c < 3; ++c)
        if (!(std::fabs(s.head_pos[c]) <= kMaxCoordinateM)) {
          char b[160];
          std::snprintf(
              b, sizeof b,
              "head position %.6g m at t = %.6g s is beyond the coordinate "
              "bound +-1e5 m%s",
              s.head_pos[c], s.t,
              placement == "scene" ? " (after placing the trace at the scene's default eye)" : "");
          throw Error(root.where("trace"), b);
        }
  }

  // The frame range against the trace: past its end is an error; a range longer than the trace
  // is one too unless frames.on_short_trace = "truncate"; frames.count 0 takes all.
  void check_frame_range(Params& fp, const std::string& on_short) {
    int avail = int(trace.samples.size());
    if (start >= avail)
      fp.fail(warmup > 0 ? "warmup" : "start",
              "frame " + std::to_string(start) +
                  (warmup > 0 ? " (after " + std::to_string(warmup) + " warm-up frames)" : "") +
                  " is past the end of the trace (" + std::to_string(avail) + " frames at " +
                  format_number(display.refresh_hz) + " Hz)");
    int max_count = (avail - start + stride - 1) / stride;
    if (count == 0) count = max_count;
    if (count > max_count) {
      if (on_short == "fail")
        fp.fail("count", "trace is too short: " + std::to_string(count) +
                             " frames requested from frame " + std::to_string(start) +
                             " with stride " + std::to_string(stride) + ", only " +
                             std::to_string(max_count) +
                             " available (set frames.on_short_trace=\"truncate\" to accept)");
      count = max_count;
    }
  }
};

// The fidelity a run used and the bias the fidelity ladder (docs/fidelity.md, `fovsim
// fidelity` on the quickstart methods, top rung render.scale 0.5, 90 frames) measured for it:
// the largest |difference| of any method's mean from the top rung's. Rungs not measured say
// so; nothing is extrapolated.
Json fidelity_record(double scale, int stride, int spp, double display_ppd) {
  Json bias = nullptr;
  std::string note;
  struct Rung {
    double scale;
    double psnr_db, fpsnr_db, frame_time_pct, shaded_fraction;
  };
  // docs/fidelity.md, ladder table (scale rungs against the top rung 0.5).
  static const Rung rungs[] = {{0.125, 4.65, 4.58, 7.01, 0.125}, {0.25, 2.39, 2.35, 2.27, 0.040}};
  for (const Rung& r : rungs)
    if (std::fabs(scale - r.scale) < 1e-9)
      bias = Json{{"vs_render_scale", 0.5},
                  {"psnr_db", r.psnr_db},
                  {"fpsnr_db", r.fpsnr_db},
                  {"est_ms_total_percent", r.frame_time_pct},
                  {"shaded_fraction", r.shaded_fraction},
                  {"ranking_kept", false}};
  if (bias.is_object())
    note = "render.scale " + format_number(scale) +
           ": the fidelity ladder (docs/fidelity.md) measured mean biases up to " +
           format_number(bias["psnr_db"].get<double>()) + " dB PSNR, " +
           format_number(bias["est_ms_total_percent"].get<double>()) + "% frame time and " +
           format_number(bias["shaded_fraction"].get<double>()) +
           " shaded fraction against render.scale 0.5, with method rankings changed: a paired "
           "difference smaller than that may not hold at full resolution (check with `fovsim "
           "fidelity`)";
  else if (scale < 0.5)
    note = "render.scale " + format_number(scale) +
           " is below 0.5 and not a rung the fidelity ladder measured (docs/fidelity.md): its "
           "bias is unknown; measure it with `fovsim fidelity`";
  Json j{{"render_scale", scale},
         {"frames_stride", stride},
         {"reference_spp", spp},
         {"known_bias", bias},
         {"jod", jod_fidelity_record(scale, display_ppd)}};  // JOD against native resolution
  if (!note.empty()) j["note"] = note;
  return j;
}

// Values that are valid but probably not what was meant (printed as warnings, recorded in
// the manifest): an angle in degrees below 1 (phi_f = 0.17 reads as radians), image frames
// that are not frames of the run, an implausible trace (trace_stats: a map's "unit": "rad" on
// degrees gives head speeds of hundreds of deg/s). `shared`: also the shared keys' warnings.
std::vector<std::string> config_warnings(const Json& doc, const Params& root, const Shared& sh,
                                         const std::set<int>& image_frames, bool shared) {
  std::vector<std::string> w;
  if (doc.contains("methods") && doc["methods"].is_array()) {
    const Json& ms = doc["methods"];
    for (size_t i = 0; i < ms.size(); ++i) {
      if (!ms[i].is_object()) continue;
      for (auto it = ms[i].begin(); it != ms[i].end(); ++it) {
        const std::string& k = it.key();
        const bool angle = k == "phi_f" || k == "phi_0" ||
                           (k.size() > 4 && k.compare(k.size() - 4, 4, "_deg") == 0);
        if (!angle || !it.value().is_number()) continue;
        const double v = it.value().get<double>();
        if (v > 0 && v < 1)
          w.push_back(root.where("methods[" + std::to_string(i) + "]." + k) + ": " +
                      format_number(v) + " deg is below 1 degree: angles are in degrees (" +
                      format_number(v) + " rad would be " + format_number(v * 180 / M_PI) +
                      " deg)");
      }
    }
  }
  std::vector<std::string> outside;
  for (int f : image_frames) {
    const bool in =
        f >= sh.start && f < sh.start + sh.count * sh.stride && (f - sh.start) % sh.stride == 0;
    if (!in) outside.push_back(std::to_string(f));
  }
  if (!outside.empty()) {
    std::string list;
    for (size_t i = 0; i < outside.size() && i < 8; ++i) list += (i ? ", " : "") + outside[i];
    if (outside.size() > 8) list += ", ...";
    w.push_back(root.where("outputs.image_frames") + ": frame" + (outside.size() > 1 ? "s " : " ") +
                list + " not among the frames of this run (" + std::to_string(sh.start) + " to " +
                std::to_string(sh.start + (sh.count - 1) * sh.stride) + ", stride " +
                std::to_string(sh.stride) + "): no images written for " +
                (outside.size() > 1 ? "them" : "it"));
  }
  if (shared)
    for (auto& t : trace_stats(sh.raw_trace).warnings) w.push_back(root.where("trace") + ": " + t);
  return w;
}

// The reference side of one frame's measurements, once per group of cells whose `metrics`
// blocks agree (docs/architecture.md §2, "Memory"): the sequence metrics' reference streams
// (FovVideoVDP's temporal window and pyramids of the reference), `full` at the methods'
// sampling rate (metrics.foveation_loss) with its own streams, and the reference's floor. Every
// cell sharing it only reads it while its methods are measured (in parallel); per cell remain
// the methods' test streams.
//
// At render.spp 1 with `full`'s default lighting, `full` *is* the shared reference
// (image_is_reference): the foveation-loss reference is then the reference itself, aliased
// (fl_ref points at the tone-mapped reference; no second image, no second set of streams), and
// every `<metric>_fl` sequence value is the plain one (the same test against the same frames).
struct RefSide {
  std::string key;   // the resolved `metrics` block
  std::string file;  // the first cell's config file (location of the fl `full`'s Params)
  MetricsConfig mcfg, fl_mcfg;
  struct Seq {
    const MetricDecl* decl = nullptr;
    // Against the converged reference; against `full` at the methods' sampling rate (null when
    // aliased); `floor` scores that `full` against the converged reference (at_floor).
    std::unique_ptr<SequenceReference> ref, ref_fl;
    std::unique_ptr<SequenceTest> floor;
  };
  std::vector<Seq> seq;
  bool ready = false;
  bool video = true;  // consecutive frames at the refresh rate (describe_sequence_metrics)
  SequenceSetup setup;
  std::unique_ptr<FoveationMethod> fl_full;
  FrameOutput fl_fo;
  Image fl_display;
  const Image* fl_ref = nullptr;  // the foveation-loss reference: &fl_display or the reference
  int aliased = -1;               // -1 before the first frame; 1: fl_ref is the reference
  MetricsScratch floor_scratch;
  // The reference's floor: every metric of `full` at the methods' sampling rate against the
  // converged reference, per recorded frame (column -> frame -> value); summary `at_floor`
  // names the metrics a method cannot be told from it by (mark_reference_floor, runner.h).
  std::map<std::string, std::map<int, double>> floor_vals;
  int cells = 0;  // cells sharing it (memory estimate, manifest)

  const SequenceReference& ref_fl(size_t k) const {
    return seq[k].ref_fl ? *seq[k].ref_fl : *seq[k].ref;
  }
  bool fl_aliased() const { return aliased == 1; }

  // The sequence metrics' reference streams, made on the first frame.
  void begin(const Shared& sh) {
    if (ready) return;
    ready = true;
    setup.display = &sh.display;
    setup.width = sh.sim_display.width;
    setup.height = sh.sim_display.height;
    setup.fps = video ? sh.display.refresh_hz : 0.0;
    setup.config = &mcfg;
    for (auto& d : metric_registry())
      if (d.sequence && d.sequence->enabled(mcfg)) {
        Seq q;
        q.decl = &d;
        q.ref = d.sequence->make_reference(setup);
        seq.push_back(std::move(q));
      }
  }

  // Frame `fi`'s reference side: the streams pushed at the true gaze, then (foveation loss)
  // `full` at the methods' sampling rate, its streams and the floor. Phases go to `ph`.
  void frame(const Shared& sh, const Renderer& renderer, const FrameData& fd,
             const Image& ref_display, int fi, bool record, PhaseTimes& ph) {
    PhaseClock pc = PhaseClock::now();
    begin(sh);
    // The true gaze (also under the latency what-if), a screen point (pixel centres at i + 0.5).
    for (auto& q : seq) q.ref->push(ref_display, fd.gaze_px.x, fd.gaze_px.y);
    if (!seq.empty()) pc = ph.lap("metrics", pc);
    if (!mcfg.foveation_loss) return;
    if (!fl_full) {
      Params fp(Json{{"method", "full"}}, file, "metrics.foveation_loss");
      (void)fp.string("method");
      fl_full = make_method("full", fp);
    }
    FrameContext fctx = fd.context(*sh.scene, renderer, sh.sim_display, false);
    fl_fo.image_is_reference = false;
    fl_fo.counters.clear();
    fl_fo.debug.clear();
    fl_fo.flags.clear();
    render_with_lighting(*fl_full, fctx, fl_fo);
    const int is_ref = fl_fo.image_is_reference ? 1 : 0;
    FOVSIM_CHECK(aliased < 0 || aliased == is_ref,
                 "metrics.foveation_loss: `full` changed between being the reference and not");
    aliased = is_ref;
    if (fl_aliased()) {
      fl_ref = &ref_display;  // the same pixels as tonemap(fd.reference): no copy
    } else {
      sh.tonemap.apply(fl_fo.image, fl_display);
      fl_ref = &fl_display;
    }
    pc = ph.lap("methods", pc);
    if (!fl_aliased())
      for (auto& q : seq) {
        if (!q.ref_fl) q.ref_fl = q.decl->sequence->make_reference(setup);
        q.ref_fl->push(*fl_ref, fd.gaze_px.x, fd.gaze_px.y);
      }
    // The reference's floor: `full` at the methods' sampling rate against the reference.
    if (record) {
      MetricValues fl = compute_metrics(fl_mcfg, *fl_ref, ref_display, fd.camera, fd.eccentricity,
                                        nullptr, &floor_scratch);
      for (auto& [k, v] : fl.items()) floor_vals[k][fi] = v;
    }
    for (auto& q : seq) {
      if (!q.floor) q.floor = q.decl->sequence->make_test(*q.ref);
      const double v = q.floor->push(*fl_ref, *q.ref, nullptr);
      if (record) floor_vals[q.decl->pooled_column][fi] = v;
    }
    ph.lap("metrics", pc);
  }

  // Forget the frame history before a non-contiguous frame.
  void reset() {
    for (auto& q : seq) {
      q.ref->reset();
      if (q.ref_fl) q.ref_fl->reset();
      if (q.floor) q.floor->reset();
    }
    if (fl_full) fl_full->reset();
  }
};

// One cell: its methods, metrics, GPU profiles, outputs and accumulated rows.
struct Cell {
  const CellJob* job = nullptr;
  Watchdog* watchdog = nullptr;  // a method's frame taking far longer than its previous frames
  size_t watchdog_slot = 0;
  std::string name;
  std::vector<MethodRun> methods;
  MetricsConfig mcfg;
  std::vector<GpuProfile> gpus;
  double fit_level = kDefaultFitLevel;  // budget.p_fit
  Workload workload;
  ImageOutputs io;
  OutputsBlock outputs;  // the `outputs` block as read (run_config.h)
  bool print_table = false;
  uint32_t channels = 0;
  Json manifest;
  std::set<std::string> flags_seen;
  ResultTable frames;
  double cell_ms = 0;
  PhaseTimes phases;  // manifest "phases" (phase_times.h)
  Image out_display;  // per-cell scratch, reused every frame
  MetricsScratch metrics_scratch;
  ImageJobs image_jobs;  // this frame's images (want_images), written at the end of process()
  // Memoised methods' files of this frame (path, stored bytes), written after image_jobs.
  std::vector<std::pair<std::string, const std::string*>> memo_files;
  LatencyConfig latency;  // the latency what-if (docs/latency.md)
  std::set<std::string> metric_names;
  std::unique_ptr<GazeSource> gaze;  // the gaze each method sees (made by parse_group)
  // The reference side of the sequence metrics and the foveation-loss reference, shared with
  // the other cells of the group whose `metrics` block is the same (RefSide; made by
  // share_reference_sides before the first frame).
  RefSide* side = nullptr;
  MetricsScratch fl_scratch;
  // --target (intervals.h): each cell stops on its own once its targets hold, so its frames do
  // not depend on the other cells of its group (sweep batches and shards give the same cell).
  bool stopped = false, met = false;
  int used = 0, warmup = 0;
  std::vector<std::string> warnings;  // config_warnings(): manifest "warnings", printed by the CLI

  void parse(Params& root, const std::string& models, bool default_print) {
    RunCellKeys keys;
    keys.name = fs::path(job->file).stem().string();  // the default
    run_cell_table().read_into(root, keys);
    name = keys.name;
    std::set<std::string> labels;
    // Labels become image file names through safe_file_name (sim/core/files.h); two labels
    // that map to one name, or to the reference image's, are reported, never overwritten.
    std::map<std::string, std::string> stems{{"reference", "the reference image"}};
    channels = kShadingChannels;
    auto mps = root.children("methods");
    if (mps.empty())
      root.fail("methods", "at least one method is required, e.g. [{\"method\": \"full\"}]");
    for (size_t i = 0; i < mps.size(); ++i) {
      Params& mp = mps[i];
      MethodRun m;
      m.method = mp.string("method");
      m.label = mp.string("label", m.method);
      if (m.label.empty())
        mp.fail("label", "empty label (give the entry a name, or omit \"label\" for the method's)");
      if (!labels.insert(m.label).second)
        mp.fail("label",
                "duplicate label \"" + m.label + "\" (give each method entry a unique \"label\")");
      m.stem = safe_file_name(m.label);
      auto [st, fresh] = stems.insert({m.stem, "label \"" + m.label + "\""});
      if (!fresh)
        mp.fail(mp.has("label") ? "label" : "method",
                "label \"" + m.label + "\" would be written as the file name \"" + m.stem +
                    "\", as " + st->second +
                    " is (labels keep only [A-Za-z0-9._+-]; give it another label)");
      m.impl = make_method(m.method, mp);
      channels |= m.impl->required_channels();
      methods.push_back(std::move(m));
    }
    {
      Params mp = root.child("metrics");
      mcfg = MetricsConfig::from_params(mp);
    }
    for (auto& n : GpuProfile::names_from_config(root)) gpus.push_back(GpuProfile::load(n, models));
    {
      Params bp = root.child("budget");
      fit_level = budget_block_table().read(bp).p_fit;
    }
    // Workload descriptor for what the scene does not say (overdraw, bytes, flops per sample).
    workload = Workload::load(keys.workload, models);

    Params op = root.child("outputs");
    outputs.print_summary = default_print;  // the default
    outputs_block_table().read_into(op, outputs);
    for (double f : outputs.image_frames) io.frames.insert(int(f));
    io.png = outputs.png;
    io.exr = outputs.exr;
    io.debug = outputs.debug_images;
    print_table = outputs.print_summary;
    latency = LatencyConfig::from_params(root);
  }

  // What every stage of one frame of this cell reads (process() below).
  struct FrameIn {
    const Shared& sh;
    const FrameData& fd;
    const Image& ref_display;  // the reference, tone-mapped: every row is measured against it
    int fi;
    double ref_ms;
    bool record;       // false: a warm-up frame (state advances, no rows, no images)
    bool want_images;  // this frame is one of outputs.image_frames
    std::string img_dir;
    SceneFeatures features;
  };
  // What step_method produced for one method on one frame.
  struct Step {
    double lat_ms = 0;        // the end-to-end latency the method's gaze had (latency what-if)
    double sim_ms = 0;        // wall time of the method and its lighting
    std::string cost_method;  // the method costed (`full` while trace.on_invalid = full swaps)
    const FoveationMethod* impl = nullptr;  // the method that rendered (its declared passes)
    const Image* linear = nullptr;          // its linear image (or the reference's)
  };

  // This cell's work on one frame: per method the gaze (GazeSource), step_method, measure,
  // its images and build_rows; the images are written together at the end of the frame.
  // `record` false: a warm-up frame under --target or frames.warmup.
  void process(const Shared& sh, const Renderer& renderer, const FrameData& fd,
               const Image& ref_display, int fi, double ref_ms, bool record = true) {
    auto c0 = Clock::now();
    PhaseClock pc = PhaseClock::now();
    const bool want_images = record && io.frames.count(fi) > 0;
    const FrameIn in{sh,
                     fd,
                     ref_display,
                     fi,
                     ref_ms,
                     record,
                     want_images,
                     job->out_dir + "/images/frame_" + std::to_string(fi),
                     sh.scene->features()};
    if (want_images)
      write_images(in.img_dir, "reference", ref_display, &fd.reference, io, image_jobs);
    pc = phases.lap("images", pc);
    FrameContext ctx = fd.context(*sh.scene, renderer, sh.sim_display, want_images && io.debug);
    ctx.render_scale = sh.scale;  // methods size their filters and tiles in display pixels
    // The reference side (side->frame: sequence streams, foveation-loss reference, floor) was
    // computed for this frame before the cells ran.
    // Latency what-if and tracking loss: methods see the gaze source's gaze, metrics keep fd's
    // true gaze.
    gaze->begin_frame(fi, methods.size(), ctx);
    for (size_t mi = 0; mi < methods.size(); ++mi) {
      MethodRun& m = methods[mi];
      if (m.replay) {  // memoised: this frame's outputs from the method memo
        replay_method(in, mi, ctx);
        pc = phases.lap("cost_rows", pc);
        continue;
      }
      const Step st = step_method(in, mi, ctx, pc);
      std::vector<std::pair<std::string, Image>> heat;  // sequence metrics' heat maps
      const MetricValues metrics = measure(in, m, heat);
      pc = phases.lap("metrics", pc);
      const size_t queued = image_jobs.jobs.size();
      if (want_images) queue_method_images(in, m, *st.linear, heat);
      if (m.rec) record_frame(in, m, st, metrics, queued);
      pc = phases.lap("images", pc);
      build_rows(in, mi, st, ctx, metrics);
      pc = phases.lap("cost_rows", pc);
    }
    if (!image_jobs.jobs.empty() || !memo_files.empty()) {
      image_jobs.write_all();
      memo_images(in);
      pc = phases.lap("images", pc);
    }
    cell_ms += ms_since(c0);
  }

  // Method `mi` on this frame: its gaze, the method (or `full` while tracking is lost under
  // trace.on_invalid = full) with its lighting strategy, the frame's shared RSM counters, tone
  // mapping into out_display.
  Step step_method(const FrameIn& in, size_t mi, FrameContext& ctx, PhaseClock& pc) {
    const Shared& sh = in.sh;
    const FrameData& fd = in.fd;
    MethodRun& m = methods[mi];
    Step st;
    FrameOutput& fo = m.fo;  // cleared; fo.image keeps its storage (no per-frame allocation)
    fo.image_is_reference = false;
    fo.counters.clear();
    fo.debug.clear();
    fo.flags.clear();
    st.lat_ms = gaze->gaze_for(mi, fd, ctx);
    // trace.on_invalid = full: the method renders as `full` until tracking returns; its
    // temporal history restarts then (what it had is from before the loss).
    FoveationMethod* impl = m.impl.get();
    st.cost_method = m.method;
    if (gaze->tracked().render_full && m.method != "full") {
      if (!m.full) {
        Params fp(Json::object(), "trace.on_invalid");
        m.full = make_method("full", fp);
      }
      impl = m.full.get();
      st.cost_method = "full";
      m.was_full = true;
    } else if (m.was_full) {
      m.impl->reset();
      if (m.impl->lighting()) m.impl->lighting()->reset();
      m.was_full = false;
    }
    auto m0 = Clock::now();
    if (watchdog)
      watchdog->begin(watchdog_slot, "frame " + std::to_string(in.fi) + ", method \"" + m.method +
                                         "\" (label \"" + m.label + "\")");
    render_with_lighting(*impl, ctx, fo);  // the method + its lighting strategy (lighting.h)
    if (watchdog) watchdog->end(watchdog_slot);
    st.impl = impl;
    st.sim_ms = ms_since(m0);
    pc = phases.lap("methods", pc);
    const Image& lin = fo.image_is_reference ? fd.reference : fo.image;
    FOVSIM_CHECK(lin.width == sh.sim_display.width && lin.height == sh.sim_display.height &&
                     lin.channels == 3,
                 "method \"" + m.label + "\" produced an image of the wrong size");
    check_finite_image(lin, "frame " + std::to_string(in.fi) + ": method \"" + m.method +
                                "\" (label \"" + m.label + "\")");
    sh.tonemap.apply(lin, out_display);
    st.linear = &lin;
    pc = phases.lap("tonemap", pc);
    return st;
  }

  // The metrics of out_display (method `m`'s frame) against the reference, at the true gaze;
  // sequence metrics' pooled value and the metric of this frame alone (heat maps of the saved
  // frames into `heat`); with metrics.foveation_loss the same against `full` at the methods'
  // sampling rate.
  MetricValues measure(const FrameIn& in, MethodRun& m,
                       std::vector<std::pair<std::string, Image>>& heat) {
    const FrameData& fd = in.fd;
    const MetricValues image_metrics =
        compute_metrics(mcfg, out_display, in.ref_display, fd.camera, fd.eccentricity, &m.temporal,
                        &metrics_scratch);
    MetricValues metrics = image_metrics;
    const std::vector<RefSide::Seq>& seq = side->seq;
    std::vector<double> seq_q(seq.size());
    std::vector<size_t> seq_heat(seq.size(), SIZE_MAX);  // index into `heat`
    for (size_t k = 0; k < seq.size(); ++k) {
      const MetricDecl& d = *seq[k].decl;
      if (m.seq.size() <= k) m.seq.push_back(d.sequence->make_test(*seq[k].ref));
      const bool h = in.want_images && *d.sequence->heatmap_suffix;
      Image img;
      const double q = m.seq[k]->push(out_display, *seq[k].ref, h ? &img : nullptr);
      seq_q[k] = q;
      metrics.set(d.pooled_column, q);
      metrics.set(d.name, d.from_mean(q));
      if (h) {
        seq_heat[k] = heat.size();
        heat.emplace_back(m.stem + d.sequence->heatmap_suffix, std::move(img));
      }
    }
    if (mcfg.foveation_loss) {  // every metric against full at the same sampling rate
      if (side->fl_aliased()) {
        // The foveation-loss reference is the reference: the values above, but for
        // temporal_error (against the reference only; fl_mcfg has it off).
        for (auto& [k, v] : image_metrics.items())
          if (k != "temporal_error") metrics.set(k + kFoveationLossSuffix, v);
      } else {
        // The same test image: its FLIP preparation from the call above, when it made one.
        MetricValues fl = compute_metrics(
            side->fl_mcfg, out_display, *side->fl_ref, fd.camera, fd.eccentricity, &m.temporal_fl,
            &fl_scratch, metrics_scratch.flip_test_valid ? &metrics_scratch.flip_test : nullptr);
        for (auto& [k, v] : fl.items()) metrics.set(k + kFoveationLossSuffix, v);
      }
      for (size_t k = 0; k < seq.size(); ++k) {
        const MetricDecl& d = *seq[k].decl;
        const bool h = in.want_images && *d.sequence->heatmap_suffix;
        Image img;
        double q = seq_q[k];
        if (side->fl_aliased()) {
          // The foveation-loss reference is the reference: the same test against the same
          // frames (no second test stream per method).
          if (h) img = heat[seq_heat[k]].second;
        } else {
          if (m.seq_fl.size() <= k) m.seq_fl.push_back(d.sequence->make_test(side->ref_fl(k)));
          // The same test frame as m.seq[k]'s push above: its work on the frame is reused.
          q = m.seq_fl[k]->push_same(out_display, side->ref_fl(k), h ? &img : nullptr, *m.seq[k],
                                     *seq[k].ref);
        }
        metrics.set(d.pooled_column + kFoveationLossSuffix, q);
        metrics.set(d.name + kFoveationLossSuffix, d.from_mean(q));
        if (h)
          heat.emplace_back(m.stem + d.sequence->heatmap_suffix + kFoveationLossSuffix,
                            std::move(img));
      }
    }
    for (auto& f : m.fo.flags) flags_seen.insert(m.label + ":" + f);
    if (latency.enabled)
      for (auto& kv : metrics.items()) metric_names.insert(kv.first);
    return metrics;
  }

  // The images of method `m` on a saved frame: display and linear image, error and FLIP maps,
  // sequence metrics' heat maps, the method's debug buffers.
  void queue_method_images(const FrameIn& in, MethodRun& m, const Image& lin,
                           std::vector<std::pair<std::string, Image>>& heat) {
    write_images(in.img_dir, m.stem, out_display, &lin, io, image_jobs);
    if (outputs.error_images)
      image_jobs.add(in.img_dir + "/" + safe_file_name(m.stem + "_error") + ".png",
                     error_heatmap(out_display, in.ref_display));
    if (mcfg.flip && mcfg.flip_images)
      image_jobs.add(in.img_dir + "/" + safe_file_name(m.stem + "_flip") + ".png",
                     flip_colormap(metrics_scratch.flip_map));
    for (auto& [name, img] : heat)
      image_jobs.add(in.img_dir + "/" + safe_file_name(name) + ".png", std::move(img));
    for (auto& [dname, dimg] : m.fo.debug)
      image_jobs.add(in.img_dir + "/" + safe_file_name(m.stem + "_" + dname) + ".png",
                     std::move(dimg));
  }

  // One ResultRow per GPU profile for method `mi` on this frame (results/README.md): the cost
  // estimate (its first GPU's total is the gaze source's feedback), parameter and lighting
  // columns, gaze, latency and tracking columns, counters, est_ms_*, metrics, timings.
  void build_rows(const FrameIn& in, size_t mi, const Step& st, const FrameContext& ctx,
                  const MetricValues& metrics) {
    const Shared& sh = in.sh;
    const FrameData& fd = in.fd;
    const TraceSample& s = sh.trace.samples[size_t(in.fi)];
    MethodRun& m = methods[mi];
    const FrameOutput& fo = m.fo;
    for (auto& gpu : gpus) {
      CostInputs ci;
      ci.method = st.cost_method;
      ci.counters = &fo.counters;
      ci.passes = declared_passes(*st.impl);             // its cost passes and shared work
      ci.shared = fd.has_vpls ? &fd.counters : nullptr;  // the frame's RSMs
      ci.features = in.features;
      ci.display = sh.display;
      ci.pixel_scale = sh.pixel_scale;
      ci.workload = &workload;
      FrameCost cost = estimate_frame(gpu, ci);
      if (&gpu == &gpus.front()) gaze->feedback(mi, cost.total_ms);
      ResultRow row;
      row.set_text("config_id", gpus.size() > 1 ? m.label + "@" + gpu.name : m.label);
      row.set_text("method", m.method);
      row.set_text("label", m.label);
      row.set_text("gpu", gpu.name);
      for (auto& [pn, pv] : m.impl->param_columns()) row.set(pn, pv);
      for (auto& [pn, pv] : m.impl->text_param_columns()) row.set_text(pn, pv);
      if (fd.has_vpls && m.impl->lighting()) {  // lighting strategy columns (results/README.md)
        row.set_text("lighting", m.impl->lighting()->name());
        for (auto& [pn, pv] : m.impl->lighting()->param_columns()) row.set(pn, pv);
      }
      row.set("frame", in.fi);
      row.set("t", s.t);
      row.set("gaze_x", fd.gaze_px.x / sh.scale);  // pixels of the real display
      row.set("gaze_y", fd.gaze_px.y / sh.scale);
      row.set("gaze_valid", fd.gaze_valid ? 1 : 0);
      if (sh.tracking_column) row.set_text("tracking", gaze->tracked().state);  // docs/tracking.md
      if (latency.enabled) {  // results/README.md "Latency what-if"
        row.set_text("phase", gaze->phase());
        row.set("latency_ms", st.lat_ms);
        row.set("gaze_est_x", ctx.gaze_px.x / sh.scale);
        row.set("gaze_est_y", ctx.gaze_px.y / sh.scale);
        row.set("gaze_error_deg", angle_deg(fd.gaze_dir, ctx.gaze_dir));
        row.set("gaze_speed_deg_s", gaze->speed_deg_s());
      }
      double shaded = fo.counters.get(Counter::shaded_samples);
      row.set("shaded_samples", shaded * display_scale(Counter::shaded_samples, sh.pixel_scale));
      row.set("shaded_fraction", shaded / double(sh.sim_display.width * sh.sim_display.height));
      row.set("prims_submitted",
              fo.counters.get(Counter::prims_submitted, double(in.features.triangles)));
      row.set("prims_culled", fo.counters.get(Counter::prims_culled, 0.0));
      for (auto& [cn, cv] : fo.counters.items())
        if (const auto k = find_counter(cn); !k || !reported_by_row_builder(k->id)) row.set(cn, cv);
      for (auto& [cn, cv] : shared_counters(ci).items()) row.set(cn, cv);  // the frame's RSMs
      // A counter the cost model needed and the method did not fill (its pass was charged 0 or
      // a fallback) is a flag of the row, never silence (results/README.md).
      if (!cost.missing_counters.empty()) {
        std::string mc;
        for (const auto& n : cost.missing_counters) mc += (mc.empty() ? "" : ";") + n;
        row.set_text("missing_counters", mc);
        flags_seen.insert(m.label + ":missing_counters");
      }
      row.set("est_ms_total", cost.total_ms);
      if (cost.interval_level > 0) {  // the profile's prediction interval (docs/cost_model.md)
        row.set("est_ms_total_lo", cost.total_lo_ms);
        row.set("est_ms_total_hi", cost.total_hi_ms);
      }
      for (auto& pc : cost.passes) {
        row.set("est_ms_" + pc.pass, pc.ms);
        if (cost.interval_level > 0) {  // per-pass interval (docs/cost_model.md)
          row.set("est_ms_" + pc.pass + "_lo", pc.lo_ms);
          row.set("est_ms_" + pc.pass + "_hi", pc.hi_ms);
        }
      }
      for (auto& [mn, mv] : metrics.items()) row.set(mn, mv);
      row.set("ref_ms", in.ref_ms);
      row.set("sim_ms", st.sim_ms);
      if (in.record) frames.add(std::move(row));
    }
  }

  // The method memo's images of this frame: memoised methods' files written as stored, and the
  // files just written for the methods being recorded read back into their records.
  void memo_images(const FrameIn& in) {
    if (!memo_files.empty()) make_dirs(in.img_dir);
    for (auto& [path, bytes] : memo_files) write_file_atomic(path, *bytes);
    memo_files.clear();
    for (auto& m : methods)
      if (m.rec && !m.rec->frames.empty() && m.rec->frames.back().fi == in.fi)
        for (auto& [name, bytes] : m.rec->frames.back().images)
          if (bytes.empty()) bytes = read_file(in.img_dir + "/" + name);
  }

  // The method memo's record of method `m` on this frame: what build_rows reads and the images
  // queued for it (image_jobs from `queued` on).
  void record_frame(const FrameIn& in, MethodRun& m, const Step& st, const MetricValues& metrics,
                    size_t queued) {
    MemoFrame f;
    f.fi = in.fi;
    f.record = in.record;
    f.cost_method = st.cost_method;
    f.sim_ms = st.sim_ms;
    f.counters = m.fo.counters.items();
    f.metrics = metrics.items();
    f.flags = m.fo.flags;
    const size_t dir_len = in.img_dir.size() + 1;
    for (size_t i = queued; i < image_jobs.jobs.size(); ++i)  // read back once written
      f.images.emplace_back(image_jobs.jobs[i].first.substr(dir_len), std::string());
    m.rec->frames.push_back(std::move(f));
  }

  // A memoised method on this frame: its gaze (the gaze source's state and the row's gaze
  // columns), the stored counters, metrics, flags and images, and build_rows as when computed.
  void replay_method(const FrameIn& in, size_t mi, FrameContext& ctx) {
    MethodRun& m = methods[mi];
    FOVSIM_CHECK(m.replay_next < m.replay->frames.size() &&
                     m.replay->frames[m.replay_next].fi == in.fi &&
                     m.replay->frames[m.replay_next].record == in.record,
                 "method memo of \"" + m.label + "\" is out of step with the frame order");
    const MemoFrame& f = m.replay->frames[m.replay_next++];
    Step st;
    st.lat_ms = gaze->gaze_for(mi, in.fd, ctx);
    st.cost_method = f.cost_method;
    st.sim_ms = f.sim_ms;
    st.impl = m.impl.get();
    if (f.cost_method != m.method) {  // rendered as `full` while tracking was lost
      if (!m.full) {
        Params fp(Json::object(), "trace.on_invalid");
        m.full = make_method("full", fp);
      }
      st.impl = m.full.get();
    }
    m.fo.counters.clear();
    for (auto& [n, v] : f.counters) m.fo.counters.set_named(n, v);
    m.fo.flags = f.flags;
    MetricValues metrics;
    for (auto& [k, v] : f.metrics) metrics.set(k, v);
    for (auto& fl : m.fo.flags) flags_seen.insert(m.label + ":" + fl);
    if (latency.enabled)
      for (auto& kv : metrics.items()) metric_names.insert(kv.first);
    for (auto& [name, bytes] : f.images) memo_files.emplace_back(in.img_dir + "/" + name, &bytes);
    build_rows(in, mi, st, ctx, metrics);
  }

  // Forget the frame history (temporal methods, temporal_error) before a non-contiguous frame.
  void reset_temporal() {
    for (auto& m : methods) {
      m.impl->reset();
      if (m.impl->lighting()) m.impl->lighting()->reset();
      m.temporal.reset();
      for (auto& t : m.seq) t->reset();
      for (auto& t : m.seq_fl) t->reset();
      m.temporal_fl.reset();
    }
    gaze->reset();
  }
};

}  // namespace

namespace {
std::vector<CellResult> run_cells_impl(const std::vector<CellJob>& jobs, const EngineOptions& opt,
                                       GroupStats* stats);
}

std::string cache_growth_note(const std::vector<GroupStats>& stats) {
  std::string dir;
  double cap = 0, note_mb = -1;
  uint64_t bytes = 0;
  for (auto& g : stats) {
    if (g.cache_dir.empty()) continue;
    if (dir.empty()) dir = g.cache_dir;
    if (g.cache_dir != dir) continue;  // one folder per note (a sweep's groups share one)
    cap = g.cache_cap_gb;
    note_mb = note_mb < 0 ? g.cache_note_mb : std::min(note_mb, g.cache_note_mb);
    bytes += g.cache_bytes_written;
  }
  if (dir.empty()) return "";
  return cache_growth_note(dir, bytes, cap, uint64_t(std::max(note_mb, 0.0) * 1e6));
}

std::vector<CellResult> run_cells(const std::vector<CellJob>& jobs, const EngineOptions& opt,
                                  GroupStats* stats) {
  // Out of memory outside the scene and the trace (which say so themselves): the frames, whose
  // buffers scale with the simulated resolution and the number of cells run side by side.
  const std::string where = jobs.empty() ? std::string() : jobs.front().file + ": render.scale";
  const std::string what = "rendering and measuring " + std::to_string(jobs.size()) +
                           (jobs.size() == 1 ? " configuration's frames"
                                             : " cells side by side over one shared reference");
  return with_memory_context(where, what,
                             jobs.size() > 1
                                 ? "run fewer cells at once with `fovsim sweep --memory-budget "
                                   "GB` (or --batch N), or lower render.scale"
                                 : "lower render.scale, or run fewer methods at once",
                             [&] { return run_cells_impl(jobs, opt, stats); });
}

namespace {

// The manifest a cell starts with (status "running"; write_cell_outputs completes it).
Json cell_manifest(const CellJob& job, const Shared& sh, const Json& resolved,
                   const EngineOptions& opt) {
  Json manifest = Json{
      {"tool", "fovsim"},
      {"version", version_string()},
      {"git_commit", git_commit()},
      {"command_line", job.command_line},
      {"config_file", job.file},
      {"config", job.doc},
      {"resolved_config", resolved},
      {"seed", sh.seed},
      {"display", sh.display.to_json()},
      {"simulated_resolution", {sh.sim_display.width, sh.sim_display.height}},
      {"scene",
       {{"name", sh.scene->name},
        {"triangles", sh.scene->triangle_count()},
        {"features", sh.scene->features().to_json()}}},
      {"trace", {{"source", sh.trace.source}, {"samples", sh.trace.samples.size()}}},
      {"fidelity", fidelity_record(sh.scale, sh.stride, sh.rs.spp, jod_display_ppd(sh.display))},
      {"frames",
       {{"start", sh.start}, {"count", sh.count}, {"stride", sh.stride}, {"warmup", sh.warmup}}},
      {"machine", machine_info()},
      {"metrics", metric_registry_json()},  // the declarations viz and Python read
      {"threads", opt.threads > 0 ? opt.threads : int(tbb::info::default_concurrency())},
      {"start_time", iso_now()},
      {"status", "running"}};
  if (job.extra_manifest.is_object())
    for (auto it = job.extra_manifest.begin(); it != job.extra_manifest.end(); ++it)
      manifest[it.key()] = it.value();
  return manifest;
}

// Configuration: the first cell parses the shared keys (scene, trace, ...) into `sh`; every
// cell parses its own keys; Params::finish fails on any key nobody read. All cells are
// validated before any frame is computed.
std::vector<std::unique_ptr<Cell>> parse_group(const std::vector<CellJob>& jobs,
                                               const EngineOptions& opt, Shared& sh) {
  std::vector<std::unique_ptr<Cell>> cells;
  for (size_t ci = 0; ci < jobs.size(); ++ci) {
    const CellJob& job = jobs[ci];
    // Later cells read only their own keys (the shared ones were validated by the first).
    Json own = job.doc;
    if (ci > 0 && own.is_object())
      for (auto it = job.doc.begin(); it != job.doc.end(); ++it)
        if (std::find(per_cell_keys().begin(), per_cell_keys().end(), it.key()) ==
            per_cell_keys().end())
          own.erase(it.key());
    Params root(own, job.file);
    root.set_origins(job.origins);
    root.set_inherited(job.inherited);
    root.ignore("comment");
    root.ignore("description");
    auto cell = std::make_unique<Cell>();
    cell->job = &job;
    if (ci == 0) {
      // Same reading order as a single run, so the first error reported is the same.
      cell->name = root.string("name", fs::path(job.file).stem().string());
      sh.parse(root, job.file, job.base_dir);
      cell->parse(root, sh.models, opt.print_summary);
    } else {
      cell->parse(root, sh.models, opt.print_summary);
    }
    root.finish();  // any key nobody read is a typo: fail before computing anything
    cell->warnings = config_warnings(job.doc, root, sh, cell->io.frames, ci == 0);
    // FPSNR clips at the real display's Nyquist frequency (docs/metrics.md).
    cell->mcfg.ppd_scale = double(sh.display.width) / double(sh.sim_display.width);
    cell->gaze = std::make_unique<GazeSource>(cell->latency, sh.raw_trace, sh.trace, sh.tracking,
                                              sh.display);
    Json resolved = ci == 0 ? root.resolved() : sh.resolved;
    if (ci == 0) {
      sh.resolved = resolved;
    } else {
      for (auto& k : per_cell_keys()) {
        resolved.erase(k);
        if (root.resolved().contains(k)) resolved[k] = root.resolved()[k];
      }
    }
    cell->manifest = cell_manifest(job, sh, resolved, opt);
    if (!cell->warnings.empty()) cell->manifest["warnings"] = cell->warnings;
    cells.push_back(std::move(cell));
  }
  return cells;
}

// A cell in progress is marked so it never looks complete. Each folder is locked for the run
// (a second writer stops with an error naming the lock) and emptied of an earlier run's
// outputs, so a finished folder holds only this run's files (clear_run_outputs).
std::vector<std::unique_ptr<DirLock>> start_output_folders(
    const std::vector<std::unique_ptr<Cell>>& cells) {
  std::vector<std::unique_ptr<DirLock>> locks;
  for (auto& c : cells) {
    const std::string& out = c->job->out_dir;
    make_dirs(out);
    locks.push_back(std::make_unique<DirLock>(out, ".lock", "another fovsim run"));
    const bool earlier_run = path_kind(out + "/manifest.json") != PathKind::missing;
    // "running" replaces an old "complete" manifest before the old results go, so a kill in
    // between never leaves a manifest that claims files that are gone.
    write_file_atomic(out + "/manifest.json", c->manifest.dump(2) + "\n");
    clear_run_outputs(out, earlier_run);
  }
  return locks;
}

// The reference cache when both the caller and the config's cache.enabled want it; a cache
// without a folder is a warning (`no_cache_dir`), not an error.
std::unique_ptr<ReferenceCache> open_reference_cache(const EngineOptions& opt, Shared& sh,
                                                     std::string& no_cache_dir) {
  if (!opt.use_cache || !sh.cache.enabled) return nullptr;
  sh.cache.resolve_cap();  // the folder, and cache.max_gb 0 -> from the free disk space
  if (sh.cache.dir.empty()) {
    no_cache_dir =
        "reference cache: no folder (cache.dir, FOVSIM_CACHE_DIR, XDG_CACHE_HOME and HOME are "
        "unset): not used";
    return nullptr;
  }
  return std::make_unique<ReferenceCache>(sh.cache, *sh.scene, sh.scene_config, sh.sim_display,
                                          sh.rs);
}

// The frames of a run without --target in evaluation order (frame_order.h): (trace frame,
// recorded), the warm-up frames first.
std::vector<std::pair<int, bool>> memo_frame_list(const Shared& sh) {
  std::vector<std::pair<int, bool>> v;
  for (int k = -sh.warmup; k < sh.count; ++k) v.emplace_back(sh.start + k * sh.stride, k >= 0);
  return v;
}

// Hash of every file of the models folder (displays, GPU profiles, workloads, metric data):
// 35 small files, read once per run.
std::string models_hash(const std::string& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec)) files.push_back(it->path());
  std::sort(files.begin(), files.end());
  ContentHasher h;
  for (auto& f : files) {
    h.str(fs::relative(f, dir, ec).string());
    h.str(read_file(f.string()));
  }
  return hex64(h.value());
}

// Everything of cell `c` the key of each of its method entries holds besides the entry itself
// (method_memo.h).
Json memo_cell_base(const Cell& c, const Shared& sh, const ReferenceCache& rc,
                    const std::vector<std::pair<int, bool>>& frames, const std::string& models) {
  const Json& res = c.manifest["resolved_config"];
  auto get = [&](const char* k) { return res.contains(k) ? res[k] : Json(); };
  Json shared = res;
  for (auto& k : per_cell_keys()) shared.erase(k);
  shared.erase("cache");
  shared.erase("run");
  shared.erase("sweep");
  Json outputs = get("outputs");
  if (outputs.is_object()) outputs.erase("print_summary");
  ContentHasher fk;  // every frame's reference key: code, scene content, camera, pose, gaze
  for (auto& f : frames) {
    const TraceSample& s = sh.trace.samples[size_t(f.first)];
    fk.str(rc.key(f.first, s, Camera::from_pose(sh.sim_display, s.head_pos, s.head_rot)));
  }
  ContentHasher th;  // the trace as resampled and as read (latency what-if, tracking loss)
  for (const Trace* t : {&sh.raw_trace, &sh.trace}) {
    th.pod(uint64_t(t->samples.size()));
    for (const TraceSample& s : t->samples) {
      th.pod(s.t).pod(s.head_pos).pod(s.head_rot).pod(s.gaze_dir);
      th.pod(uint8_t(s.valid ? 1 : 0));
    }
  }
  Json fl = Json::array();
  for (auto& f : frames) fl.push_back(Json::array({f.first, f.second}));
  Json j{{"shared", shared},
         {"display", sh.display.to_json()},
         {"models", models},
         {"frames", fl},
         {"frame_keys", hex64(fk.value())},
         {"trace", hex64(th.value())},
         {"metrics", get("metrics")},
         {"latency", get("latency")},
         {"outputs", outputs}};
  if (c.latency.render_from_estimate) {  // the gaze follows the first GPU's cost estimate
    j["gpus"] = get("gpus");
    j["workload"] = get("workload");
  }
  return j;
}

// The method memo (method_memo.h) with the reference cache, except under --target: each
// method entry found in it is replayed, every other one recorded.
std::unique_ptr<MethodMemo> open_method_memo(const Shared& sh, const ReferenceCache* rc,
                                             std::vector<std::unique_ptr<Cell>>& cells,
                                             bool sampled) {
  if (!rc || sampled) return nullptr;
  auto memo = std::make_unique<MethodMemo>(sh.cache);
  const std::vector<std::pair<int, bool>> frames = memo_frame_list(sh);
  const std::string models = models_hash(sh.models);
  for (auto& c : cells) {
    const Json& ms = c->manifest["resolved_config"]["methods"];
    Json memoised = Json::array();
    if (ms.is_array() && ms.size() == c->methods.size()) {
      const Json base = memo_cell_base(*c, sh, *rc, frames, models);
      for (size_t mi = 0; mi < c->methods.size(); ++mi) {
        MethodRun& m = c->methods[mi];
        m.memo_key = MethodMemo::key(base, ms[mi]);
        m.replay = memo->load(m.memo_key, frames);
        if (m.replay)
          memoised.push_back(m.label);
        else
          m.rec = std::make_unique<MemoEntry>();
      }
    }
    c->manifest["memoised_methods"] = memoised;
  }
  return memo;
}

// The shared data of frame `fi` (prepare_frame), its reference from the cache when an earlier
// run computed it (then only G-buffer and VPLs are rendered).
void render_reference(Renderer& renderer, ReferenceCache* rcache, const Shared& sh, int fi,
                      uint32_t channels, const Camera* prev, FrameData& fd) {
  const TraceSample& s = sh.trace.samples[size_t(fi)];
  renderer.set_time(s.t);
  if (rcache) {
    const std::string key =
        rcache->key(fi, s, Camera::from_pose(sh.sim_display, s.head_pos, s.head_rot));
    FrameReference cached;
    if (rcache->load(key, sh.sim_display.width, sh.sim_display.height, cached)) {
      prepare_frame(renderer, sh.sim_display, s, fi, channels, prev, fd, &cached);
    } else {
      prepare_frame(renderer, sh.sim_display, s, fi, channels, prev, fd);
      rcache->store(key, fd);
    }
  } else {
    prepare_frame(renderer, sh.sim_display, s, fi, channels, prev, fd);
  }
}

// Whether any method of the group carries state from frame to frame (then --target keeps the
// trace order).
bool any_temporal(const std::vector<std::unique_ptr<Cell>>& cells, const Shared& sh) {
  bool temporal = false;
  for (auto& c : cells)
    for (auto& m : c->methods)
      temporal = temporal || m.impl->temporal() ||
                 (sh.scene->wants_indirect && m.impl->lighting() && m.impl->lighting()->temporal());
  return temporal;
}

// The reference sides (RefSide) of a group's cells: one per distinct resolved `metrics` block,
// in the order of each one's first cell.
std::string side_key(const Cell& c) {
  const Json& res = c.manifest["resolved_config"];
  return res.contains("metrics") ? res["metrics"].dump() : std::string();
}

std::vector<std::unique_ptr<RefSide>> share_reference_sides(
    const std::vector<std::unique_ptr<Cell>>& cells) {
  std::vector<std::unique_ptr<RefSide>> sides;
  for (auto& c : cells) {
    const std::string key = side_key(*c);
    RefSide* s = nullptr;
    for (auto& o : sides)
      if (o->key == key) s = o.get();
    if (!s) {
      sides.push_back(std::make_unique<RefSide>());
      s = sides.back().get();
      s->key = key;
      s->file = c->job->file;
      s->mcfg = c->mcfg;
      s->fl_mcfg = c->mcfg;
      s->fl_mcfg.temporal = false;  // temporal_error: against the reference only
    }
    ++s->cells;
    c->side = s;
  }
  return sides;
}

// Sequence metrics' mode (docs/metrics.md): a video of consecutive frames, else still images;
// recorded in each cell's manifest under the metric's key.
void describe_sequence_metrics(const std::vector<std::unique_ptr<Cell>>& cells, const Shared& sh,
                               bool shuffled) {
  const bool video = sh.stride == 1 && !shuffled;
  for (auto& c : cells) {
    c->side->video = video;
    SequenceSetup su;
    su.display = &sh.display;
    su.width = sh.sim_display.width;
    su.height = sh.sim_display.height;
    su.fps = video ? sh.display.refresh_hz : 0.0;
    su.config = &c->mcfg;
    for (auto& d : metric_registry()) {
      if (!d.sequence || !d.sequence->enabled(c->mcfg)) continue;
      Json j = d.sequence->describe(su);
      j["mode"] = video ? "video" : "image";
      j["fps"] = su.fps;
      j["why"] = video ? "consecutive frames at the display's refresh rate"
                 : sh.stride != 1
                     ? "frames.stride > 1: frames are not consecutive, each is a still image"
                     : "--target evaluates units in random order: each frame a still image";
      c->manifest[d.sequence->manifest_key] = j;
    }
  }
}

// What the group-level stages hand to write_cell_outputs.
struct GroupOutputs {
  const EngineOptions& opt;
  const FrameOrder& order;
  const ReferenceCache* rcache;
  const std::string& no_cache_dir;
  const Renderer& renderer;
  const PhaseTimes& group_phases;
  PhaseClock outputs_start;  // when the outputs stage began
  int threads;
  const MethodMemo* memo;
  const Json& memory;  // the pass's manifest "memory" record (MemoryPlan::record)
};

// The start-up frames the cell's means leave out (startup.h): each method's declared warm-up,
// each stateful metric's settle time at the run's frame rate.
StartupPlan startup_plan(const Cell& c, const Shared& sh) {
  StartupPlan p;
  p.include = sh.include_startup;
  p.warmup_rendered = sh.warmup;
  for (const MethodRun& m : c.methods) p.method_frames[m.label] = m.impl->warmup_frames();
  const double fps = c.side->video ? sh.display.refresh_hz : 0.0;  // as the streams ran
  for (auto& d : metric_registry()) {
    if (!d.sequence || !d.sequence->enabled(c.mcfg) || !d.sequence->settle_frames) continue;
    StartupPlan::Metric m;
    m.name = d.name;
    m.frames = d.sequence->settle_frames(fps);
    m.seconds = fps > 0 ? m.frames / fps : 0.0;
    for (const std::string& col : {d.pooled_column, d.name})
      m.columns.insert(m.columns.end(), {col, col + kFoveationLossSuffix});
    p.metrics.push_back(std::move(m));
  }
  return p;
}

// One cell's outputs, written atomically with the manifest ("complete") last: frames.csv,
// summary.csv (means with intervals, reference floor, latency phases, tracking states),
// paired.csv with the fidelity's known bias, summary.json; the --target record.
CellResult write_cell_outputs(Cell& c, const Shared& sh, const GroupOutputs& g) {
  const std::string& out = c.job->out_dir;
  CellResult r;
  r.out_dir = out;
  r.name = c.name;
  r.budget_ms = sh.display.frame_budget_ms();
  r.refresh_hz = sh.display.refresh_hz;
  r.print_summary = c.print_table;
  r.flags.assign(c.flags_seen.begin(), c.flags_seen.end());
  if (g.rcache) {  // entries found unusable (recomputed), a cache that could not be written
    for (auto& w : g.rcache->warnings()) c.warnings.push_back(w);
    if (g.memo)
      for (auto& w : g.memo->warnings()) c.warnings.push_back(w);
    if (!c.warnings.empty()) c.manifest["warnings"] = c.warnings;
  } else if (!g.no_cache_dir.empty()) {
    c.warnings.push_back(g.no_cache_dir);
    c.manifest["warnings"] = c.warnings;
  }
  r.warnings = c.warnings;
  if (c.manifest["fidelity"].contains("note"))
    r.fidelity_note = c.manifest["fidelity"]["note"].get<std::string>();
  r.fidelity = c.manifest["fidelity"];
  r.cell_ms = c.cell_ms;
  // The means leave out the start-up frames (startup.h; frames.csv keeps them).
  const StartupPlan plan = startup_plan(c, sh);
  StartupReport startup;
  const ResultTable means = exclude_startup(c.frames, plan, startup);
  c.manifest["startup"] = startup.manifest;
  FitRule fit;  // the budget decisions: budget.p_fit and each profile's interval
  fit.level = c.fit_level;
  for (auto& g : c.gpus) fit.intervals.emplace(g.name, g.interval);
  r.summary = summarize(means, r.budget_ms, &fit);
  mark_startup(r.summary, startup, plan);
  r.notes = startup.notes;
  for (auto& n : interval_notes(r.summary)) r.notes.push_back(n);
  if (c.mcfg.foveation_loss) mark_reference_floor(r.summary, means, c.side->floor_vals);
  if (c.latency.enabled) r.summary = summarize_phases(means, r.summary, c.metric_names);
  // Tracking states (docs/tracking.md): means with intervals per state, next to the phases.
  if (sh.tracking_column) r.summary = summarize_tracking(means, r.summary);
  if (g.order.sampled()) {  // what --target asked for and what it achieved (results/README.md)
    Json specs = Json::array(), achieved;
    for (auto& t : g.opt.targets) specs.push_back(t.spec);
    targets_met(g.opt.targets, c.frames, &achieved);
    r.target = {{"targets", specs},
                {"met", c.met},
                {"seed", sh.seed},
                {"order", g.order.shuffled() ? "random_units" : "trace"},
                {"unit_frames", g.order.unit_frames()},
                {"warmup_per_unit", kTargetWarmupFrames},
                {"frames_available", sh.count},
                {"frames_used", c.used},
                {"warmup_frames", c.warmup},
                {"achieved", achieved}};
    c.manifest["target"] = r.target;
  }
  // A JOD metric below native resolution: its bias (or that it has none measured) is said.
  const Json& jod = c.manifest["fidelity"]["jod"];
  bool has_jod = false;
  for (auto& row : r.summary.rows())
    has_jod = has_jod || !std::isnan(row.get("fvvdp_jod", NAN)) ||
              !std::isnan(row.get("fvvdp_jod_fl", NAN));
  if (has_jod && jod.contains("note"))
    r.fidelity_note += (r.fidelity_note.empty() ? "" : "; ") + jod["note"].get<std::string>();
  write_file_atomic(out + "/frames.csv", c.frames.to_csv());
  write_file_atomic(out + "/summary.csv", r.summary.to_csv());
  // Paired differences with the known bias of the run's fidelity (docs/intervals.md): a
  // difference whose interval excludes 0 but that is smaller than the bias is named.
  size_t n_below = 0;
  const ResultTable paired =
      with_fidelity_bias(paired_differences(means), c.manifest["fidelity"], &n_below);
  write_file_atomic(out + "/paired.csv", paired.to_csv());
  if (c.manifest["fidelity"]["known_bias"].is_object())
    c.manifest["fidelity"]["paired_real_below_bias"] = n_below;
  if (n_below > 0)
    r.fidelity_note += "; " + std::to_string(n_below) +
                       " paired difference(s) in paired.csv exclude 0 but are smaller than "
                       "that bias (paired.csv below_fidelity_bias = 1)";
  Json sj = Json::array();
  for (auto& row : r.summary.rows()) {
    Json o;
    for (auto& [k, v] : row.text) o[k] = v;
    for (auto& [k, v] : row.num) o[k] = std::isfinite(v) ? Json(v) : Json(format_number(v));
    sj.push_back(o);
  }
  Json summary{{"name", c.name}, {"budget_ms", r.budget_ms}, {"configs", sj}, {"flags", r.flags}};
  summary["fidelity"] = c.manifest["fidelity"];  // the fidelity used and its known bias
  write_file_atomic(out + "/summary.json", summary.dump(2) + "\n");
  // The methods' limitation flags (as summary.json), e.g. a size below a simulated pixel.
  c.manifest["flags"] = r.flags;
  c.manifest["status"] = "complete";
  c.manifest["end_time"] = iso_now();
  c.manifest["rays_traced"] = g.renderer.rays_traced();
  // How many frames' references came from the reference cache (reference_cache.h).
  c.manifest["reference_cache"] = g.rcache ? Json(g.rcache->manifest()) : Json{{"used", false}};
  if (g.rcache) c.manifest["reference_cache"]["used"] = true;
  // Method entries whose outputs came from the method memo (method_memo.h; their sim_ms is the
  // one recorded when they were computed).
  c.manifest["method_memo"] = g.memo ? Json(g.memo->manifest()) : Json{{"used", false}};
  if (g.memo) c.manifest["method_memo"]["used"] = true;
  if (!c.manifest.contains("memoised_methods")) c.manifest["memoised_methods"] = Json::array();
  PhaseTimes ph = g.group_phases;
  ph.merge(c.phases);
  ph.lap("outputs", g.outputs_start);  // this cell's output files so far (one cell: all of them)
  c.manifest["phases"] = ph.to_json(g.threads);
  // The memory budget, this cell's pass, the estimate and the process's peak resident memory
  // (ru_maxrss) so far (docs/architecture.md §2 "Memory").
  c.manifest["memory"] = g.memory;
  c.manifest["memory"]["peak_rss_bytes"] = double(peak_rss_bytes());
  write_file_atomic(out + "/manifest.json", c.manifest.dump(2) + "\n");
  r.frames = std::move(c.frames);
  return r;
}

// The memory estimate (docs/architecture.md §2 "Memory"), bytes, from the simulated size, the
// cells' methods and metrics, and the sequence metrics' windows. Calibrated against
// `/usr/bin/time -v` peaks (bench/README.md "Memory"); an estimate, not a bound.
struct MemoryEstimator {
  const Shared& sh;
  bool video = true;  // sequence metrics run as a video (their temporal window is held)
  double pixels() const { return double(sh.sim_display.width) * double(sh.sim_display.height); }
  double image() const { return 12 * pixels(); }  // RGB float
  double plane() const { return 4 * pixels(); }
  // At render.spp 1 `full` is the reference: the foveation-loss reference is aliased.
  bool aliased() const { return sh.rs.spp <= 1; }
  // Once per group: the frame's reference, direct light, G-buffer (up to ~16 floats a pixel)
  // and eccentricity, the tone-mapped reference, a saved frame's image jobs.
  double group() const { return 5 * image() + 17 * plane(); }
  // A MetricsScratch: its copy of the reference, SSIM's preparation, FLIP's of both images.
  double scratch(const MetricsConfig& m) const {
    return (m.ssim || m.flip ? image() : 0) + (m.ssim ? 5 * plane() : 0) +
           (m.flip ? 6 * image() : 0);
  }
  // One reference stream and one test stream of every sequence metric `m` enables.
  std::pair<double, double> sequence(const MetricsConfig& m) const {
    SequenceSetup su;
    su.display = &sh.display;
    su.width = sh.sim_display.width;
    su.height = sh.sim_display.height;
    su.fps = video ? sh.display.refresh_hz : 0.0;
    su.config = &m;
    double ref = 0, test = 0;
    for (auto& d : metric_registry())
      if (d.sequence && d.sequence->enabled(m)) {
        if (d.sequence->reference_bytes) ref += d.sequence->reference_bytes(su);
        if (d.sequence->test_bytes) test += d.sequence->test_bytes(su);
      }
    return {ref, test};
  }
  // A reference side (RefSide): the streams against the reference; with the foveation loss the
  // floor's test streams and scratch and, unless aliased, `full`'s images and streams.
  double side(const MetricsConfig& m) const {
    const auto [ref, test] = sequence(m);
    double b = ref;
    if (m.foveation_loss) {
      b += test + scratch(m);
      if (!aliased()) b += ref + 2 * image();
    }
    return b;
  }
  // A cell: its tone-mapped image and scratch; per method its image and working buffers,
  // temporal_error's two planes, its test streams (against `full` too unless aliased); rows.
  double cell(const Cell& c) const {
    const MetricsConfig& m = c.mcfg;
    const bool fl = m.foveation_loss && !aliased();
    const double test = sequence(m).second;
    double b = image() + scratch(m) + (fl ? scratch(m) : 0);
    const double per_method =
        3 * image() + (m.temporal ? 2 * plane() : 0) + test + (fl ? 5 * plane() : 0);
    b += double(c.methods.size()) * per_method;
    b += double(sh.count) * double(c.methods.size() * c.gpus.size()) * 4096;
    return b;
  }
};

// How a group's cells are split into passes under the memory budget (run_cells_impl).
struct MemoryPlan {
  double budget = INFINITY;  // bytes
  std::string budget_from;
  double resident = 0;  // resident memory when the plan was made (scene, trace, cells parsed)
  double group = 0;
  std::vector<double> cell;                 // per cell
  std::vector<std::vector<size_t>> passes;  // cell indices, in order

  // The manifest's "memory" record of pass `p`.
  Json record(size_t p, size_t sides_in_pass, double side_bytes, double seq_ref,
              const std::string& fl_reference) const {
    double pass_bytes = group + double(sides_in_pass) * side_bytes;
    for (size_t i : passes[p]) pass_bytes += cell[i];
    return Json{{"budget_bytes", std::isfinite(budget) ? Json(budget) : Json("unlimited")},
                {"budget_from", budget_from},
                {"passes", passes.size()},
                {"pass", p + 1},
                {"cells_in_pass", passes[p].size()},
                {"reference_sides", sides_in_pass},
                {"foveation_loss_reference", fl_reference},
                {"resident_at_start_bytes", resident},
                {"estimate_bytes",
                 {{"group", group},
                  {"reference_side", side_bytes},
                  {"sequence_reference", seq_ref},
                  {"cell", cell.empty() ? 0.0 : cell[passes[p].front()]},
                  {"pass", pass_bytes}}}};
  }
};

// The budget (--memory-budget, run.memory_gb, else 75% of MemAvailable) and the passes: cells
// in order, as many per pass as the estimate fits in what the budget leaves after the memory
// resident now and the group's shared data; at least one per pass.
MemoryPlan plan_memory(const EngineOptions& opt, const Shared& sh,
                       const std::vector<std::unique_ptr<Cell>>& cells,
                       const MemoryEstimator& est) {
  MemoryPlan p;
  if (opt.memory_budget_gb > 0) {
    p.budget = opt.memory_budget_gb * 1e9;
    p.budget_from = "--memory-budget";
  } else if (sh.memory_gb > 0) {
    p.budget = sh.memory_gb * 1e9;
    p.budget_from = "run.memory_gb";
  } else if (const uint64_t avail = available_memory_bytes(); avail > 0) {
    p.budget = 0.75 * double(avail);
    p.budget_from = "75% of MemAvailable";
  } else {
    p.budget_from = "unlimited (MemAvailable unreadable)";
  }
  p.resident = double(current_rss_bytes());
  p.group = est.group();
  const double room = p.budget - p.resident - p.group;
  std::vector<std::string> keys;  // the metrics blocks of the current pass (one side each)
  double used = 0;
  for (size_t i = 0; i < cells.size(); ++i) {
    p.cell.push_back(est.cell(*cells[i]));
    const std::string key = side_key(*cells[i]);
    const bool new_side = std::find(keys.begin(), keys.end(), key) == keys.end();
    const double cost = p.cell.back() + (new_side ? est.side(cells[i]->mcfg) : 0);
    if (p.passes.empty() || (used + cost > room && !p.passes.back().empty())) {
      p.passes.emplace_back();
      keys.clear();
      used = 0;
    }
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      keys.push_back(key);
      used += est.side(cells[i]->mcfg);
    }
    used += p.cell.back();
    p.passes.back().push_back(i);
  }
  return p;
}

// What every pass of a group shares (run_cells_impl, run_pass).
struct GroupRun {
  const std::vector<CellJob>& jobs;
  const EngineOptions& opt;
  Shared& sh;
  ReferenceCache* rcache;
  const std::string& no_cache_dir;
  const PhaseTimes& setup_phases;
  bool temporal;  // any method of the group is temporal (the frame order of every pass)
  const MemoryPlan& plan;
  const MemoryEstimator& est;
  GroupStats* stats;
};

// One pass of the frames over `cells` (docs/architecture.md §2): one reference per frame, the
// reference sides, each cell's process() in parallel, in FrameOrder; then write_cell_outputs.
void run_pass(const GroupRun& g, std::vector<std::unique_ptr<Cell>>& cells, size_t pass,
              std::vector<CellResult>& results) {
  const Shared& sh = g.sh;
  const EngineOptions& opt = g.opt;
  PhaseTimes group_phases = g.setup_phases;  // setup, reference, outputs (shared by the cells)
  uint32_t channels = kShadingChannels;
  for (auto& c : cells) channels |= c->channels;
  Renderer renderer(*sh.scene, sh.rs);
  // Slot 0: the frame's reference; slot 1 + i: cell i's methods (watchdog.h).
  Watchdog watchdog(cells.size() + 1, opt.watchdog);
  for (size_t i = 0; i < cells.size(); ++i) {
    cells[i]->watchdog = &watchdog;
    cells[i]->watchdog_slot = i + 1;
  }
  FrameData fd;
  Image ref_display;
  std::optional<Camera> prev_cam;
  const std::string of_passes =
      g.plan.passes.size() > 1
          ? ", pass " + std::to_string(pass + 1) + "/" + std::to_string(g.plan.passes.size())
          : std::string();
  // Frames of the group, warm-up frames included (progress.h; inside a sweep's or a
  // ladder's progress this is its innermost level).
  Progress progress(
      (cells.size() > 1 ? "frames x " + std::to_string(cells.size()) + " cells" : "frames") +
          of_passes,
      size_t(sh.count + sh.warmup));
  progress.phase("frames");
  double ref_total = 0;
  auto do_frame = [&](int k, bool record) {
    int fi = sh.start + k * sh.stride;
    auto t0 = Clock::now();
    PhaseClock rpc = PhaseClock::now();
    watchdog.begin(0, "frame " + std::to_string(fi) + ", reference rendering");
    render_reference(renderer, g.rcache, sh, fi, channels, prev_cam ? &*prev_cam : nullptr, fd);
    watchdog.end(0);
    check_finite_image(fd.reference, "frame " + std::to_string(fi) + ": reference");
    sh.tonemap.apply(fd.reference, ref_display);
    double ref_ms = ms_since(t0);
    group_phases.lap("reference", rpc);
    ref_total += ref_ms;
    std::vector<Cell*> active;
    std::vector<RefSide*> active_sides;
    for (auto& c : cells)
      if (!c->stopped) {
        active.push_back(c.get());
        ++(record ? c->used : c->warmup);
        if (std::find(active_sides.begin(), active_sides.end(), c->side) == active_sides.end())
          active_sides.push_back(c->side);
      }
    // The reference side of the frame, once per group of cells sharing it.
    for (RefSide* s : active_sides)
      s->frame(sh, renderer, fd, ref_display, fi, record, group_phases);
    if (active.size() == 1) {
      active[0]->process(sh, renderer, fd, ref_display, fi, ref_ms, record);
    } else {
      // Cells are independent (own methods, state, scratch); each row list stays in order.
      tbb::parallel_for(tbb::blocked_range<size_t>(0, active.size(), 1),
                        [&](const tbb::blocked_range<size_t>& r) {
                          for (size_t i = r.begin(); i != r.end(); ++i)
                            active[i]->process(sh, renderer, fd, ref_display, fi, ref_ms, record);
                        });
    }
    prev_cam = fd.camera;
    progress.step();
  };
  // Evaluation order (frame_order.h): the trace order; under --target, seeded random units
  // (trace order with a temporal method of the group) until every cell's targets hold; each
  // cell stops on its own, so its frames do not depend on the other cells of its group or pass.
  const bool sampled = !opt.targets.empty();
  std::vector<std::unique_ptr<RefSide>> sides = share_reference_sides(cells);
  FrameOrder order(sh.count, sh.warmup, sampled, !g.temporal, sh.seed);
  describe_sequence_metrics(cells, sh, order.shuffled());
  std::unique_ptr<MethodMemo> memo = open_method_memo(sh, g.rcache, cells, sampled);
  FrameOrder::Steps steps;
  steps.frame = do_frame;
  steps.discontinuity = [&] {
    for (auto& s : sides) s->reset();
    for (auto& c : cells) c->reset_temporal();
    prev_cam.reset();
  };
  steps.unit_done = [&](int units_done) {
    bool all = true;
    for (auto& c : cells) {
      if (c->stopped) continue;
      c->met = targets_met(opt.targets, c->frames, nullptr);
      if (units_done >= kTargetMinUnits && c->met) c->stopped = true;
      all = all && c->stopped;
    }
    return all;
  };
  order.run(steps);
  progress.phase("outputs");
  if (memo) {  // the cells completed: their computed method entries go to the memo
    for (auto& c : cells)
      for (auto& m : c->methods)
        if (m.rec) memo->store(m.memo_key, *m.rec);
    if (g.stats) g.stats->cache_bytes_written += memo->disk().stats().bytes_written;
  }

  // ---- outputs (atomic; manifest "complete" last) ----
  const MetricsConfig& m0 = cells.front()->mcfg;
  const std::string fl_reference = !m0.foveation_loss            ? "off"
                                   : sides.front()->fl_aliased() ? "the reference"
                                                                 : "full at 1 spp";
  const Json memory =
      g.plan.record(pass, sides.size(), g.est.side(m0), g.est.sequence(m0).first, fl_reference);
  const int threads = opt.threads > 0 ? opt.threads : int(tbb::info::default_concurrency());
  const GroupOutputs go{opt,        order,        g.rcache,          g.no_cache_dir,
                        renderer,   group_phases, PhaseClock::now(), threads,
                        memo.get(), memory};
  for (auto& c : cells) results.push_back(write_cell_outputs(*c, sh, go));
  progress.done();
  if (g.stats) {
    g.stats->frames += order.recorded() + order.warmup();
    g.stats->ref_ms += ref_total;
    g.stats->rays += renderer.rays_traced();
    g.stats->passes += 1;
  }
}

// The stages of docs/architecture.md §2: parse_group, output folders, the memory plan, then per
// pass the frame loop over its cells (run_pass) and their outputs; a pass's cells are freed
// before the next pass starts.
std::vector<CellResult> run_cells_impl(const std::vector<CellJob>& jobs, const EngineOptions& opt,
                                       GroupStats* stats) {
  auto g0 = Clock::now();
  PhaseTimes setup_phases;
  PhaseClock gpc = PhaseClock::now();
  std::vector<CellResult> results;
  if (jobs.empty()) return results;
  const std::string key = reference_key(jobs.front().doc);
  for (auto& j : jobs)
    FOVSIM_CHECK(reference_key(j.doc) == key,
                 "cells of one reference group differ in a reference key (" + j.file + ")");

  embree_device_config();  // FOVSIM_EMBREE_ISA / FOVSIM_SIMD: a bad value fails here, not mid-run
  simd_path();
  Shared sh;
  sh.models = opt.models_dir.empty() ? default_models_dir() : opt.models_dir;
  std::vector<std::unique_ptr<Cell>> cells = parse_group(jobs, opt, sh);
  const auto locks = start_output_folders(cells);
  std::string no_cache_dir;  // the cache is on but has no folder (a warning, not an error)
  std::unique_ptr<ReferenceCache> rcache = open_reference_cache(opt, sh, no_cache_dir);
  const double setup_ms = ms_since(g0);
  setup_phases.lap("setup", gpc);

  const bool temporal = any_temporal(cells, sh);
  MemoryEstimator est{sh};
  est.video = sh.stride == 1 &&
              !FrameOrder(sh.count, sh.warmup, !opt.targets.empty(), !temporal, sh.seed).shuffled();
  const MemoryPlan plan = plan_memory(opt, sh, cells, est);
  const GroupRun g{jobs,         opt,      sh,   rcache.get(), no_cache_dir,
                   setup_phases, temporal, plan, est,          stats};
  for (size_t p = 0; p < plan.passes.size(); ++p) {
    std::vector<std::unique_ptr<Cell>> pass;
    for (size_t i : plan.passes[p]) pass.push_back(std::move(cells[i]));
    run_pass(g, pass, p, results);
  }  // the pass's cells (their methods and streams) are freed here
  if (stats) {
    stats->setup_ms += setup_ms;
    stats->wall_ms += ms_since(g0);
    if (rcache) {
      stats->frames_from_cache += int(rcache->manifest()["frames_from_cache"].get<int>());
      stats->cache_dir = rcache->disk().dir();
      stats->cache_cap_gb = rcache->max_gb();
      stats->cache_note_mb = sh.cache.note_mb;
      stats->cache_bytes_written += rcache->disk().stats().bytes_written;
    }
    stats->peak_rss_bytes = peak_rss_bytes();
  }
  return results;
}
}  // namespace

}  // namespace fovsim
