#include "sim/experiment/cell.h"

#include <chrono>
#include <filesystem>
#include <map>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/lighting.h"

namespace fovsim {

void Cell::parse(Params& root, const std::string& models, bool default_print) {
  RunCellKeys keys;
  keys.name = std::filesystem::path(job->file).stem().string();  // the default
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
    // With TAA the shared pass (or `full` as its foveation-loss reference) reads screen motion.
    channels |= m.impl->required_channels() | (m.impl->taa().enabled ? uint32_t(kMotion) : 0u);
    methods.push_back(std::move(m));
  }
  {
    Params mp = root.child("metrics");
    metric.cfg = MetricsConfig::from_params(mp);
  }
  for (auto& n : GpuProfile::names_from_config(root))
    cost.gpus.push_back(GpuProfile::load(n, models));
  {
    Params bp = root.child("budget");
    cost.fit_level = budget_block_table().read(bp).p_fit;
  }
  // Workload descriptor for what the scene does not say (overdraw, bytes, flops per sample).
  cost.workload = Workload::load(keys.workload, models);

  Params op = root.child("outputs");
  outputs.print_summary = default_print;  // the default
  outputs_block_table().read_into(op, outputs);
  for (double f : outputs.image_frames) images.io.frames.insert(int(f));
  images.io.png = outputs.png;
  images.io.exr = outputs.exr;
  images.io.debug = outputs.debug_images;
  print_table = outputs.print_summary;
  latency.config = LatencyConfig::from_params(root);
}

void Cell::process(const Shared& sh, const Renderer& renderer, const FrameData& fd,
                   const Image& ref_display, int fi, double ref_ms, bool record,
                   CellWorkspaces& pool) {
  auto c0 = std::chrono::steady_clock::now();
  PhaseClock pc = PhaseClock::now();
  const bool want_images = record && images.io.frames.count(fi) > 0;
  const CellWorkspaces::Lease ws = pool.take();
  const FrameIn in{sh,
                   fd,
                   ref_display,
                   *ws,
                   fi,
                   ref_ms,
                   record,
                   want_images,
                   job->out_dir + "/images/frame_" + std::to_string(fi),
                   sh.scene->features()};
  if (want_images)
    write_images(in.img_dir, "reference", ref_display, &fd.reference, images.io, images.jobs);
  pc = phases.lap("images", pc);
  FrameContext ctx =
      fd.context(*sh.scene, renderer, sh.sim_display, want_images && images.io.debug);
  ctx.render_scale = sh.scale;  // methods size their filters and tiles in display pixels
  // The reference side (metric.side->frame: sequence streams, foveation-loss reference, floor)
  // was computed for this frame before the cells ran.
  // Latency what-if and tracking loss: methods see the gaze source's gaze, metrics keep fd's
  // true gaze.
  gaze->begin_frame(fi, methods.size(), ctx);
  for (size_t mi = 0; mi < methods.size(); ++mi) {
    MethodRun& m = methods[mi];
    if (m.memo.replay) {  // memoised: this frame's outputs from the method memo
      replay_method(in, mi, ctx);
      pc = phases.lap("cost_rows", pc);
      continue;
    }
    const Step st = step_method(in, mi, ctx, pc);
    std::vector<std::pair<std::string, Image>> heat;  // sequence metrics' heat maps
    const MetricValues metrics = measure(in, m, heat);
    pc = phases.lap("metrics", pc);
    const size_t queued = images.jobs.jobs.size();
    if (want_images) queue_method_images(in, m, *st.linear, heat);
    if (m.memo.rec) record_frame(in, m, st, metrics, queued);
    pc = phases.lap("images", pc);
    build_rows(in, mi, st, ctx, metrics);
    pc = phases.lap("cost_rows", pc);
  }
  if (!images.jobs.jobs.empty() || !images.memo_files.empty()) {
    images.jobs.write_all();
    memo_images(in);
    pc = phases.lap("images", pc);
  }
  cell_ms += elapsed_ms(c0);
}

Cell::Step Cell::step_method(const FrameIn& in, size_t mi, FrameContext& ctx, PhaseClock& pc) {
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
  const bool render_full = gaze->tracked().render_full && m.method != "full";
  FoveationMethod* impl = &m.tracking.select(*m.impl, m.method, gaze->tracked().render_full);
  st.cost_method = render_full ? "full" : m.method;
  auto m0 = std::chrono::steady_clock::now();
  if (watchdog)
    watchdog->begin(watchdog_slot, "frame " + std::to_string(in.fi) + ", method \"" + m.method +
                                       "\" (label \"" + m.label + "\")");
  render_with_lighting(*impl, ctx, fo);  // the method + its lighting strategy (lighting.h)
  if (watchdog) watchdog->end(watchdog_slot);
  st.impl = impl;
  st.sim_ms = elapsed_ms(m0);
  pc = phases.lap("methods", pc);
  const Image& lin = fo.image_is_reference ? fd.reference : fo.image;
  FOVSIM_CHECK(
      lin.width == sh.sim_display.width && lin.height == sh.sim_display.height && lin.channels == 3,
      "method \"" + m.label + "\" produced an image of the wrong size");
  check_finite_image(lin, "frame " + std::to_string(in.fi) + ": method \"" + m.method +
                              "\" (label \"" + m.label + "\")");
  sh.tonemap.apply(lin, in.ws.out_display);
  st.linear = &lin;
  pc = phases.lap("tonemap", pc);
  return st;
}

std::string side_key(const Cell& c) {
  const Json& res = c.manifest["resolved_config"];
  return res.contains("metrics") ? res["metrics"].dump() : std::string();
}

TaaSettings side_taa(const Cell& c, const MethodRun& m) {
  return c.metric.cfg.foveation_loss ? m.impl->taa() : TaaSettings{};
}

std::string method_side_key(const Cell& c, const MethodRun& m) {
  return side_key(c) + "|" + side_taa(c, m).keys().dump();
}

void MethodStreams::reset() {
  temporal.reset();
  for (auto& t : seq) t->reset();
  for (auto& t : seq_fl) t->reset();
  temporal_fl.reset();
}

void Cell::reset_temporal() {
  for (auto& m : methods) {
    m.impl->restart();
    m.streams.reset();
  }
  gaze->reset();
}

}  // namespace fovsim
