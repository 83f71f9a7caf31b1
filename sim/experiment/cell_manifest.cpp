#include "sim/experiment/cell_manifest.h"

#include <tbb/info.h>
#include <unistd.h>

#include <cmath>
#include <ctime>
#include <thread>

#include "sim/core/version.h"
#include "sim/experiment/jod_fidelity.h"
#include "sim/experiment/table.h"
#include "sim/foveation/simd_kernels.h"
#include "sim/metrics/registry.h"
#include "sim/render/embree_device.h"
#include "sim/trace/stats.h"

namespace fovsim {

std::string iso_now() {
  std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

namespace {

Json machine_info() {
  char host[256] = {0};
  ::gethostname(host, sizeof host - 1);
  // Code paths that ran (results do not depend on them; recorded for bug reports).
  return Json{{"hostname", host},
              {"hardware_threads", int(std::thread::hardware_concurrency())},
              {"embree_isa", embree_active_isa()},
              {"simd_path", simd_path_name(simd_path())}};
}

}  // namespace

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

}  // namespace fovsim
