#include "sim/experiment/runner.h"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/hash.h"
#include "sim/core/progress.h"
#include "sim/core/version.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/frame.h"
#include "sim/metrics/metrics.h"
#include "sim/render/renderer.h"
#include "sim/trace/trace.h"

namespace fovsim {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

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
  return Json{{"hostname", host}, {"hardware_threads", int(std::thread::hardware_concurrency())}};
}

struct MethodRun {
  std::string label;
  std::string method;
  std::unique_ptr<FoveationMethod> impl;
  TemporalState temporal;
};

struct ImageOutputs {
  std::set<int> frames;
  bool png = true, exr = false, debug = false;
};

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void write_images(const std::string& dir, const std::string& stem, const Image& display_img,
                  const Image* linear, const ImageOutputs& io) {
  if (io.png) write_image(dir + "/" + stem + ".png", display_img);
  if (io.exr && linear) write_image(dir + "/" + stem + ".exr", *linear);
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

}  // namespace

RunResult run_experiment(const LoadedConfig& cfg, const RunOptions& opt) {
  std::unique_ptr<tbb::global_control> threads;
  if (opt.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                     size_t(opt.threads));
  const std::string models = opt.models_dir.empty() ? default_models_dir() : opt.models_dir;
  Params root(cfg.doc, cfg.file);

  // ---- configuration (every key validated; defaults recorded in the manifest) ----
  root.ignore("comment");
  root.ignore("description");
  std::string name = root.string("name", fs::path(cfg.file).stem().string());
  uint64_t seed = uint64_t(root.integer("seed", 1, Range::closed(0, 2e9)));

  Display display;
  if (root.has("display") && root.json()["display"].is_object()) {
    Params dp = root.child("display");
    display = Display::from_params(dp);
  } else {
    std::string dname = root.string("display", "htc_vive_pro_eye");
    display = Display::load(dname, models);
  }
  Params rp = root.child("render");
  double scale = rp.number("scale", 1.0, Range::above(0, 4));
  RenderSettings rs = RenderSettings::from_params(rp);
  Params tp = rp.child("tonemap");
  Display sim_display = display.scaled(scale);

  Params sp = root.child("scene");
  Scene scene = make_scene(sp, models);
  ToneMap tonemap;
  tonemap.exposure = tp.number("exposure", scene.exposure, Range::above(0, 1e6));
  std::string curve = tp.string("curve", "aces", {"aces", "reinhard", "clamp"});
  tonemap.curve = curve == "aces" ? ToneMap::Curve::Aces
                                  : (curve == "reinhard" ? ToneMap::Curve::Reinhard : ToneMap::Curve::Clamp);

  Params trp = root.child("trace");
  Trace raw_trace = load_trace(trp, display, cfg.base_dir);
  std::string placement = root.string("trace_placement", "scene", {"scene", "absolute"});
  Trace trace = resample(raw_trace, display.refresh_hz);
  if (trace.samples.empty()) throw Error(root.where("trace"), "trace has no samples after resampling");
  if (placement == "scene") {
    // The trace's first head position is placed at the scene's default eye (recordings use
    // their own world origin); orientation is kept as recorded.
    glm::dvec3 p0 = trace.samples.front().head_pos;
    for (auto& s : trace.samples) s.head_pos = glm::dvec3(scene.default_eye) + (s.head_pos - p0);
  }

  Params fp = root.child("frames");
  int start = fp.integer("start", 0, Range::at_least(0));
  int stride = fp.integer("stride", 1, Range::closed(1, 1e6));
  int avail = int(trace.samples.size());
  int count = fp.integer("count", 0, Range::at_least(0));  // 0 = all available
  std::string on_short = fp.string("on_short_trace", "fail", {"fail", "truncate"});
  if (start >= avail)
    fp.fail("start", "frame " + std::to_string(start) + " is past the end of the trace (" +
                         std::to_string(avail) + " frames at " + format_number(display.refresh_hz) + " Hz)");
  int max_count = (avail - start + stride - 1) / stride;
  if (count == 0) count = max_count;
  if (count > max_count) {
    if (on_short == "fail")
      fp.fail("count", "trace is too short: " + std::to_string(count) + " frames requested from frame " +
                           std::to_string(start) + " with stride " + std::to_string(stride) + ", only " +
                           std::to_string(max_count) + " available (set frames.on_short_trace=\"truncate\" to accept)");
    count = max_count;
  }

  std::vector<MethodRun> methods;
  std::set<std::string> labels;
  uint32_t channels = kShadingChannels;
  auto mps = root.children("methods");
  if (mps.empty()) root.fail("methods", "at least one method is required, e.g. [{\"method\": \"full\"}]");
  for (size_t i = 0; i < mps.size(); ++i) {
    Params& mp = mps[i];
    MethodRun m;
    m.method = mp.string("method");
    m.label = mp.string("label", m.method);
    if (!labels.insert(m.label).second)
      mp.fail("label", "duplicate label \"" + m.label + "\" (give each method entry a unique \"label\")");
    m.impl = make_method(m.method, mp);
    channels |= m.impl->required_channels();
    methods.push_back(std::move(m));
  }

  MetricsConfig mcfg;
  {
    Params mp = root.child("metrics");
    mcfg = MetricsConfig::from_params(mp);
  }
  std::vector<GpuProfile> gpus;
  {
    std::vector<std::string> names;
    if (root.has("gpus")) {
      const Json& gj = root.raw("gpus");
      if (!gj.is_array() || gj.empty()) root.fail("gpus", "expected a non-empty array of GPU profile names");
      for (size_t i = 0; i < gj.size(); ++i) {
        if (!gj[i].is_string()) root.fail("gpus[" + std::to_string(i) + "]", "expected a profile name, got " + describe_json(gj[i]));
        names.push_back(gj[i].get<std::string>());
      }
    } else {
      names.push_back("gtx1080");
    }
    for (auto& n : names) gpus.push_back(GpuProfile::load(n, models));
  }

  Params op = root.child("outputs");
  ImageOutputs io;
  for (double f : op.numbers("image_frames", {}, Range::at_least(0))) io.frames.insert(int(f));
  io.png = op.boolean("png", true);
  io.exr = op.boolean("exr", false);
  io.debug = op.boolean("debug_images", false);
  bool print_table = op.boolean("print_summary", opt.print_summary);

  root.finish();  // any key nobody read is a typo: fail before computing anything

  // ---- output directory: a run in progress is marked so it never looks complete ----
  std::string out = opt.out_dir.empty() ? "results/" + name : opt.out_dir;
  make_dirs(out);
  for (const char* f : {"frames.csv", "summary.csv", "summary.json"}) {
    std::error_code ec;
    fs::remove(fs::path(out) / f, ec);
  }
  Json manifest{{"tool", "fovsim"},
                {"version", version_string()},
                {"git_commit", git_commit()},
                {"command_line", opt.command_line},
                {"config_file", cfg.file},
                {"config", cfg.doc},
                {"resolved_config", root.resolved()},
                {"seed", seed},
                {"display", display.to_json()},
                {"simulated_resolution", {sim_display.width, sim_display.height}},
                {"scene", {{"name", scene.name}, {"triangles", scene.triangle_count()}}},
                {"trace", {{"source", trace.source}, {"samples", trace.samples.size()}}},
                {"frames", {{"start", start}, {"count", count}, {"stride", stride}}},
                {"machine", machine_info()},
                {"threads", opt.threads > 0 ? opt.threads : int(tbb::info::default_concurrency())},
                {"start_time", iso_now()},
                {"status", "running"}};
  write_file_atomic(out + "/manifest.json", manifest.dump(2) + "\n");

  // ---- frame loop ----
  Renderer renderer(scene, rs);
  SceneFeatures features = scene.features();
  RunResult result;
  result.out_dir = out;
  FrameData fd;
  Image ref_display, out_display, override_display;
  std::optional<Camera> prev_cam;
  const double pixel_scale = double(display.width) * display.height / (double(sim_display.width) * sim_display.height);
  Progress progress("frames", size_t(count));
  std::set<std::string> flags_seen;

  for (int k = 0; k < count; ++k) {
    int fi = start + k * stride;
    const TraceSample& s = trace.samples[size_t(fi)];
    auto t0 = Clock::now();
    renderer.set_time(s.t);
    prepare_frame(renderer, sim_display, s, fi, channels, prev_cam ? &*prev_cam : nullptr, fd);
    tonemap.apply(fd.reference, ref_display);
    double ref_ms = ms_since(t0);
    bool want_images = io.frames.count(fi) > 0;
    std::string img_dir = out + "/images/frame_" + std::to_string(fi);
    if (want_images) write_images(img_dir, "reference", ref_display, &fd.reference, io);
    FrameContext ctx = fd.context(scene, renderer, sim_display, want_images && io.debug);

    for (size_t mi = 0; mi < methods.size(); ++mi) {
      MethodRun& m = methods[mi];
      FrameOutput fo;
      auto m0 = Clock::now();
      m.impl->render(ctx, fo);
      double sim_ms = ms_since(m0);
      const Image& lin = fo.image_is_reference ? fd.reference : fo.image;
      if (lin.width != sim_display.width || lin.height != sim_display.height || lin.channels != 3)
        throw Error("method " + m.label, "produced an image of the wrong size");
      tonemap.apply(lin, out_display);
      const Image* refd = &ref_display;
      if (fo.reference) {
        tonemap.apply(*fo.reference, override_display);
        refd = &override_display;
      }
      Counters metrics = compute_metrics(mcfg, out_display, *refd, fd.camera, fd.eccentricity, &m.temporal);
      for (auto& f : fo.flags) flags_seen.insert(m.label + ":" + f);

      if (want_images) {
        write_images(img_dir, m.label, out_display, &lin, io);
        write_image(img_dir + "/" + m.label + "_error.png", error_heatmap(out_display, *refd));
        if (fo.reference) write_images(img_dir, m.label + "_reference", override_display, &*fo.reference, io);
        for (auto& [dname, dimg] : fo.debug) write_image(img_dir + "/" + m.label + "_" + dname + ".png", dimg);
      }

      for (auto& gpu : gpus) {
        CostInputs ci;
        ci.method = m.method;
        ci.counters = &fo.counters;
        ci.features = features;
        ci.display = display;
        ci.pixel_scale = pixel_scale;
        FrameCost cost = estimate_frame(gpu, ci);
        ResultRow row;
        row.set_text("config_id", gpus.size() > 1 ? m.label + "@" + gpu.name : m.label);
        row.set_text("method", m.method);
        row.set_text("label", m.label);
        row.set_text("gpu", gpu.name);
        for (auto& [pn, pv] : m.impl->param_columns()) row.set(pn, pv);
        row.set("frame", fi);
        row.set("t", s.t);
        row.set("gaze_x", fd.gaze_px.x / scale);  // pixels of the real display
        row.set("gaze_y", fd.gaze_px.y / scale);
        row.set("gaze_valid", fd.gaze_valid ? 1 : 0);
        double shaded = fo.counters.get("shaded_samples");
        row.set("shaded_samples", shaded * pixel_scale);
        row.set("shaded_fraction", shaded / double(sim_display.width * sim_display.height));
        row.set("prims_submitted", fo.counters.get("prims_submitted", double(features.triangles)));
        row.set("prims_culled", fo.counters.get("prims_culled", 0.0));
        for (auto& [cn, cv] : fo.counters.items())
          if (cn != "shaded_samples" && cn != "prims_submitted" && cn != "prims_culled") row.set(cn, cv);
        row.set("est_ms_total", cost.total_ms);
        for (auto& pc : cost.passes) row.set("est_ms_" + pc.pass, pc.ms);
        for (auto& [mn, mv] : metrics.items()) row.set(mn, mv);
        row.set("ref_ms", ref_ms);
        row.set("sim_ms", sim_ms);
        result.frames.add(std::move(row));
      }
    }
    prev_cam = fd.camera;
    progress.step();
  }
  progress.done();

  // ---- outputs (atomic) ----
  result.summary = summarize(result.frames, display.frame_budget_ms());
  write_file_atomic(out + "/frames.csv", result.frames.to_csv());
  write_file_atomic(out + "/summary.csv", result.summary.to_csv());
  Json sj = Json::array();
  for (auto& r : result.summary.rows()) {
    Json o;
    for (auto& [k, v] : r.text) o[k] = v;
    for (auto& [k, v] : r.num) o[k] = std::isfinite(v) ? Json(v) : Json(format_number(v));
    sj.push_back(o);
  }
  Json summary{{"name", name},
               {"budget_ms", display.frame_budget_ms()},
               {"configs", sj},
               {"flags", std::vector<std::string>(flags_seen.begin(), flags_seen.end())}};
  write_file_atomic(out + "/summary.json", summary.dump(2) + "\n");
  manifest["status"] = "complete";
  manifest["end_time"] = iso_now();
  manifest["rays_traced"] = renderer.rays_traced();
  write_file_atomic(out + "/manifest.json", manifest.dump(2) + "\n");

  if (print_table) {
    std::printf("\n%-16s %-10s %7s %9s %10s %8s %7s %8s\n", "config", "gpu", "frames", "shaded%", "est_ms", "psnr",
                "ssim", "fpsnr");
    for (auto& r : result.summary.rows()) {
      const std::string* id = r.text_of("label");
      const std::string* g = r.text_of("gpu");
      std::printf("%-16s %-10s %7.0f %8.1f%% %10.3f %8.2f %7.4f %8.2f\n", id ? id->c_str() : "?", g ? g->c_str() : "?",
                  r.get("frames", 0), 100.0 * r.get("shaded_fraction", NAN), r.get("est_ms_total", NAN),
                  r.get("psnr", NAN), r.get("ssim", NAN), r.get("fpsnr", NAN));
    }
    std::printf("budget %.2f ms (%.0f Hz); results in %s\n", display.frame_budget_ms(), display.refresh_hz,
                out.c_str());
    for (auto& f : flags_seen) std::printf("flag: %s\n", f.c_str());
  }
  return result;
}

ResultTable summarize(const ResultTable& frames, double budget_ms) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<const ResultRow*>> groups;
  for (auto& r : frames.rows()) {
    const std::string* id = r.text_of("config_id");
    std::string key = id ? *id : "";
    if (!groups.count(key)) order.push_back(key);
    groups[key].push_back(&r);
  }
  auto cols = frames.numeric_columns();
  ResultTable t;
  for (auto& key : order) {
    auto& rows = groups[key];
    ResultRow s;
    for (auto& kv : rows.front()->text) s.set_text(kv.first, kv.second);
    s.set("frames", double(rows.size()));
    for (auto& c : cols) {
      if (c == "frame" || c == "t" || c == "gaze_x" || c == "gaze_y") continue;
      double sum = 0;
      size_t n = 0;
      for (auto* r : rows) {
        double v = r->get(c, NAN);
        if (std::isfinite(v)) {
          sum += v;
          ++n;
        }
      }
      s.set(c, n ? sum / double(n) : NAN);
    }
    std::vector<double> tot;
    for (auto* r : rows) tot.push_back(r->get("est_ms_total", NAN));
    std::sort(tot.begin(), tot.end());
    auto pct = [&](double p) {
      if (tot.empty()) return double(NAN);
      double idx = p * double(tot.size() - 1);
      size_t lo = size_t(std::floor(idx)), hi = size_t(std::ceil(idx));
      return tot[lo] + (tot[hi] - tot[lo]) * (idx - double(lo));
    };
    s.set("est_ms_total_p50", pct(0.5));
    s.set("est_ms_total_p95", pct(0.95));
    s.set("est_ms_total_p99", pct(0.99));
    s.set("budget_ms", budget_ms);
    s.set("fits_budget", pct(0.95) <= budget_ms ? 1 : 0);
    s.set("headroom_ms", budget_ms - pct(0.95));
    t.add(std::move(s));
  }
  return t;
}

}  // namespace fovsim
